"""The bed's static sag on its four mounts: the modal statics of the
floating-frame model against a direct static FE solution of the same plate
on the same springs, with the truncation error falling as modes are added."""

import numpy as np
import pytest
import scipy.sparse as sp
import scipy.sparse.linalg as sla

from flexbed.dynamics.flexible import FlexibleBody
from flexbed.dynamics.laws import LinearLaw
from flexbed.dynamics.scene import Base, Body, Mount, Scene
from flexbed.dynamics.statics import solve_statics
from flexbed.dynamics.system import System
from flexbed.fem.bed import compute_bed_modes
from flexbed.fem.plate import assemble_plate
from flexbed.fem.spec import PlateSpec

K_MOUNT = 5.0e5          # N/m, the reference scene's base-to-bed mounts
G = 9.81
CORNERS = np.array([[sx * 0.4, sy * 2.4, 0.0] for sx in (-1, 1) for sy in (-1, 1)])


def direct_fe_sag():
    """(K + springs) w = weight, on the FE plate itself."""
    spec = PlateSpec()
    model = assemble_plate(spec)
    d = model.node_dofs
    x, y = model.nodes.T
    corner_nodes = [int(np.flatnonzero(np.isclose(x, cx) & np.isclose(y, cy))[0])
                    for cx, cy, _ in CORNERS]
    springs = sp.coo_matrix((np.full(4, K_MOUNT), (d[0, corner_nodes], d[0, corner_nodes])),
                            shape=model.K.shape)
    weight = -G * (model.M_w @ model.rigid_vectors()[:, 0])
    w = sla.spsolve((model.K + springs).tocsc(), weight)
    return model, w[d[0]]


def modal_sag(bed, n, sag=True):
    inv = bed.invariants
    k = slice(0, n)
    node = [int(np.flatnonzero(np.all(np.isclose(bed.nodes, c), axis=1))[0]) for c in CORNERS]
    fb = FlexibleBody(
        mass=inv.mass, first_moment=inv.first_moment, inertia=inv.inertia,
        phi_integral=inv.phi_integral[:, k], u_cross_phi=inv.u_cross_phi[:, k],
        phi_cross_phi=inv.phi_cross_phi[k, :, k], modal_mass=inv.modal_mass[k, k],
        inertia_first_order=inv.inertia_first_order[k],
        inertia_second_order=inv.inertia_second_order[k, k],
        modal_stiffness=inv.modal_stiffness[k, k], modal_damping=np.zeros((n, n)),
        points=CORNERS, point_shapes=np.transpose(bed.translation[:n, node], (1, 2, 0)))
    s = PlateSpec()
    bodies = (Body("base", 1e6, [1e8, 1e8, 1e8], [0, 0, 0]),
              Body("bed", s.mass, s.inertia, [0, 0, 5.1]))
    law = LinearLaw(K_MOUNT)
    mounts = tuple(Mount(f"M{i + 1}", "base", "bed", c + [0, 0, 5.0], c, np.eye(3), (law,) * 3)
                   for i, c in enumerate(CORNERS))
    system = System(Scene(bodies=bodies, base=Base(), mounts=mounts, gravity=[0, 0, -G],
                          flexible=(("bed", fb),)))
    eq = solve_statics(system, tol=1e-10, sag=sag)
    assert eq.success, eq.message
    parts = system.layout.split(eq.y)
    a = eq.y[system.layout.q_modal]
    return parts["r"][0], parts["p"][0], a


@pytest.fixture(scope="module")
def bed():
    return compute_bed_modes(PlateSpec(), n_modes=40)


def test_modal_statics_converge_to_the_direct_fe_sag(bed):
    model, w_direct = direct_fe_sag()
    errors = []
    for n in (1, 4, 8, 20, 40):
        r, p, a = modal_sag(bed, n)
        assert np.allclose(p, [1, 0, 0, 0], atol=1e-12)      # symmetric: stays level
        w_modal = (r[2] - 5.1) + np.einsum("kn,k->n", bed.translation[:n, :, 2], a)
        errors.append(np.abs(w_modal - w_direct).max() / np.abs(w_direct).max())
    errors = np.array(errors)
    # the bed sags as a whole (rigid drop m g / 4k) plus its elastic bending
    drop = PlateSpec().mass * G / (4 * K_MOUNT)
    assert np.abs(w_direct).max() > drop
    assert np.all(np.diff(errors) < 0), errors           # falls as modes are added
    assert errors[0] < 0.01 and errors[-1] < 3e-4, errors


def test_paper_statics_without_sag_give_the_rigid_drop(bed):
    """static_sag off: modal coordinates held at zero, the bed drops as a
    rigid body by m g / 4k."""
    drop = bed.invariants.mass * G / (4 * K_MOUNT)
    r, p, a = modal_sag(bed, 2, sag=False)
    assert np.all(a == 0)
    assert r[2] == pytest.approx(5.1 - drop, abs=1e-12)
    r_sag, _, a_sag = modal_sag(bed, 2, sag=True)
    assert r_sag[2] < r[2] - 1e-4 and abs(a_sag[0]) > 0       # the sag lowers the frame

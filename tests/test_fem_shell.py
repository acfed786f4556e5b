"""The Mindlin flat shell (issue 14): NAFEMS FV12, no shear locking, the
reference bed against a 3D solid, rigid modes, invariants exact for the
consistent mass, and the Kirchhoff default left as it was."""

from __future__ import annotations

import numpy as np
import pytest

from flexbed.fem.bed import compute_bed_modes
from flexbed.fem.invariants import shell_mass_properties
from flexbed.fem.mitc4 import GAUSS, shape
from flexbed.fem.quad_shapes import QuadShapes
from flexbed.fem.grid_shapes import OutsidePlateError
from flexbed.fem.shell import assemble_shell
from flexbed.fem.spec import PlateSpec, PlateSpecError

FV12 = dict(length_x=10.0, length_y=10.0, young=2e11, poisson=0.3, density=8000.0)
# 3D-solid frequencies of the reference bed (issue 14: 171,963-DOF hexahedra)
SOLID = np.array([23.144, 63.807, 80.281, 124.997, 163.317, 169.63, 206.168])


@pytest.mark.slow
def test_nafems_fv12_free_square_plate():
    """NAFEMS FV12 (1.622, 2.360, 2.922 Hz) and Leissa's 4.190, 4.190,
    7.356 Hz, within 0.2 % on 64 x 64 MITC4 elements."""
    bed = compute_bed_modes(PlateSpec(**FV12, thickness=0.05, nx=64, ny=64,
                                      theory="mindlin"), n_modes=6)
    target = np.array([1.622, 2.360, 2.922, 4.190, 4.190, 7.356])
    rel = bed.modes.frequency / target - 1.0
    assert np.all(np.abs(rel) < 2e-3), rel
    assert bed.modes.rigid_omega.shape == (6,)


def test_no_shear_locking_at_t_over_l_1_1000():
    """t/L = 1/1000: against the converged thin-plate (Kirchhoff) values the
    error is the mesh's, falling as h² (a locking element stays far off
    whatever the mesh)."""
    spec = dict(FV12, thickness=0.01)
    thin = compute_bed_modes(PlateSpec(**spec, nx=24, ny=24, rotary_inertia=False),
                             n_modes=6).modes.frequency
    err = [np.abs(compute_bed_modes(PlateSpec(**spec, nx=n, ny=n, theory="mindlin"),
                                    n_modes=6).modes.frequency / thin - 1.0) for n in (8, 16)]
    assert np.all(err[1] < 0.025), err[1]
    assert np.all(err[1] < 0.3 * err[0]), err


@pytest.fixture(scope="module")
def reference_bed():
    return compute_bed_modes(PlateSpec(nx=16, ny=96, theory="mindlin"), n_modes=8)


def test_reference_bed_against_the_3d_solid(reference_bed):
    """First seven elastic modes within 0.5 % of the 3D solid on 16 x 96
    elements, the in-plane bending mode (6th) included."""
    f = reference_bed.modes.frequency[:7]
    rel = f / SOLID - 1.0
    assert np.all(np.abs(rel) < 5e-3), rel
    assert reference_bed.modes.labels[5] == "in-plane"
    assert reference_bed.modes.labels[:3] == ("bending about x", "bending about x", "torsion")
    assert reference_bed.modes.symmetry[:3] == ("SS", "SA", "AA")


def test_in_plane_mode_moves_in_plane(reference_bed):
    t = reference_bed.translation[5]
    assert np.abs(t[:, 2]).max() < 1e-6 * np.abs(t[:, :2]).max()
    assert np.abs(reference_bed.rotation[5][:, 2]).max() > 0      # in-plane rotation


def test_mass_properties_are_the_solid_plates():
    spec = PlateSpec(nx=3, ny=5, theory="mindlin")
    m, first, J = shell_mass_properties(assemble_shell(spec))
    assert m == pytest.approx(spec.mass, rel=1e-14)
    assert np.abs(first).max() < 1e-12 * m
    assert np.allclose(J, np.diag(spec.inertia), rtol=1e-13, atol=1e-9)


def test_invariants_rigid_free_and_mass_normalised(reference_bed):
    inv = reference_bed.invariants
    assert np.abs(inv.phi_integral).max() < 1e-10
    assert np.abs(inv.u_cross_phi).max() < 1e-10
    assert np.allclose(inv.modal_mass, np.eye(8), atol=1e-12)
    omega = 2 * np.pi * reference_bed.modes.frequency
    assert np.allclose(np.diag(inv.modal_stiffness), omega ** 2, rtol=1e-10)


def test_invariants_equal_the_integrals_of_the_field():
    """I3, I4, I5, I8 and I9 against Gauss quadrature of the displacement
    field Φ(x, y, z) = (u + z θy, v − z θx, w) over the solid (2 × 2 in the
    plane, 2 points through the thickness: exact for these polynomials)."""
    spec = PlateSpec(length_x=0.8, length_y=1.2, thickness=0.15, nx=3, ny=4, theory="mindlin")
    bed = compute_bed_modes(spec, n_modes=5)
    model = assemble_shell(spec)
    shapes = QuadShapes(model.nodes, model.cells, bed.translation, bed.rotation)
    n = 5
    S = np.zeros((3, n))
    Q = np.zeros((n, 3, 3))
    P = np.zeros((n, n, 3, 3))
    h = spec.thickness
    for cell in model.cells:
        xy = model.nodes[cell]
        for xi, eta in GAUSS:
            N, dN = shape(xi, eta)
            det = np.linalg.det(dN.T @ xy)
            x, y = N @ xy
            for zeta in (-1 / np.sqrt(3), 1 / np.sqrt(3)):
                z = 0.5 * h * zeta
                phi, _ = shapes.at(np.array([[x, y, z]]))        # (n, 1, 3)
                phi = phi[:, 0]
                wgt = spec.density * det * 0.5 * h
                u0 = np.array([x, y, z])
                S += wgt * phi.T
                Q += wgt * u0[None, :, None] * phi[:, None, :]
                P += wgt * phi[:, None, :, None] * phi[None, :, None, :]
    inv = bed.invariants
    eye = np.eye(3)
    assert np.allclose(inv.phi_integral, S, atol=1e-12)
    I8 = np.trace(Q, axis1=1, axis2=2)[:, None, None] * eye - np.transpose(Q, (0, 2, 1))
    I9 = np.trace(P, axis1=2, axis2=3)[:, :, None, None] * eye - np.transpose(P, (1, 0, 2, 3))
    assert np.allclose(inv.inertia_first_order, I8, atol=1e-12)
    assert np.allclose(inv.inertia_second_order, I9, atol=1e-12)
    assert np.allclose(inv.modal_mass, np.trace(P, axis1=2, axis2=3), atol=1e-12)


def test_point_shapes_reproduce_the_nodes_and_refuse_points_off_the_bed(reference_bed):
    nodes = reference_bed.nodes
    shapes = QuadShapes(nodes[:, :2], reference_bed.cells, reference_bed.translation,
                        reference_bed.rotation)
    trans, rot = shapes.at(nodes[[0, 17, 300]])
    assert np.allclose(trans, reference_bed.translation[:, [0, 17, 300]], atol=1e-14)
    # off the mid-surface: U = (u + z θy, v − z θx, w)
    up, _ = shapes.at(nodes[[17]] + [0.0, 0.0, 0.05])
    t, r = reference_bed.translation[:, 17], reference_bed.rotation[:, 17]
    assert np.allclose(up[:, 0], t + 0.05 * np.column_stack([r[:, 1], -r[:, 0], 0 * r[:, 0]]))
    with pytest.raises(OutsidePlateError, match=r"\(0.5, 0, 0\) m lies off the bed"):
        shapes.at([[0.5, 0.0, 0.0]])


def test_kirchhoff_spec_keeps_its_digest():
    """The default bed's hash is the one it had before ``theory`` existed,
    so Kirchhoff modes files made before stay valid."""
    assert PlateSpec().digest() == \
        "05f9b4ae50267b8403444e27cef358c8b267ec37facdae1713a58264564f3040"
    assert PlateSpec(theory="mindlin").digest() != PlateSpec().digest()
    with pytest.raises(PlateSpecError, match="theory = 'reissner'"):
        PlateSpec(theory="reissner")

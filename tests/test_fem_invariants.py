"""Modal invariants: exact solid values, free-free orthogonality, and the
configuration-dependent terms against brute-force integration over the
deformed solid."""

import numpy as np
import pytest

from flexbed.fem.bed import compute_bed_modes
from flexbed.fem.invariants import second_moments
from flexbed.fem.plate import assemble_plate
from flexbed.fem.grid_shapes import GridShapes
from flexbed.fem.spec import PlateSpec

N_MODES = 5


@pytest.fixture(scope="module")
def bed():
    return compute_bed_modes(PlateSpec(), n_modes=N_MODES)


def test_mass_and_inertia_are_table_1(bed):
    inv = bed.invariants
    assert inv.mass == pytest.approx(2995.2, rel=1e-14)
    J = inv.inertia
    assert J[0, 0] == pytest.approx(5753.28, rel=1e-14)
    assert J[1, 1] == pytest.approx(162.24, rel=1e-14)
    assert J[2, 2] == pytest.approx(5910.53, abs=0.005)     # Table 1 rounds 5910.528
    assert np.all(J == np.diag(np.diag(J)))
    assert np.all(inv.first_moment == 0)


def test_fe_rigid_rotations_carry_the_solid_inertia():
    """With the rotary inertia in the mass, the FE tilts about x and y have
    exactly the solid plate's Jxx and Jyy, and the FE translation its mass."""
    model = assemble_plate(PlateSpec())
    R = model.rigid_vectors()
    G = R.T @ model.M @ R
    s = PlateSpec()
    assert np.allclose(np.diag(G), [s.mass, s.inertia[0], s.inertia[1]], rtol=1e-13)
    assert np.abs(G - np.diag(np.diag(G))).max() < 1e-10 * s.mass


def test_free_free_modes_make_i3_and_i4_vanish(bed):
    scale = np.sqrt(bed.invariants.mass)          # |∫ρΦ| ≤ sqrt(m) for unit modal mass
    assert np.abs(bed.invariants.phi_integral).max() < 1e-13 * scale
    assert np.abs(bed.invariants.u_cross_phi).max() < 1e-13 * scale * 2.4


def test_generalized_mass_and_stiffness(bed):
    inv = bed.invariants
    assert np.abs(inv.modal_mass - np.eye(N_MODES)).max() < 1e-13
    w2 = bed.modes.omega ** 2
    assert np.abs(inv.modal_stiffness - np.diag(w2)).max() < 1e-11 * w2.max()


def deformed_solid_integrals(model, phi, a):
    """Brute force: J(a) = ∫ρ ũᵀũ dV and C(a) = ∫ρ ũ Φ dV over the solid
    plate with every point moved by Φ a, by quadrature: the element's 4 x 4
    Gauss points in the plane, 2 Gauss points through the thickness (the
    integrands are quadratic in z)."""
    spec = model.spec
    basis = model.basis
    w = basis.interpolate(phi @ a)
    fields = [basis.interpolate(phi[:, k]) for k in range(phi.shape[1])]
    x, y = np.asarray(basis.global_coordinates())
    dA = basis.dx
    J = np.zeros((3, 3))
    C = np.zeros((3, phi.shape[1]))
    for z in (-0.5 / np.sqrt(3) * spec.thickness, 0.5 / np.sqrt(3) * spec.thickness):
        weight = spec.density * 0.5 * spec.thickness * dA
        u = np.stack([x - z * w.grad[0], y - z * w.grad[1], z + np.asarray(w)])
        uu = np.einsum("iep,jep->ijep", u, u)
        J += np.einsum("ijep,ep->ij", np.eye(3)[:, :, None, None] * np.einsum("iiep->ep", uu)
                       - uu, weight)
        for k, f in enumerate(fields):
            Phi = np.stack([-z * f.grad[0], -z * f.grad[1], np.asarray(f)])
            C[:, k] += np.einsum("iep,ep->i", np.cross(u, Phi, axis=0), weight)
    return J, C


def test_configuration_dependent_inertia_against_brute_force(bed):
    """J(a) = I7 + Σ a_k (I8_k + I8_kᵀ) + Σ a_k a_l I9_kl and
    ∫ρ ũΦ = I4 + Σ a_k I5_k, at a large deformation (so the second-order
    terms matter), against direct quadrature of the deformed solid. The
    in-plane inertia the bending model lacks (the solid's x, y extent) is in
    I7 exactly, so the comparison is to round-off."""
    model = assemble_plate(PlateSpec())
    from flexbed.fem.modes import free_free_modes
    modes = free_free_modes(model, n_modes=N_MODES)
    inv = compute_bed_modes(PlateSpec(), n_modes=N_MODES).invariants
    a = np.array([3.0, -2.0, 1.5, 0.7, -1.1])        # sqrt(kg) m: deflections of ~0.1 m
    J_brute, C_brute = deformed_solid_integrals(model, modes.vectors, a)
    J = (inv.inertia + np.einsum("k,kij->ij", a, inv.inertia_first_order
                                 + np.transpose(inv.inertia_first_order, (0, 2, 1)))
         + np.einsum("k,l,klij->ij", a, a, inv.inertia_second_order))
    assert np.abs(J - J_brute).max() < 1e-10 * np.abs(J).max()
    C = inv.u_cross_phi + np.einsum("k,kil->il", a, inv.phi_cross_phi)
    assert np.abs(C - C_brute).max() < 1e-10 * np.abs(C).max()
    # and the deformation did change the inertia beyond round-off
    assert np.abs(J - inv.inertia).max() > 1e-4 * np.abs(J).max()


def test_second_moments_match_the_mass_matrix(bed):
    model = assemble_plate(PlateSpec())
    from flexbed.fem.modes import free_free_modes
    phi = free_free_modes(model, n_modes=N_MODES).vectors
    S, Q, P = second_moments(model, phi)
    trace = np.trace(P, axis1=2, axis2=3)
    assert np.allclose(trace, phi.T @ model.M @ phi, rtol=0, atol=1e-14)


@pytest.mark.slow
def test_grid_shapes_reproduce_the_fe_field(bed):
    """Mode shapes from the modes-file data (nodal translation, rotation,
    twist) evaluated between nodes equal the FE field there."""
    model = assemble_plate(PlateSpec())
    from flexbed.fem.modes import free_free_modes
    phi = free_free_modes(model, n_modes=N_MODES).vectors
    shapes = GridShapes.from_nodes(bed.nodes, bed.translation, bed.rotation, bed.twist)
    rng = np.random.default_rng(1)
    pts = np.column_stack([rng.uniform(-0.4, 0.4, 40), rng.uniform(-2.4, 2.4, 40),
                           rng.uniform(-0.05, 0.05, 40)])
    trans, rot = shapes.at(pts)
    probes = model.basis.probes(pts[:, :2].T)
    h = 1e-6
    px = model.basis.probes((pts[:, :2] + [h, 0]).T) - model.basis.probes((pts[:, :2] - [h, 0]).T)
    py = model.basis.probes((pts[:, :2] + [0, h]).T) - model.basis.probes((pts[:, :2] - [0, h]).T)
    for k in range(N_MODES):
        w = probes @ phi[:, k]
        wx = px @ phi[:, k] / (2 * h)
        wy = py @ phi[:, k] / (2 * h)
        scale = np.abs(w).max()
        assert np.abs(trans[k, :, 2] - w).max() < 1e-12 * scale
        assert np.abs(rot[k, :, 0] - wy).max() < 1e-7 * np.abs(wy).max()
        assert np.abs(rot[k, :, 1] + wx).max() < 1e-7 * np.abs(wx).max()
        assert np.allclose(trans[k, :, 0], -pts[:, 2] * wx, rtol=1e-6, atol=1e-9 * scale)
    # at the nodes: the stored data itself
    t_nodes, r_nodes = shapes.at(bed.nodes)
    assert np.allclose(t_nodes, bed.translation, rtol=0,
                       atol=1e-13 * np.abs(bed.translation).max())
    assert np.allclose(r_nodes, bed.rotation, rtol=0, atol=1e-13 * np.abs(bed.rotation).max())


def test_points_off_the_plate_are_refused(bed):
    shapes = GridShapes.from_nodes(bed.nodes, bed.translation, bed.rotation, bed.twist)
    with pytest.raises(ValueError, match="outside the plate"):
        shapes.at(np.array([[0.5, 0.0, 0.0]]))

"""Masses fixed to the bed (issue 14): point masses and rigid equipment
change the bed's mass, centre of mass and inertia exactly, its rigid-body
mass matrix is the composite's, and the invariants stay exact."""

from __future__ import annotations

import numpy as np
import pytest

import flexbed
from flexbed.errors import InputError
from flexbed.fem.bed import compute_bed_modes
from flexbed.fem.fixed_masses import FixedMass
from flexbed.fem.invariants import shell_mass_properties
from flexbed.fem.layout import bed_mass_properties
from flexbed.fem.shell import assemble_shell
from flexbed.fem.spec import PlateSpec, PlateSpecError
from flexbed.files.builtin import builtin_scene_path

ITEMS = (FixedMass("pump", (0.2, 1.0, 0.3), 200.0),
         FixedMass("motor", (-0.1, -1.2, 0.25), 500.0, ((20.0, 1.0, 0.0), (1.0, 30.0, 2.0),
                                                         (0.0, 2.0, 40.0))))
SPEC = PlateSpec(theory="mindlin", nx=4, ny=24, masses=ITEMS)


def _tilde(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def _composite():
    """Mass, centre and inertia about the centre: plate block + items."""
    mp = PlateSpec().mass
    parts = [(mp, np.zeros(3), np.diag(PlateSpec().inertia))]
    parts += [(it.mass, np.array(it.position), np.array(it.inertia)) for it in ITEMS]
    m = sum(p[0] for p in parts)
    c = sum(p[0] * p[1] for p in parts) / m
    J = sum(Ji + mi * ((pi - c) @ (pi - c) * np.eye(3) - np.outer(pi - c, pi - c))
            for mi, pi, Ji in parts)
    return m, c, J


def test_composite_mass_properties_are_exact():
    m, c, J = _composite()
    mp = bed_mass_properties(SPEC)
    assert mp.mass == pytest.approx(m, rel=1e-14)
    assert np.allclose(mp.centre, c, rtol=0, atol=1e-14)
    assert np.allclose(mp.inertia, J, rtol=1e-13, atol=1e-10)
    model = assemble_shell(SPEC)                     # origin at the composite centre
    assert model.mid_z == pytest.approx(-c[2], rel=1e-14)
    mm, first, Jm = shell_mass_properties(model)
    assert mm == pytest.approx(m, rel=1e-14)
    assert np.abs(first).max() < 1e-11 * m
    assert np.allclose(Jm, J, rtol=1e-13, atol=1e-10)


def test_rigid_body_mass_matrix_is_the_composites():
    """Rᵀ M R over the six rigid motions (about the mid-surface point under
    the centre of mass) equals the rigid composite's [[m I, -m d~], [m d~, J_o]]:
    the items' translation and rotation operators and their heights are right."""
    m, c, J = _composite()
    model = assemble_shell(SPEC)
    R = model.rigid_vectors()
    MR = R.T @ (model.M @ R)
    d = np.array([0.0, 0.0, -model.mid_z])          # centre of mass seen from the axes' point
    Jo = J + m * (d @ d * np.eye(3) - np.outer(d, d))
    expect = np.block([[m * np.eye(3), -m * _tilde(d)], [m * _tilde(d), Jo]])
    assert np.allclose(MR, expect, rtol=1e-12, atol=1e-9 * m)


def test_invariants_with_fixed_masses():
    bed = compute_bed_modes(SPEC, n_modes=6)
    inv = bed.invariants
    _, _, J = _composite()
    assert np.abs(inv.first_moment).max() < 1e-10
    assert np.allclose(inv.inertia, J, rtol=1e-13, atol=1e-10)
    assert np.abs(inv.phi_integral).max() < 1e-10          # rigid-free modes
    assert np.abs(inv.u_cross_phi).max() < 1e-10
    assert np.allclose(inv.modal_mass, np.eye(6), atol=1e-12)
    assert np.allclose(bed.nodes[:, 2], -_composite()[1][2])
    plain = compute_bed_modes(PlateSpec(theory="mindlin", nx=4, ny=24), n_modes=6)
    assert np.all(bed.modes.frequency < plain.modes.frequency)


def test_fixed_mass_inputs(tmp_path):
    with pytest.raises(PlateSpecError, match="fixed_mass needs theory"):
        PlateSpec(masses=ITEMS)
    text = builtin_scene_path().read_text().replace(
        'model = "rigid"', 'model = "flexible"\ntheory = "mindlin"', 1)
    text = text.replace("nx = 10\nny = 10\n", "nx = 4\nny = 24\n")
    good = text.replace("rayleigh = [0.0, 0.01]\n", "rayleigh = [0.0, 0.01]\n[[bed.fixed_mass]]\n"
                        "name = \"pump\"\nposition = [0.2, 1.0, 0.3]\nmass = 200.0\n", 1)
    bad = good.replace("mass = 200.0", "mass = -2.0")
    folder = tmp_path
    (folder / "good.toml").write_text(good)
    (folder / "bad.toml").write_text(bad)
    sf = flexbed.load_scene(folder / "good.toml")
    body = sf.scene.bodies[1]
    m = PlateSpec().mass + 200.0
    c = 200.0 * np.array([0.2, 1.0, 0.3]) / m
    assert body.mass == pytest.approx(m, rel=1e-14)
    assert np.allclose(body.position, np.array([0.0, 0.0, 5.1]) + c, atol=1e-14)
    with pytest.raises(InputError, match=r"bad.toml: bed: fixed_mass 'pump': mass = -2.0 must be"):
        flexbed.load_scene(folder / "bad.toml")

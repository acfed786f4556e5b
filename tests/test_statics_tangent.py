"""Newton-Raphson's Jacobian in the statics (issue 30, part 5): the exact
tangent stiffness at rest (:mod:`flexbed.dynamics.tangent`, one right-hand
side) where it covers the scene, central differences by colour classes
where it does not. The equilibrium is the one the differences give, to
round-off (1e-12 m and rad, the issue's tolerance), the steps converge
quadratically (the rigid scene's tangent is the residual's exact
derivative), and the right-hand sides fall from ~50 to ~10."""

from __future__ import annotations

import numpy as np
import pytest

import flexbed
from flexbed.dynamics import statics as statics_module
from flexbed.dynamics.statics import solve_statics


def _no_tangent(mp):
    """Take the tangent away (its NumPy form and the compiled one of rigid
    scenes, :mod:`flexbed.dynamics.rigid_statics`): differences answer."""
    mp.setattr(statics_module, "tangent", lambda *a, **k: None)
    mp.setattr(statics_module, "_rigid_jacobian", lambda *a, **k: None)


def _pair(system, monkeypatch):
    """The equilibrium with the tangent, and with central differences alone."""
    exact = solve_statics(system)
    with monkeypatch.context() as m:
        _no_tangent(m)
        differences = solve_statics(system)
    return exact, differences


def _close(system, a, b):
    pa, qa = system.poses(a.y)
    pb, qb = system.poses(b.y)
    assert np.max(np.abs(pa - pb)) < 1e-12            # m
    assert np.max(np.abs(qa - qb)) < 1e-12            # Euler parameters (rad / 2)


def test_the_rigid_equilibrium_is_the_differences_one_with_a_tenth_of_the_rhs(monkeypatch):
    system = flexbed.statics(flexbed.load_scene()).system
    exact, differences = _pair(system, monkeypatch)
    assert exact.success and differences.success
    _close(system, exact, differences)
    assert exact.residual < 1e-12 and differences.residual < 1e-12
    # one right-hand side a Jacobian against 24 (2 colour classes x 6 coordinates x 2)
    assert exact.rhs_evaluations <= 12 and differences.rhs_evaluations >= 48
    # quadratic convergence while the steps are above round-off
    steps = [s for s, _ in exact.history]
    for s0, s1 in zip(steps, steps[1:]):
        if s1 > 1e-13:
            assert s1 <= s0 ** 2, steps


def test_where_the_tangent_does_not_apply_differences_answer():
    """:func:`flexbed.dynamics.tangent.tangent` gives None where it does not
    cover the scene (a law of another kind, a flexible body's frame without
    its modal coordinates): each Jacobian is then central differences."""
    from flexbed.dynamics.tangent import uncovered
    scene = flexbed.load_scene()
    st = flexbed.statics(scene)
    system = st.system
    assert uncovered(system, st.equilibrium.y) == ""
    calls = []
    real = statics_module.force_jacobian

    def spy(*a, **k):
        calls.append(1)
        return real(*a, **k)
    mp = pytest.MonkeyPatch()
    mp.setattr(statics_module, "force_jacobian", spy)
    _no_tangent(mp)
    try:
        eq = solve_statics(system)
    finally:
        mp.undo()
    assert eq.success and calls and eq.jacobian_evaluations == len(calls)


@pytest.mark.slow
def test_the_flexible_bed_s_sag_is_the_differences_one(monkeypatch):
    """The flexible bed (modal unknowns, sag on): the tangent leaves out
    ∂M(q)/∂q v̇ (nil at the equilibrium), Newton still lands on the
    differences' equilibrium to round-off."""
    scene = flexbed.vary(flexbed.load_scene(), {"bed.model": "flexible"})
    system = flexbed.statics(scene, modes=flexbed.modes(scene)).system
    exact, differences = _pair(system, monkeypatch)
    assert exact.success and differences.success
    _close(system, exact, differences)
    a = exact.y[system.layout.q_modal]
    assert np.max(np.abs(a - differences.y[system.layout.q_modal])) < 1e-12 * max(
        1.0, float(np.max(np.abs(a))))


def _unstable_scene(tmp_path, k_z: float):
    """10 kg without gravity on four mounts of vertical stiffness k_z (a
    polynomial law, so the tangent covers it), stiff sideways: at zero
    deflection M⁻¹K has the eigenvalue 4 k_z / m in z, exactly."""
    from scene_text import base_and_body, four_mounts
    path = tmp_path / "unstable.toml"
    path.write_text(base_and_body("held", gravity=0.0, mass=10.0, inertia="[1.0, 1.0, 1.0]")
                    + four_mounts(f"""
law = "polynomial"
stiffness = [[0.0, 1.0e4], [0.0, 1.0e4], [0.0, {k_z}, 0.0, 1.0e8]]
"""))
    return flexbed.load_scene(path)


def test_the_stability_check_takes_the_statics_tangent(tmp_path):
    """The stability check of a rigid scene's equilibrium reuses the last
    Newton Jacobian (the exact tangent stiffness) rather than linearising
    again: the same M⁻¹K as the linearisation's to its central differences'
    accuracy (1e-8 relative on the reference scene), the same verdict; on a
    mount of negative stiffness the exact eigenvalue 4 k_z / m = −4000 1/s²
    (to 1e-9; the linearisation's within 1e-6), the same body and
    direction."""
    import flexbed.dynamics.stability as stability_module
    from flexbed.api.bed_modes import compiled
    from flexbed.dynamics.linear.model import linearise
    from flexbed.dynamics.stability import _from_tangent, instability
    st = flexbed.statics(flexbed.load_scene())
    system, eq = st.system, st.equilibrium
    assert eq.jacobian is not None and eq.stability == "stable"
    assert instability(system, eq.y, jacobian=eq.jacobian) is None
    assert instability(system, eq.y) is None
    lin = linearise(system, eq.y)
    c = lin.coords
    free = np.setdiff1d(np.arange(c.n_pos), c.base_index)
    want = -lin.A[c.n_pos:, :c.n_pos][np.ix_(free, free)]
    seen = {}
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(stability_module, "_decide", lambda s, K: seen.setdefault("K", K))
        _from_tangent(system, eq.jacobian)
    assert np.max(np.abs(seen["K"] - want)) < 1e-8 * np.max(np.abs(want))

    sf = _unstable_scene(tmp_path, -1.0e4)
    system = compiled(sf, None)
    eq = solve_statics(system)
    assert eq.success and eq.jacobian is not None
    exact = instability(system, eq.y, jacobian=eq.jacobian)
    lin = instability(system, eq.y)
    assert (exact.body, exact.direction) == (lin.body, lin.direction) == ("mass", "z")
    assert exact.eigenvalue == pytest.approx(-4000.0, rel=1e-9)
    assert lin.eigenvalue == pytest.approx(exact.eigenvalue, rel=1e-6)


def test_differences_hand_the_stability_check_no_jacobian(monkeypatch):
    """A Jacobian by differences is not handed on (the check linearises)."""
    system = flexbed.statics(flexbed.load_scene()).system
    _no_tangent(monkeypatch)
    assert solve_statics(system).jacobian is None

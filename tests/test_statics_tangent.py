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


def _pair(system, monkeypatch):
    """The equilibrium with the tangent, and with central differences alone."""
    exact = solve_statics(system)
    with monkeypatch.context() as m:
        m.setattr(statics_module, "tangent", lambda *a, **k: None)
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
    mp.setattr(statics_module, "tangent", lambda *a, **k: None)
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

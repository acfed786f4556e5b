"""The compiled steppers (dynamics/steppers/) against closed forms and
against SciPy's own DOP853 and Radau on the same right-hand side: the same
step control must take the same steps, and pausing a run in chunks must not
change it."""

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from flexbed.dynamics import integrate as integrate_module
from flexbed.dynamics.integrate import Settings, integrate
from flexbed.dynamics.statics import solve_statics
from flexbed.dynamics.system import System
from built_scenes import K, M_BODY, Z0, free_vibration, one_mount

AMP = 0.01


def _displaced(zeta):
    s = System(one_mount(2 * zeta * math.sqrt(K * M_BODY)))
    y0 = s.initial_state()
    y0[s.layout.q_rigid.start + 2] += AMP
    return s, y0


def _scipy(system, y0, method, rtol, atol, t_end, t_eval):
    """SciPy's stepper on the same shifted problem as integrate() builds."""
    lay = system.layout
    shift = np.zeros(y0.size)
    shift[lay.q_rigid] = y0[lay.q_rigid]
    atol_v = np.full(y0.size, atol)
    atol_v[lay.work] = 1e30
    return solve_ivp(lambda t, z: system.rhs(t, z + shift), (0.0, t_end), y0 - shift,
                     method=method, rtol=rtol, atol=atol_v, t_eval=t_eval), shift


@pytest.mark.parametrize("rtol", [1e-6, 1e-10])
def test_dop853_takes_scipys_steps(rtol, monkeypatch):
    monkeypatch.setattr(integrate_module, "CHUNK_STEPS", 10**6)    # a resume costs one f
    s, y0 = _displaced(0.05)
    # output at the end only: no dense output, whose 3 extra stages SciPy would not spend
    run = integrate(s, y0, Settings("dop853", t_end=1.0, rtol=rtol, atol=1e-3 * rtol,
                                    output_dt=1.0))
    sol, shift = _scipy(s, y0, "DOP853", rtol, 1e-3 * rtol, 1.0, None)
    assert run.complete and sol.success
    assert run.stats.steps == sol.t.size - 1
    # the stiffness check's differences (nq + nv + 1 evaluations) come on top
    lay = s.layout
    assert run.stats.rhs_evaluations == sol.nfev + lay.nq + lay.nv + 1
    assert np.max(np.abs(run.y[-1] - (sol.y[:, -1] + shift))) < 1e-12     # [m, m/s, J]


@pytest.mark.parametrize("zeta", [0.0, 0.05])
def test_radau_against_the_closed_form(zeta):
    s, y0 = _displaced(zeta)
    run = integrate(s, y0, Settings("radau", t_end=2.0, rtol=1e-10, atol=1e-13,
                                    output_dt=0.01))
    assert run.complete
    z = s.layout.split(run.y)["r"][:, 0, 2] - Z0
    assert np.max(np.abs(z - free_vibration(s, AMP, zeta, run.t))) < 1e-8 * AMP
    assert run.stats.jacobian_evaluations >= 1 and run.stats.lu_decompositions >= 1


def test_radau_follows_scipys_radau_on_the_reference_scene(reference_system):
    system = reference_system
    y0 = solve_statics(system).y
    rtol = 1e-7
    run = integrate(system, y0, Settings("radau", t_end=0.5, rtol=rtol, atol=1e-3 * rtol,
                                         output_dt=0.01))
    # SciPy's Radau on the same segments (the load's curve ends at 1 s: one segment)
    sol, shift = _scipy(system, y0, "Radau", rtol, 1e-3 * rtol, 0.5, run.t)
    assert run.complete and sol.success
    n = system.layout.nq + system.layout.nv          # the motion, not the quadratures
    diff = np.max(np.abs(run.y[:, :n] - (sol.y.T + shift)[:, :n]))
    motion = np.max(np.abs(run.y[:, :n] - y0[:n]))
    assert diff < 1e-5 * motion, (diff, motion)


@pytest.mark.parametrize("method,setting", [("rk4", {"dt": 1e-3}),
                                            ("dop853", {"rtol": 1e-8, "atol": 1e-11}),
                                            ("radau", {"rtol": 1e-7, "atol": 1e-10})])
def test_pausing_in_chunks_changes_nothing(method, setting, monkeypatch, reference_system):
    system = reference_system
    y0 = system.initial_state()
    st = Settings(method, t_end=1.2, output_dt=0.01, **setting)
    whole = integrate(system, y0, st)
    monkeypatch.setattr(integrate_module, "CHUNK_STEPS", 3)
    seen = []
    chunked = integrate(system, y0, st, progress=seen.append)
    assert whole.complete and chunked.complete
    assert chunked.stats.steps == whole.stats.steps
    assert len(seen) >= whole.stats.steps // 3
    lay = system.layout
    motion = slice(0, lay.nq + lay.nv)
    # a resumed dop853 evaluates f afresh where a whole run rescales the projected one:
    # step sizes then differ in the last bits; far below the runs' own errors (~1e-9)
    assert np.max(np.abs(chunked.y[:, motion] - whole.y[:, motion])) < 1e-10   # [m, m/s]
    # the energy quadratures: out of the error control, sums of large powers
    work = whole.y[:, lay.work]
    assert np.max(np.abs(chunked.y[:, lay.work] - work)) < 1e-9 * np.max(np.abs(work))

"""Hard cases (issue 6), one scene file each under tests/scenes/, each
checked against an exact solution, a conservation law or a converged
reference:

1. ``hard_beta20.toml``: a flexible bed with 20 modes and Rayleigh β = 0.01
   (fastest eigenvalue near −βω₂₀²): radau and bdf step far above the
   fastest time scale and converge; rk4 and dop853 refuse to start, with
   one line saying why and what to use.
2. ``hard_stiff_soft.toml``: 1e9 N/m mounts under 10 kg carrying 10 kg on
   1e3 N/m: statics, eigenvalues and motion against the exact two-mass
   chain; the rk4 stability bound is sharp.
3. ``hard_hardening_pulse.toml``: degree-8 hardening mounts under a 20 g,
   6 ms triangular base pulse: methods and tolerances agree with a
   converged reference, and the energy balance closes.
4. ``hard_long_free.toml``: 1000 s of undamped free vibration: |p| − 1 and
   the energy drift.
5. ``hard_free_spin.toml``: a free body spinning about each principal axis:
   energy and angular momentum conserved, the intermediate axis flips at
   the times of the exact (Jacobi elliptic) solution.
6. ``hard_heavy_base.toml``: a free base 1e6 times heavier than the
   equipment: the exact two-body oscillation and momentum.

Tolerances are about ten times what was measured (figures in each
docstring); the measured figures are printed (``pytest -s``).
"""

import math
import re
from pathlib import Path

import numpy as np
import pytest
from scipy.special import ellipj, ellipk

from flexbed.dynamics.history import history
from flexbed.dynamics.integrate import (Settings, integrate, motion_eigenvalues, stable_step,
                                        stiff_message)
from flexbed.dynamics.rotation import A as rotation_matrix
from flexbed.dynamics.statics import solve_statics
from flexbed.cli import main as flexbed
from flexbed.stages.system import compile_scene
from flexbed.files.results import read_results
from flexbed.files.scene import load_scene

SCENES = Path(__file__).parent / "scenes"
G = 9.81


def scene(name):
    return load_scene(SCENES / name)


def settings(sf, **overrides):
    """The scene's solver settings with some replaced."""
    return sf.solver.settings(**overrides)


# ---------------------------------------------------------------- 1. β = 0.01, 20 modes

# the scene, its modes, system and equilibrium: the session fixture beta20 (conftest.py)

def test_rk4_stability_bounds_are_the_known_ones():
    """RK4 is stable up to |hλ| = 2.7852935634 on the negative real axis
    and 2√2 on the imaginary axis; DOP853's region is larger."""
    h, rate = stable_step("rk4", np.array([-1.0, -1e-3]))
    assert rate == 1.0 and h == pytest.approx(2.7852935634, rel=1e-9)
    h, _ = stable_step("rk4", np.array([3j, -3j]))
    assert 3 * h == pytest.approx(2 * math.sqrt(2), rel=1e-9)
    # a growing mode is physics: only its imaginary part limits the step
    h, _ = stable_step("rk4", np.array([5.0, 0.1 + 2j]))
    assert 2 * h == pytest.approx(2 * math.sqrt(2), rel=1e-9)
    assert stable_step("dop853", np.array([-1.0]))[0] > 6.0
    assert stable_step("dop853", np.array([1j]))[0] > 5.0
    assert stable_step("rk4", np.zeros(3)) == (math.inf, 0.0)


def test_beta20_fastest_rate_is_the_top_modes_damping(beta20):
    """The guard's rate estimate (eigenvalues of the forward-difference
    Jacobian at the equilibrium) is the fast root of the 20th mode's own
    block, ä + c ȧ + k a = 0 with c = β k: −c/2 − √(c²/4 − k) ≈ −βω₂₀²
    (measured: 359586.70 against 359586.04 1/s; the mounts couple the
    modes, 1.8e-6 relative)."""
    sf, _, system, y0 = beta20
    eom = system.flex_compiled[0].eom
    k, c = np.diag(eom.K)[-1], np.diag(eom.C)[-1]
    assert c == pytest.approx(0.01 * k, rel=1e-12)
    fast = c / 2 + math.sqrt(c * c / 4 - k)
    rho = np.abs(motion_eigenvalues(system, y0)).max()
    print(f"\nbeta20: fastest rate {rho:.6e} 1/s, block's own {fast:.6e}, "
          f"omega_20 = {math.sqrt(k):.1f} rad/s")
    assert rho == pytest.approx(fast, rel=1e-5)


def test_beta20_implicit_methods_take_long_steps_and_converge(beta20):
    """1 s after a 10 ms base pulse, against radau at rtol 1e-8 (itself
    within 1.3e-11 m of radau at 1e-10): radau at the scene's rtol 1e-6
    takes 391 steps (t_end·ρ = 3.6e5, t_end·ω₂₀ = 6.0e3) and is within
    5.4e-10 m; bdf at rtol 1e-8 takes 974 steps and is within 1.5e-9 m
    (the bodies move 12 mm relative to the base); modal coordinates within
    1.6e-9 and 3.3e-9 kg^1/2 m (the first mode's amplitude is 0.083)."""
    sf, _, system, y0 = beta20
    t_end = 1.0
    rho = np.abs(motion_eigenvalues(system, y0)).max()
    omega20 = math.sqrt(np.diag(system.flex_compiled[0].eom.K)[-1])
    lay = system.layout
    ref = integrate(system, y0, settings(sf, t_end=t_end, rtol=1e-8, atol=1e-11))
    assert ref.complete, ref.message
    r_ref = lay.split(ref.y)["r"]
    a_ref = ref.y[:, lay.q_modal]
    r_base = np.array([system.base_motion_at(t)[0] for t in ref.t])
    rel = r_ref - r_base[:, None, :]
    motion = np.abs(rel - rel[0]).max()                    # relative to the base
    assert motion > 1e-3
    cases = (("radau", sf.solver.rtol, sf.solver.atol, 5e-9, 1.5e-8),
             ("bdf", 1e-8, 1e-11, 1.5e-8, 3.3e-8))
    for method, rtol, atol, tol_r, tol_a in cases:
        run = integrate(system, y0, settings(sf, method=method, t_end=t_end, rtol=rtol, atol=atol))
        assert run.complete, run.message
        err_r = np.abs(lay.split(run.y)["r"] - r_ref).max()
        err_a = np.abs(run.y[:, lay.q_modal] - a_ref).max()
        steps = run.stats.steps
        print(f"\nbeta20 {method} rtol {rtol:g}: {steps} steps (t_end rho = {t_end * rho:.3g}, "
              f"t_end omega_20 = {t_end * omega20:.3g}), {run.stats.jacobian_evaluations} "
              f"Jacobians, error {err_r:.2e} m (motion on the mounts {motion:.3g} m), "
              f"modal {err_a:.2e}")
        assert np.all(np.isfinite(run.y))
        assert steps < 0.01 * t_end * rho
        assert err_r < tol_r and err_a < tol_a


def test_beta20_explicit_methods_refuse_with_one_line(beta20):
    """Over the scene's 2 s, DOP853's stability (|hλ| ≤ 6.39 on the
    negative real axis) would force 112,000 steps (above stiff_steps =
    100,000) and rk4's dt = 1 ms is 130 times its stable step: both stop
    before the first step, state finite, and say what to use."""
    sf, _, system, y0 = beta20
    rho = np.abs(motion_eigenvalues(system, y0)).max()
    for method in ("dop853", "rk4"):
        run = integrate(system, y0, settings(sf, method=method))
        print(f"\nbeta20 {method}: {run.message}")
        assert not run.complete and run.stats.steps == 0 and run.t_reached == 0.0
        assert run.t.size == 1 and np.all(np.isfinite(run.y))
        assert "\n" not in run.message
        m = re.fullmatch(r"stiff scene: the fastest rate (\S+) 1/s limits (\w+) to steps below "
                         r"(\S+) s \((.*)\); use integrator = \"auto\", \"radau\" or \"bdf\"",
                         run.message)
        assert m and m[2] == method
        assert float(m[1]) == pytest.approx(rho, rel=0.05)
        bound = 6.39 if method == "dop853" else 2.785
        assert float(m[3]) == pytest.approx(bound / rho, rel=0.05)
        if method == "dop853":
            steps = re.fullmatch(r"(\d+) steps for 2 s, more than stiff_steps = 100000", m[4])
            assert steps and int(steps[1]) == pytest.approx(2.0 * rho / 6.39, rel=0.01)
        else:
            assert m[4] == "dt = 0.001 s"
    # a shorter run, or a higher threshold, lets dop853 go (checked, not run)
    assert stiff_message(system, y0, settings(sf, method="dop853", t_end=0.5)) is None
    assert stiff_message(system, y0, Settings("dop853", t_end=2.0, stiff_steps=200_000)) is None


def test_beta20_simulate_command_exits_1_with_the_stiff_message(beta20, tmp_path, capsys):
    sf, modes, _, _ = beta20
    out = tmp_path / "r.h5"
    code = flexbed(["simulate", str(SCENES / "hard_beta20.toml"), "--modes-file", str(modes),
                    "--integrator", "dop853", "-o", str(out), "--no-progress"])
    err = capsys.readouterr().err.strip()
    assert code == 1
    assert len(err.splitlines()) == 1
    assert err.startswith("flexbed simulate: stiff scene: the fastest rate 3.6e+05 1/s limits "
                          "dop853 to steps below 1.8e-05 s")
    assert 'use integrator = "auto", "radau" or "bdf"' in err
    assert read_results(out).attrs[""]["complete"] is False


# ----------------------------------------------------- 2. stiff and soft mounts together

@pytest.fixture(scope="module")
def stiff_soft():
    """Scene, system, equilibrium and the exact vertical two-mass chain:
    block m1 on 4 k1 (damping 4 c1), box m2 on 4 k2 above it."""
    sf = scene("hard_stiff_soft.toml")
    system = compile_scene(sf)
    eq = solve_statics(system, tol=sf.solver.static_tol)
    assert eq.success, eq.message
    m1, m2, k1, c1, k2 = 10.0, 10.0, 4e9, 2e4, 4e3
    M = np.diag([m1, m2])
    K = np.array([[k1 + k2, -k2], [-k2, k2]])
    C = np.diag([c1, 0.0])
    A = np.block([[np.zeros((2, 2)), np.eye(2)],
                  [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    lam, V = np.linalg.eig(A)
    return sf, system, eq.y, dict(m1=m1, m2=m2, k1=k1, k2=k2, lam=lam, V=V)


def kicked_box(system, y_eq, v0):
    y0 = y_eq.copy()
    system.layout.split(y0)["rd"][1, 2] = v0
    return y0


def chain_errors(system, y_eq, run, exact, v0):
    """Largest errors [m] of the block's and the box's vertical motion
    against x(t) = V e^{Λt} V⁻¹ x0, and the box's amplitude [m]."""
    lam, V = exact["lam"], exact["V"]
    c = np.linalg.solve(V, [0.0, 0.0, 0.0, v0])
    x = np.real(V @ (c[:, None] * np.exp(np.outer(lam, run.t))))
    r = system.layout.split(run.y)["r"][:, :, 2] - system.layout.split(y_eq)["r"][:, 2]
    return np.abs(r[:, 0] - x[0]).max(), np.abs(r[:, 1] - x[1]).max(), np.abs(x[1]).max()


def test_stiff_soft_statics_and_eigenvalues_are_exact(stiff_soft):
    """Static drops (m1 + m2) g / 4k1 = 4.9e-8 m and m2 g / 4k2 = 24.5 mm:
    measured relative errors 1.2e-10 and 1.6e-15. The guard's Jacobian has
    the chain's four eigenvalues −1000 ± 19975 i and ±20.0 i 1/s to
    1.3e-15 and 2.9e-14 relative."""
    sf, system, y_eq, ex = stiff_soft
    r_eq = system.layout.split(y_eq)["r"]
    drop_block = 0.5 - r_eq[0, 2]
    drop_box = (0.8 - r_eq[1, 2]) - drop_block
    e1 = abs(drop_block / ((ex["m1"] + ex["m2"]) * G / ex["k1"]) - 1)
    e2 = abs(drop_box / (ex["m2"] * G / ex["k2"]) - 1)
    lam = motion_eigenvalues(system, y_eq)
    e_lam = [np.abs(lam - v).min() / abs(v) for v in ex["lam"]]
    print(f"\nstiff/soft statics: drops {drop_block:.6e} m, {drop_box:.6e} m, relative errors "
          f"{e1:.1e}, {e2:.1e}; eigenvalue errors {max(e_lam[:2] + e_lam[2:]):.1e}")
    assert e1 < 2e-9 and e2 < 1e-13
    assert max(e_lam) < 3e-13
    assert np.abs(r_eq[:, :2]).max() == 0.0


def test_stiff_soft_motion_against_the_exact_chain(stiff_soft):
    """The box kicked at 0.1 m/s: radau (the scene's rtol 1e-8, atol 1e-10)
    takes 444 steps over 1 s where the stiff mode's |λ| t_end is 2.0e4,
    errors 6.7e-14 m (block, 1.6e-8 m of motion) and 9.4e-11 m (box, 5 mm);
    dop853 (0.5 s, held at its stable step) 9.8e-12 m and 2e-16 m."""
    sf, system, y_eq, ex = stiff_soft
    v0 = 0.1
    y0 = kicked_box(system, y_eq, v0)
    stiff_rate = abs(ex["lam"][0])
    run = integrate(system, y0, settings(sf))
    assert run.complete, run.message
    e_block, e_box, amp = chain_errors(system, y_eq, run, ex, v0)
    print(f"\nstiff/soft radau: {run.stats.steps} steps (t_end |lambda| = "
          f"{sf.solver.t_end * stiff_rate:.3g}), errors {e_block:.2e} m, {e_box:.2e} m "
          f"(amplitude {amp:.3g} m)")
    assert run.stats.steps < 0.05 * sf.solver.t_end * stiff_rate
    assert e_block < 7e-13 and e_box < 1e-9
    run = integrate(system, y0, settings(sf, method="dop853", t_end=0.5))
    assert run.complete, run.message
    e_block, e_box, _ = chain_errors(system, y_eq, run, ex, v0)
    print(f"stiff/soft dop853: {run.stats.steps} steps, errors {e_block:.2e} m, {e_box:.2e} m")
    assert e_block < 1e-10 and e_box < 1e-12


def test_stiff_soft_rk4_bound_is_sharp(stiff_soft):
    """rk4 with the scene's dt = 1 ms stops: 'rk4 step too long: … use dt
    below 6.9e-05 s'. Just below that bound it runs and matches the exact
    chain (6.6e-13 m); just above it (guard off, every velocity nudged by
    1e-6) it grows a billionfold in 0.05 s."""
    sf, system, y_eq, ex = stiff_soft
    y0 = kicked_box(system, y_eq, 0.1)
    run = integrate(system, y0, settings(sf, method="rk4", t_end=0.05))
    print(f"\nstiff/soft rk4: {run.message}")
    assert not run.complete and run.stats.steps == 0
    m = re.fullmatch(r"rk4 step too long: the fastest rate (\S+) 1/s limits rk4 to steps below "
                     r"(\S+) s \(dt = 0.001 s\); use dt below (\S+) s", run.message)
    assert m and m[2] == m[3]
    h, _ = stable_step("rk4", motion_eigenvalues(system, y0))
    assert float(m[2]) == pytest.approx(h, rel=0.01)
    below = integrate(system, y0, Settings("rk4", t_end=0.05, dt=0.98 * h))
    assert below.complete, below.message
    e_block, e_box, _ = chain_errors(system, y_eq, below, ex, 0.1)
    assert e_block < 7e-12 and e_box < 1e-12
    nudged = y0.copy()
    lay = system.layout
    nudged[lay.nq:lay.nq + lay.nv] += 1e-6
    growth = {}
    for f in (0.98, 1.02):
        run = integrate(system, nudged, Settings("rk4", t_end=0.05, dt=f * h, stiff_steps=0))
        dev = run.y[:, :lay.nq + lay.nv] - run.y[0, :lay.nq + lay.nv]
        growth[f] = np.abs(dev).max() if np.all(np.isfinite(dev)) else math.inf
    print(f"rk4 at 0.98 and 1.02 times the bound {h:.3e} s: largest deviation "
          f"{growth[0.98]:.3g}, {growth[1.02]:.3g}")
    assert growth[0.98] < 0.1 and growth[1.02] > 1e3


# ------------------------------------------------- 3. hardening mounts under a shock

def test_hardening_mounts_under_a_shock_pulse_converge_and_balance():
    """20 g, 6 ms triangle under 50 kg on degree-8 mounts; reference
    dop853 at rtol 1e-12 (4.7e-15 m from rtol 1e-13). Peak mount force
    3615 N, 9.5 times the linear part. Errors: dop853 at the scene's rtol
    1e-8 7.3e-12 m, 2.3e-11 in p; radau at 1e-8 3.0e-12 m, 4.6e-12.
    Energy balance drift over the largest kinetic energy (1763 J; the
    drive does 16 kJ of work): reference 8e-15, dop853 1.1e-11, radau
    1.4e-9."""
    sf = scene("hard_hardening_pulse.toml")
    system = compile_scene(sf)
    eq = solve_statics(system, tol=sf.solver.static_tol)
    assert eq.success, eq.message
    lay = system.layout
    ref = integrate(system, eq.y, settings(sf, rtol=1e-12, atol=1e-14))
    assert ref.complete, ref.message
    h = history(system, ref.t, ref.y)
    T_max = h["kinetic"].sum(axis=1).max()
    b = h["balance"]
    drift_ref = np.abs(b - b[0]).max() / T_max
    # the hardening is what carries the load
    dz = h["deflection"][:, :, 2]
    f_lin = 1e5 * dz
    peak = np.abs(h["force"][:, :, 2]).max()
    assert peak > 5 * np.abs(f_lin).max()
    assert np.abs(h["work"][:, 2]).max() > 5 * T_max
    r_ref, p_ref = lay.split(ref.y)["r"], lay.split(ref.y)["p"]
    print(f"\nhardening: peak force {peak:.0f} N, largest deflection {np.abs(dz).max():.3e} m, "
          f"reference balance drift {drift_ref:.1e} of {T_max:.0f} J")
    assert drift_ref < 1e-13
    for method, tol_r, tol_p, tol_b in (("dop853", 7e-11, 2.3e-10, 1e-10),
                                         ("radau", 3e-11, 4.6e-11, 1.5e-8)):
        run = integrate(system, eq.y, settings(sf, method=method))
        assert run.complete, run.message
        err_r = np.abs(lay.split(run.y)["r"] - r_ref).max()
        err_p = np.abs(lay.split(run.y)["p"] - p_ref).max()
        bb = history(system, run.t, run.y)["balance"]
        drift = np.abs(bb - bb[0]).max() / T_max
        print(f"hardening {method} rtol {sf.solver.rtol:g}: {run.stats.steps} steps, error "
              f"{err_r:.1e} m, {err_p:.1e} in p, balance drift {drift:.1e}")
        assert err_r < tol_r and err_p < tol_p and drift < tol_b


# ------------------------------------------------------- 4. 1000 s of free vibration

def test_thousand_seconds_of_free_vibration_keep_p_and_energy():
    """Kicked box (0.1 m/s, 0.5 rad/s; rotations up to 18°), 1000 s with
    the scene's dop853 at rtol 1e-10 (6854 steps): |p| − 1 at most 1.1e-16
    at every sample; the total energy drifts by 2.6e-9 of itself (steadily
    down: the method's dissipation)."""
    sf = scene("hard_long_free.toml")
    system = compile_scene(sf)
    y0 = system.initial_state()
    parts = system.layout.split(y0)
    parts["rd"][0] = [0.05, -0.08, 0.1]
    parts["w"][0] = [0.3, -0.2, 0.5]
    run = integrate(system, y0, settings(sf))
    assert run.complete, run.message
    assert run.t[-1] == 1000.0 and run.t.size == 10001
    h = history(system, run.t, run.y)
    E = (h["kinetic"].sum(axis=1) + h["gravity_potential"].sum(axis=1)
         + h["mount_potential"].sum(axis=1))
    drift = np.abs(E - E[0]).max() / E[0]
    p_err = np.abs(np.linalg.norm(h["euler_parameters"][:, 1], axis=1) - 1).max()
    angle = np.degrees(np.abs(h["orientation"][:, 1]).max())
    print(f"\n1000 s free vibration: {run.stats.steps} steps, energy drift {drift:.2e} of "
          f"E0 = {E[0]:.4f} J (end: {(E[-1] - E[0]) / E[0]:+.2e}), max ||p|-1| {p_err:.1e}, "
          f"largest angle {angle:.1f} deg")
    assert angle > 10
    assert p_err < 1e-12
    assert drift < 3e-8


# ---------------------------------------------------------------- 5. free spin

def spin(spinner, w0, t_end):
    """Run the free body with body-frame angular velocity w0 [rad/s]."""
    sf, system = spinner
    y0 = system.initial_state()
    system.layout.split(y0)["w"][0] = w0
    run = integrate(system, y0, settings(sf, t_end=t_end))
    assert run.complete, run.message
    parts = system.layout.split(run.y)
    w, p = parts["w"][:, 0], parts["p"][:, 0]
    J = system.J[0]
    Jw = w @ J
    L = np.einsum("kij,kj->ki", rotation_matrix(p), Jw)          # inertial
    T = 0.5 * np.einsum("ki,ki->k", w, Jw)
    return run, w, L, np.linalg.norm(Jw, axis=1), T


@pytest.fixture(scope="module")
def spinner():
    sf = scene("hard_free_spin.toml")
    return sf, compile_scene(sf)


def test_intermediate_axis_flips_at_the_exact_elliptic_times(spinner):
    """J = diag(1, 2, 3), ω̄0 = (0, 5, 0.01) rad/s: at t = 0 the exact
    solution is at sn = 1 (L² > 2TJ₂): ω₁ = a₁ cn(u), ω₂ = a₂ sn(u),
    ω₃ = a₃ dn(u), u = λt + K(m). ω₂ flips sign at (2n + 1) K/λ
    (from 2.4427 s, every 4.885 s). Measured over 25 s (five flips): ω
    within 0.6–1.5e-9 rad/s of the exact one (near the separatrix round-off
    differences grow: the figure moves with the right-hand side's
    arithmetic), flip times within 2.0e-9 s, kinetic energy, |J ω| and the
    inertial L vector within 7.9e-12, 4.0e-12 and 1.9e-11 relative."""
    J1, J2, J3 = np.diag(spinner[1].J[0])
    run, w, L, Jw, T = spin(spinner, (0.0, 5.0, 0.01), 25.0)
    E2, L2 = 2 * T[0], Jw[0] ** 2
    assert L2 > E2 * J2
    lam = math.sqrt((J3 - J2) * (L2 - E2 * J1) / (J1 * J2 * J3))
    m = (J2 - J1) * (E2 * J3 - L2) / ((J3 - J2) * (L2 - E2 * J1))
    K = ellipk(m)
    sn, cn, dn, _ = ellipj(lam * run.t + K, m)
    exact = np.column_stack([math.sqrt((E2 * J3 - L2) / (J1 * (J3 - J1))) * cn,
                             math.sqrt((E2 * J3 - L2) / (J2 * (J3 - J2))) * sn,
                             math.sqrt((L2 - E2 * J1) / (J3 * (J3 - J1))) * dn])
    err_w = np.abs(w - exact).max()
    wy, t = w[:, 1], run.t
    i = np.flatnonzero(np.sign(wy[1:]) != np.sign(wy[:-1]))
    flips = t[i] - wy[i] * (t[i + 1] - t[i]) / (wy[i + 1] - wy[i])
    flips_exact = (2 * np.arange(flips.size) + 1) * K / lam
    err_flip = np.abs(flips - flips_exact).max()
    e_T = np.abs(T / T[0] - 1).max()
    e_Jw = np.abs(Jw / Jw[0] - 1).max()
    e_L = np.linalg.norm(L - L[0], axis=1).max() / Jw[0]
    print(f"\nintermediate axis: {run.stats.steps} steps, flips at {np.round(flips, 4)} s "
          f"(exact period {4 * K / lam:.6f} s), omega error {err_w:.1e} rad/s, flip times "
          f"{err_flip:.1e} s; T {e_T:.1e}, |J w| {e_Jw:.1e}, L {e_L:.1e}")
    assert flips.size == 5 and wy.min() < -4.99
    assert err_w < 1.5e-8 and err_flip < 2e-8
    assert e_T < 7.5e-11 and e_Jw < 4e-11 and e_L < 2e-10


@pytest.mark.parametrize("axis", [0, 2], ids=["minor", "major"])
def test_spin_about_the_minor_and_major_axes_is_stable(spinner, axis):
    """ω̄0 = 5 rad/s about the axis, 0.01 rad/s about the others, 12 s: the
    spin stays within 6.0e-6 (minor) and 6.7e-7 (major) relative of
    5 rad/s, the others within 0.02 rad/s; energy and |J ω| within
    1.1e-14, the inertial L within 2.3e-12 relative."""
    w0 = np.full(3, 0.01)
    w0[axis] = 5.0
    run, w, L, Jw, T = spin(spinner, w0, 12.0)
    spin_err = np.abs(w[:, axis] / 5.0 - 1).max()
    others = np.abs(np.delete(w, axis, axis=1)).max()
    e_T = np.abs(T / T[0] - 1).max()
    e_Jw = np.abs(Jw / Jw[0] - 1).max()
    e_L = np.linalg.norm(L - L[0], axis=1).max() / Jw[0]
    print(f"\nspin about axis {axis}: spin within {spin_err:.1e}, others below {others:.3g} rad/s; "
          f"T {e_T:.1e}, |J w| {e_Jw:.1e}, L {e_L:.1e}")
    assert spin_err < 6e-5 and others < 0.025
    assert e_T < 1e-13 and e_Jw < 1e-13 and e_L < 2.3e-11


# -------------------------------------------------------- 6. mass ratio of a million

def test_heavy_free_base_gives_the_exact_two_body_oscillation():
    """Base 1e7 kg, equipment 10 kg, k = 4e4 N/m, equipment kicked at
    0.1 m/s: the relative motion is (v0/ω) sin ωt with ω = √(k(1/m1 +
    1/m2)) to 2.5e-12 m, while the one-body frequency √(k/m2) would be off
    by 2.5e-7 m after 5 s; momentum m1 v1 + m2 v2 stays within 5.6e-15
    kg m/s of 1 (any Runge–Kutta method keeps linear invariants), the
    centre of mass moves uniformly to 1.9e-21 m."""
    sf = scene("hard_heavy_base.toml")
    system = compile_scene(sf)
    lay = system.layout
    assert lay.base_free
    m1, m2, k, v0 = 1e7, 10.0, 4e4, 0.1
    assert system.mass[0] == m1 and system.mass[1] == m2
    y0 = system.initial_state()
    lay.split(y0)["rd"][0] = (0.0, 0.0, v0)
    run = integrate(system, y0, settings(sf))
    assert run.complete, run.message
    parts = lay.split(run.y)
    z1, z2 = parts["r_base"][:, 2], parts["r"][:, 0, 2]
    v1, v2 = parts["rd_base"][:, 2], parts["rd"][:, 0, 2]
    x = (z2 - z2[0]) - (z1 - z1[0])
    omega = math.sqrt(k * (1 / m1 + 1 / m2))
    err_two = np.abs(x - v0 / omega * np.sin(omega * run.t)).max()
    err_one = np.abs(x - v0 / math.sqrt(k / m2) * np.sin(math.sqrt(k / m2) * run.t)).max()
    err_P = np.abs(m1 * v1 + m2 * v2 - m2 * v0).max()
    cm = (m1 * z1 + m2 * z2) / (m1 + m2)
    err_cm = np.abs(cm - cm[0] - m2 * v0 / (m1 + m2) * run.t).max()
    print(f"\nheavy base: {run.stats.steps} steps; relative motion error {err_two:.1e} m "
          f"(one-body formula: {err_one:.1e} m), momentum {err_P:.1e} kg m/s, "
          f"centre of mass {err_cm:.1e} m, base speed up to {np.abs(v1).max():.2e} m/s")
    assert err_two < 2.5e-11
    assert err_one > 1e-7
    assert err_P < 5.6e-14 and err_cm < 2e-20
    assert np.abs(parts["r"][:, 0, :2]).max() == 0.0 and np.abs(parts["p"][:, 0, 1:]).max() == 0.0

"""Speed against error of every integrator on a scene, with a rigid or a flexible bed.

For each integrator, a ladder of steps or tolerances over the scene's run
(the reference scene: 0–3 s): wall time, steps, rejected steps,
right-hand-side and Jacobian evaluations, and the maximum position error of
every body but the base against the project's own reference — fixed-step
RK4 at a step far below the ladder's (adaptive methods at tight rtol are
limited by rtol·|r| with |r| ≈ 5 m, fixed steps are not), its own error
estimated by Richardson extrapolation against twice that step (with a
flexible bed the step is also kept below 0.2 / the fastest rate of its
damped modes, so that the reference is stable). Plus the cost of one
right-hand-side evaluation in µs. :func:`benchmark_dynamics` returns the
Markdown text (``flexbed bench rigid`` and ``flexbed bench flexible``).
"""

from __future__ import annotations

import math
import platform
import tempfile
import timeit
from dataclasses import replace
from pathlib import Path

import numpy as np
import scipy

from dynamics.integrate import Settings, integrate
from dynamics.statics import solve_statics

from .cmd_modes import ensure_modes
from .cmd_static import compile_scene
from .errors import NumericalError
from .scene_file import load_scene

__all__ = ["benchmark_rigid", "benchmark_dynamics", "LADDERS", "QUICK"]

LADDERS = {
    "rk4": [4e-3, 2e-3, 1e-3, 5e-4],
    "dop853": [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10],
    "adams": [1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10],
    "bdf": [1e-4, 1e-5, 1e-6, 1e-7, 1e-8],
    "radau": [1e-4, 1e-5, 1e-6, 1e-7, 1e-8],
}
QUICK = {"rk4": [2e-3], "dop853": [1e-5], "adams": [1e-7], "bdf": [1e-6], "radau": [1e-5]}
AIMS = ((1e-6, 0.05), (1e-9, 0.2))


def _positions(system, run):
    return system.layout.split(run.y)["r"]


def rhs_cost_us(system, t: float, y: np.ndarray, reps: int = 2000) -> float:
    """Best-of-5 time of one right-hand-side evaluation [µs]."""
    return min(timeit.repeat(lambda: system.rhs(t, y), number=reps, repeat=5)) / reps * 1e6


def benchmark_rigid(scene=None, *, quick: bool = False, reference_dt: float = 1e-4,
                    output_dt: float = 0.01, log=lambda m: None) -> str:
    """Run the ladders on the scene with a rigid bed and return the Markdown
    report (see the module docstring)."""
    return benchmark_dynamics(scene, quick=quick, reference_dt=reference_dt,
                              output_dt=output_dt, log=log)


def benchmark_dynamics(scene=None, *, n_modes: int | None = None, quick: bool = False,
                       reference_dt: float = 1e-4, output_dt: float = 0.01,
                       log=lambda m: None) -> str:
    """The same ladders with a rigid bed (``n_modes`` None) or a flexible bed
    keeping ``n_modes`` modes with the scene's damping."""
    sf = load_scene(scene)
    if n_modes is None:
        sf = replace(sf, bed=replace(sf.bed, model="rigid"))
        system = compile_scene(sf)
        label = "rigid bed"
    else:
        sf = replace(sf, bed=replace(sf.bed, model="flexible", modes=n_modes, fmax=None))
        with tempfile.TemporaryDirectory() as tmp:
            data, _ = ensure_modes(sf, Path(tmp) / "modes.h5", log=lambda m: None)
            system = compile_scene(sf, data.path)
        alpha, beta = sf.bed.rayleigh
        label = (f"flexible bed, {n_modes} modes, Rayleigh α = {alpha:g}, β = {beta:g}")
    t_end = sf.solver.t_end
    eq = solve_statics(system, tol=sf.solver.static_tol, sag=sf.bed.static_sag)
    if not eq.success:
        raise NumericalError(f"{sf.source.name}: {eq.message}")
    y0 = eq.y
    probe = integrate(system, y0, Settings("dop853", t_end=min(0.5, t_end), rtol=1e-6,
                                           atol=1e-9, output_dt=min(0.5, t_end)))
    t_probe, y_probe = float(probe.t[-1]), probe.y[-1]
    rhs_us = rhs_cost_us(system, t_probe, y_probe)
    log(f"bench {label}: one right-hand side {rhs_us:.1f} µs; reference ...")
    # The reference must be stable: RK4's step below 0.2 / (the fastest rate
    # of the damped modes), and a divisor of the output spacing.
    for fc in system.flex_compiled:
        k_max = float(np.max(np.diag(fc.eom.K), initial=0.0))
        c_max = float(np.max(np.diag(fc.eom.C), initial=0.0))
        rate = math.sqrt(k_max) + c_max
        if rate > 0:
            reference_dt = min(reference_dt, 0.2 / rate)
    reference_dt = output_dt / math.ceil(output_dt / reference_dt - 1e-9)
    ref = integrate(system, y0, Settings("rk4", t_end=t_end, dt=reference_dt, output_dt=output_dt))
    ref2 = integrate(system, y0, Settings("rk4", t_end=t_end, dt=2 * reference_dt,
                                          output_dt=output_dt))
    if not (ref.complete and ref2.complete):
        raise NumericalError(f"reference run failed: {ref.message} / {ref2.message}")
    R = _positions(system, ref)
    ref_err = float(np.max(np.abs(_positions(system, ref2) - R))) / 15.0
    rows = []
    for method, ladder in (QUICK if quick else LADDERS).items():
        for v in ladder:
            if method == "rk4":
                st = Settings("rk4", t_end=t_end, dt=v, output_dt=output_dt)
                setting = f"dt = {v:g} s"
            else:
                st = Settings(method, t_end=t_end, rtol=v, atol=1e-3 * v, output_dt=output_dt)
                setting = f"rtol = {v:g}, atol = {1e-3 * v:g}"
            log(f"bench {label}: {method} {setting}")
            with np.errstate(all="ignore"):      # an unstable setting fails, reported
                r = integrate(system, y0, st)
            err = float(np.max(np.abs(_positions(system, r) - R))) if r.complete else float("nan")
            s = r.stats
            rows.append((method, setting, s.steps, s.rejected, s.rhs_evaluations,
                         s.jacobian_evaluations, s.wall_time, err, r.complete))
    lines = [f"# Benchmark: {sf.scene.name}, {label}, 0–{t_end:g} s", "",
             f"Machine: {platform.machine()}, Python {platform.python_version()}, "
             f"NumPy {np.__version__}, SciPy {scipy.__version__}.", "",
             f"One right-hand-side evaluation: **{rhs_us:.1f} µs** "
             f"(timeit, best of 5 × 2000 calls, state at t = {t_probe:g} s).", "",
             f"Reference: RK4 with dt = {reference_dt:g} s; its own error, estimated from the "
             f"run with 2·dt (Richardson, /15): {ref_err:.1e} m. Error: the largest deviation "
             f"of any position coordinate of bodies 2… from the reference on a {output_dt:g} s "
             f"grid. Wall time: the integration alone (stepping, dense output, projection, "
             f"bookkeeping), not the statics or the results file. Rejected steps of adams, bdf "
             f"and radau are counted from the distinct trial times of their right-hand-side "
             f"calls (SciPy does not report them).", "",
             "| integrator | setting | steps | rejected | rhs evals | Jacobians | wall time [s] "
             "| max error [m] |", "|---|---|---:|---:|---:|---:|---:|---:|"]
    for method, setting, steps, rej, nfev, njev, wall, err, ok in rows:
        rej_s = "n/a" if rej < 0 else str(rej)
        err_s = f"{err:.2e}" if ok else "failed"
        lines.append(f"| {method} | {setting} | {steps} | {rej_s} | {nfev} | {njev} | "
                     f"{wall:.3f} | {err_s} |")
    lines += ["", "Against the aims:", ""]
    for target, budget in AIMS:
        ok = [r for r in rows if r[8] and r[7] <= target]
        if ok:
            best = min(ok, key=lambda r: r[6])
            verdict = "met" if best[6] <= budget else "not met"
            lines.append(f"- error ≤ {target:g} m in ≤ {budget:g} s: fastest is {best[0]} "
                         f"({best[1]}) in {best[6]:.3f} s with {best[4]} right-hand sides — "
                         f"{verdict}.")
        else:
            lines.append(f"- error ≤ {target:g} m in ≤ {budget:g} s: no setting of this ladder "
                         f"reached the error.")
    return "\n".join(lines) + "\n"

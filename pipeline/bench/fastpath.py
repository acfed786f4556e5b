"""Report sections for modelling only what a scene needs: the linear fast
path against the nonlinear model, and ``modes = "auto"`` against keeping
many modes. Each is a ``section(ctx) -> str`` of :mod:`flexbed.bench.report`.
"""

from __future__ import annotations

import math
import statistics
import time
from dataclasses import replace

import numpy as np

from flexbed.dynamics.integrate import Settings, integrate
from flexbed.dynamics.linear import run_linear

from flexbed.bench.cases import CaseSpec, build_case
from flexbed.bench.context import BenchContext
from flexbed.bench.dynamics import settings_for
from flexbed.bench.markdown import fmt_error, md_table
from flexbed.bench.modelling import solve
from flexbed.bench.reference import errors, sample
from flexbed.stages.modes_auto import cutoff

__all__ = ["section_linear", "section_modes_auto"]

#: the settings reaching the linear path's error timed again beside it ...
_CANDIDATES = 3
#: ... in this many interleaved pairs each (quick profile: the second)
_PAIRS, _PAIRS_QUICK = 11, 3


def _side_by_side(ctx: BenchContext, case, st: Settings, ladder: list, target: float) -> dict:
    """The linear path and each of the fastest settings (by the ladder's own
    times) whose error is at most ``target``, timed in interleaved pairs
    (CPU seconds of whole calls): the cheapest setting, the one with the
    largest median over its pairs of linear / integrator (a ratio of times
    taken side by side, steadier than either time), and that ratio; None
    when no setting reaches ``target``."""
    ok = sorted((m for m in ladder if m.ok and m.position_error <= target),
                key=lambda m: m.wall_time)[:_CANDIDATES]
    pairs = _PAIRS_QUICK if ctx.quick else _PAIRS
    found = None
    for m in ok:
        ist = settings_for(m.method, m.value, case.t_end, ctx.output_dt)
        lin, integ = [], []
        for _ in range(pairs):
            c0 = time.process_time()
            run_linear(case.system, case.y0, case.y0, st)
            c1 = time.process_time()
            integrate(case.system, case.y0, ist)
            c2 = time.process_time()
            lin.append(c1 - c0)
            integ.append(c2 - c1)
        here = dict(best=m, integrator=statistics.median(integ), linear=statistics.median(lin),
                    ratio=statistics.median(a / b for a, b in zip(lin, integ)))
        if found is None or here["ratio"] > found["ratio"]:
            found = here
    return found


def section_linear(ctx: BenchContext) -> str:
    """The linear fast path on each integrator case: cost, estimated and actual error."""
    rows, res = [], {}
    # the integrators' own output grid: the linear path's cost grows with its
    # samples, the integrators' hardly
    st = Settings("rk4", t_end=ctx.t_end, output_dt=ctx.output_dt)
    for key in ctx.profile.cases:
        case, ref = ctx.case(key), ctx.reference(key)
        ctx.log(f"bench linear: {key} ...")
        runs, cpus = [], []
        for _ in range(1 if ctx.quick else 5):
            c0 = time.process_time()
            runs.append(run_linear(case.system, case.y0, case.y0, st))
            cpus.append(time.process_time() - c0)
        lr = runs[-1]
        solve_t = statistics.median(r.solve_time for r in runs)
        est_t = statistics.median(r.time_estimate for r in runs)
        total_t = statistics.median(r.solve_time + r.time_estimate for r in runs)
        cpu_t = statistics.median(cpus)
        s = sample(case.system, lr.run)
        pos, force = errors(ref.samples, s)
        c = lr.linearisation.coords
        corrected = lr.run.y.copy()
        corrected[:, :] = c.to_y(c.to_z(lr.run.y) + lr.estimate.e)
        corrected[:, case.system.layout.work] = lr.run.y[:, case.system.layout.work]
        pos_c, _ = errors(ref.samples, sample(case.system, replace(lr.run, y=corrected)))
        ladder = ctx.results.get("integrators", {}).get(key, [])
        side = _side_by_side(ctx, case, st, ladder, max(pos, 1e-12))
        best, ratio = (None, math.nan) if side is None else (side["best"], side["ratio"])
        best_s = "–" if best is None else (
            f"{best.method} ({best.setting}): {side['integrator']:.4f} s")
        res[key] = dict(solve_time=solve_t, estimate_time=est_t, total_time=total_t,
                        cpu_time=cpu_t, estimate=lr.estimate.position,
                        position_error=pos, force_error=force, corrected_error=pos_c,
                        reference_error=ref.position_error, pieces=lr.pieces,
                        best=None if best is None else (best.method, best.setting,
                                                        side["integrator"]),
                        side_linear=None if side is None else side["linear"],
                        ratio=ratio, defect_evaluations=lr.estimate.evaluations)
        rows.append([case.label, str(lr.pieces), f"{solve_t:.4f}", f"{est_t:.4f}",
                     f"{total_t:.4f}", f"{cpu_t:.4f}",
                     fmt_error(lr.estimate.position), fmt_error(pos), fmt_error(force),
                     fmt_error(pos_c), fmt_error(ref.position_error),
                     "–" if side is None else f"{side['linear']:.4f}", best_s,
                     "–" if best is None else f"{ratio:.2f}"])
    ctx.results["linear"] = res
    from flexbed.bench.report import AIMS          # the report's own aims (imports this module)
    aims = []
    for key, r in res.items():
        for target, budget in AIMS:
            if r["position_error"] > target:
                verdict = f"its error {r['position_error']:.2e} m is above it"
            else:
                verdict = (f"{r['solve_time']:.3f} s ({r['solve_time'] + r['estimate_time']:.3f}"
                           f" s with the estimate) — **"
                           f"{'met' if r['solve_time'] <= budget else 'not met'}**")
            aims.append(f"- {ctx.case(key).label}: {target:g} m in ≤ {budget:g} s: {verdict}.")
        if r["best"] is not None:
            method, setting, wall = r["best"]
            met = "met" if r["ratio"] <= 1.0 / 3.0 else "not met"
            aims.append(f"- {ctx.case(key).label}: at most 1/3 of the best integrator at the "
                        f"same accuracy ({method}, {setting}: {wall:.4f} s of CPU), the "
                        f"estimate included: {r['side_linear']:.4f} s, {r['ratio']:.2f} of it, "
                        f"side by side — **{met}**.")
    return "\n".join([
        "## The linear fast path against the nonlinear model", "",
        "`model = \"linear\"` (`dynamics/linear/run.py`, `dynamics/linear/propagation.py`): "
        "linearised about the static equilibrium, propagated exactly over the output samples "
        f"({ctx.output_dt:g} s, the integrators' own) and the inputs' knots (the load's samples): "
        "one exponential of the state "
        "augmented with the inputs (polynomial pieces, analytic sinusoids as rotating "
        "pairs) per distinct piece length, then the recursion z ← Φ z + Ψ w in compiled "
        "code (`dynamics/linear/sweep.py`). Solve time: linearisation "
        "(central differences of the right-hand side, one compiled batch) and propagation, "
        f"median of {1 if ctx.quick else 5} (wall; \"CPU\": the whole call, median). "
        "Estimate (`dynamics/linear/estimate.py`): the nonlinear right-hand side along the "
        "linear solution (the whole refinement in one compiled pass) on every 16th piece end "
        "first (runs of longer pieces every few), then "
        "midway in the intervals next to every node where the local cubics through the "
        "nodes it was added to miss the defect or a power by more than 8 % of its largest "
        "(the cubics kept then to about 0.5 %), quiet stretches keeping long intervals; the "
        "defect's cubics propagated exactly through the linear model from node to node, the "
        "largest point error between the nodes by cubic Hermite interpolation "
        "(`model = \"auto\"` needs it, `linear` reports it). "
        "Errors against the case's RK4 reference, on the report's grid; \"+ correction\": "
        "the linear solution plus the estimated error, i.e. one Newton step towards the "
        "nonlinear solution. Last columns, side by side: the settings of the ladders above "
        f"that reach the linear path's position error (the {_CANDIDATES} fastest there) timed "
        f"again, each in {_PAIRS_QUICK if ctx.quick else _PAIRS} pairs interleaved with the "
        "linear path (whole calls, CPU seconds, medians); the cheapest of them against the "
        "linear path, and the median over its pairs of the linear path's time over its (the "
        "aim: at most 1/3). "
        "Interleaving puts both under the same load: on this shared machine timings taken "
        "minutes apart differ by up to 1.6 times.", "",
        md_table(["case", "pieces", "solve time [s]", "estimate time [s]", "total [s]",
                  "CPU [s]", "estimated error [m]", "position error [m]",
                  "mount-force error [N]", "+ correction [m]", "reference's own error [m]",
                  "side by side: linear [s]", "nonlinear, same error", "linear / nonlinear"],
                 rows, align="lrrrrrrrrrrrlr"), "",
        "Against the aims, for the linear path (where its own error allows):", "",
        *aims, ""])


def section_modes_auto(ctx: BenchContext) -> str:
    """``modes = "auto"`` on the scene: what it keeps and its error against many modes."""
    sf = ctx.scene
    f_cut, f_in, f_sus = cutoff(sf.scene, ctx.t_end, sf.bed.auto_factor, sf.solver.static_tol)
    counts = ctx.results.get("modes_count")
    if counts is None:
        return ("## modes = \"auto\"\n\n(the modes-kept section did not run; this one "
                "compares with its reference)\n")
    ref = counts["reference"]
    n_ref = int(ref.name)
    path = ctx.modes.ensure(n_ref)
    from flexbed.files.modes import read_modes_file
    freq = read_modes_file(path).frequency
    n_auto = max(1, int(np.sum(freq < f_cut)))
    known = {r.name: r for r in counts["runs"]}
    run = known.get(str(n_auto))
    from flexbed.bench.report import MODES_COUNT_SETTING, QUICK_MODES_COUNT_SETTING
    method, rtol = QUICK_MODES_COUNT_SETTING if ctx.quick else MODES_COUNT_SETTING
    if run is None:
        case = build_case(sf, CaseSpec(f"modes-{n_auto}", n_modes=n_auto, damped=True),
                          ctx.modes, ctx.t_end)
        run = solve(str(n_auto), case, method, rtol, ctx.output_dt, repeats=1,
                    rhs_seconds=ctx.profile.rhs_seconds)
        run.measure_against(ref.samples)
    ctx.log(f"bench modes auto: {n_auto} modes + static correction ...")
    # the correction draws on the reference's modes, so that the two compare like for like
    sfc = replace(sf, bed=replace(sf.bed, correction_modes=n_ref))
    ccase = build_case(sfc, CaseSpec(f"modes-{n_auto}-corrected", n_modes=n_auto, damped=True,
                                     static_correction=True), ctx.modes, ctx.t_end)
    n_coords = ccase.system.layout.n_modal
    corrected = solve(f"{n_auto}+{n_coords - n_auto}", ccase, method, rtol, ctx.output_dt,
                      repeats=1 if ctx.quick else 3, rhs_seconds=ctx.profile.rhs_seconds)
    corrected.measure_against(ref.samples)
    ctx.results["modes_auto"] = dict(f_cut=f_cut, f_input=f_in, f_suspension=f_sus,
                                     n_modes=n_auto, run=run, reference=ref,
                                     corrected=corrected)
    n_file = n_ref
    rows = [[f"auto ({n_auto})", str(n_auto), f"{freq[n_auto - 1]:.1f}",
             f"{run.wall_time:.3f}", fmt_error(run.position_error),
             fmt_error(run.motion_error), fmt_error(run.force_error)],
            [f"auto ({n_auto}) + static correction", str(n_coords), f"{freq[n_auto - 1]:.1f}",
             f"{corrected.wall_time:.3f}", fmt_error(corrected.position_error),
             fmt_error(corrected.motion_error), fmt_error(corrected.force_error)],
            [f"all {n_ref} (reference)", str(n_ref), f"{freq[n_ref - 1]:.1f}",
             f"{ref.wall_time:.3f}", "–", "–", "–"]]
    return "\n".join([
        "## modes = \"auto\"", "",
        f"The rule (`pipeline/stages/modes_auto.py`): keep the modes below auto_factor × "
        f"max(f_input, f_suspension) = {sf.bed.auto_factor:g} × max({f_in:.3g}, "
        f"{f_sus:.3g}) Hz = {f_cut:.3g} Hz, at least one; f_input: 99.9 % of the inputs' "
        "spectral energy lies below it; f_suspension: the highest natural frequency of the "
        f"linearised scene with a rigid bed. On this scene that keeps {n_auto} mode(s). "
        "Error against the modes-kept section's reference, same integrator setting "
        f"({method}, rtol = {rtol:g}), same damping; \"motion\" is from each run's own "
        "equilibrium (the static sag's own truncation excluded).", "",
        "The rule looks at frequencies only, and modes far above the excitation still "
        "deflect quasi-statically under the mount forces: that is most of the error of the "
        "auto row. `static_correction = true` (`pipeline/stages/residual_modes.py`) adds it back: "
        "residual vectors spanning the static response, at the bed's mount points, of the "
        f"modes left out up to the modes file's {n_file}th, made mass- and "
        "stiffness-orthogonal by Rayleigh–Ritz (one per independent mount-point direction: "
        f"{n_coords - n_auto} here).", "",
        md_table(["modes kept", "modal coordinates", "highest mode f [Hz]", "solve time [s]",
                  "max position error [m]", "max motion error [m]",
                  "max mount-force error [N]"], rows, align="lrrrrrr"), ""])

"""Report section: what the bed's stresses cost beside the transient.

The report's scene with its bed flexible, as a Mindlin shell on 0.05 m
elements (16 × 96 = 1,536 elements on the reference bed), keeping 10
modes (and 10 + the static correction's residual vectors at the mount
points, from 30 modes). Timed, CPU seconds once the compiled code is
loaded: the transient as ``flexbed simulate`` runs it, and the stress
recovery over its samples (:func:`flexbed.analyses.bed_stress.superpose`:
every element's von Mises stress at both faces at every sample, the
peaks, the peak map). Aim: the recovery adds under 20 % to the transient.
The modal stresses themselves come with the modes (their cost is in the
modes stage's "invariants" time).
"""

from __future__ import annotations

import statistics
import time

from flexbed.analyses.bed_stress import in_run_coordinates, superpose
from flexbed.api.bed_modes import modes
from flexbed.api.equilibrium import statics
from flexbed.api.simulation import simulate
from flexbed.bench.context import BenchContext
from flexbed.bench.markdown import md_table
from flexbed.files.scene import parse_scene

__all__ = ["section_stress", "AIM", "shell_scene"]

#: the stress recovery's share of the transient's CPU time should stay below this
AIM = 0.20


def shell_scene(scene, static_correction: bool = False):
    """``scene`` with its bed flexible: a Mindlin shell on 0.05 m elements,
    10 modes (with the static correction from 30 modes)."""
    out, in_bed = [], False
    for line in scene.text.splitlines():
        key = line.split("=")[0].strip()
        if line.startswith("["):
            in_bed = line.strip() == "[bed]"
        if in_bed and key in ("model", "theory", "nx", "ny", "element_size", "modes", "fmax",
                              "static_correction", "correction_modes"):
            continue
        out.append(line)
        if in_bed and line.strip() == "[bed]":
            out += ['model = "flexible"', 'theory = "mindlin"', "element_size = 0.05",
                    "modes = 10"]
            if static_correction:
                out += ["static_correction = true", "correction_modes = 30"]
    return parse_scene("\n".join(out) + "\n", scene.source)


def _once(sf, data, eq, t_end: float) -> dict:
    c0 = time.process_time()
    run = simulate(sf, modes=data, equilibrium=eq, t_end=t_end)
    c1 = time.process_time()
    r = run._run()
    s = superpose(in_run_coordinates(data.stress, data.n_modes, r.basis), r.a, r.t)
    c2 = time.process_time()
    st = run.solver
    return dict(transient=c1 - c0 - float(st.get("load_time", 0.0)), stress=c2 - c1,
                method=str(st["method"]), steps=int(st["steps"]), samples=int(r.t.size),
                coordinates=int(r.a.shape[1]), elements=int(s.centres.shape[0]),
                peak=s.bed.value, time=s.bed.time)


def section_stress(ctx: BenchContext) -> str:
    """CPU seconds of the transient and of the stress recovery over it."""
    repeats = 1 if ctx.quick else 3
    rows, results = [], {}
    for label, corrected in (("10 modes", False), ("10 modes + static correction", True)):
        sf = shell_scene(ctx.scene, corrected)
        ctx.log(f"bench stress: {label}: modes, equilibrium, loading the compiled code ...")
        data = modes(sf)
        eq = statics(sf, modes=data)
        _once(sf, data, eq, ctx.t_end)
        runs = [_once(sf, data, eq, ctx.t_end) for _ in range(repeats)]
        tr = statistics.median(r["transient"] for r in runs)
        sr = statistics.median(r["stress"] for r in runs)
        last = runs[-1]
        share = sr / tr
        results[label] = dict(last, transient=tr, stress=sr, share=share)
        rows.append([label, f"{last['coordinates']}", f"{last['method']}, {last['steps']:,}",
                     f"{last['samples']:,}", f"{tr:.3f}", f"{sr:.3f}", f"{100 * share:.1f}",
                     f"{last['peak'] / 1e6:.4g} at {last['time']:.4f} s"])
    ctx.results["stress"] = results
    worst = max(r["share"] for r in results.values())
    elements = next(iter(results.values()))["elements"]
    return "\n".join([
        "## Bed stresses", "",
        f"The scene's bed as a Mindlin shell on 0.05 m elements ({elements:,} elements), "
        f"flexible, over {ctx.t_end:g} s: CPU seconds of the transient and of the stress "
        f"recovery by modal superposition over its samples (von Mises at both faces of "
        f"every element at every sample, the peaks, the peak map), median of {repeats}, "
        f"once the compiled code is loaded. Aim: the recovery under {100 * AIM:g} % of the "
        f"transient; {'met' if worst < AIM else 'NOT met'} (at most {100 * worst:.1f} %).", "",
        md_table(["bed", "coordinates", "integrator, steps", "samples", "transient [s]",
                  "stresses [s]", "share [%]", "peak von Mises [MPa]"], rows, "lrlrrrrl"),
        ""])

"""Report section: the cost of a shock verdict.

The worked example of ``docs/shock-verdict.md`` (``flexbed/scenes/skid.toml``:
a pump skid on four shock mounts, 12 mounts in all, a 30 g / 11 ms half-sine
in z and 20 g in y, 0.25 s sampled every 0.1 ms), qualified as
:func:`flexbed.qualify` does: the static equilibrium, the transient, and the
verdict (every mount's signed extremes, every body's and point's peak, the
clearance). CPU seconds of each, once the compiled code is loaded (a first
run, not counted, loads it), median of a few repeats. The aim: under 2 s
for the whole verdict. The scene's own ``[solver]`` (the ``auto``
integrator) is used, whatever the report's ``--t-end``. And the cost of
its bump stops: the same run without them (the contacts located after
every step, against chunks of steps between Python's checks).
"""

from __future__ import annotations

import statistics
import time
from importlib import resources

import numpy as np

from flexbed.analyses.verdict import judge
from flexbed.api.equilibrium import statics
from flexbed.api.qualification import static_mounts
from flexbed.api.simulation import simulate
from flexbed.bench.context import BenchContext
from flexbed.bench.markdown import md_table
from flexbed.files.scene import load_scene, parse_scene

__all__ = ["section_verdict", "AIM", "skid_scene"]

#: the whole verdict's CPU time should stay below this [s]
AIM = 2.0


def skid_scene():
    """The worked example's scene (installed with flexbed)."""
    return load_scene(resources.files("flexbed") / "scenes" / "skid.toml")


def without_stops(scene):
    """The scene with its ``bump_stop`` lines left out."""
    text = "\n".join(line for line in scene.text.splitlines()
                     if not line.startswith("bump_stop"))
    return parse_scene(text, scene.source)


def _once(scene) -> dict:
    """CPU seconds of the three parts of one verdict, and what ran."""
    c0 = time.process_time()
    eq = statics(scene)
    dx, f = static_mounts(eq)
    c1 = time.process_time()
    run = simulate(scene, equilibrium=eq)
    c2 = time.process_time()
    verdict = judge(run._run(), scene.limits, dx, f)
    c3 = time.process_time()
    st = run.solver
    return dict(statics=c1 - c0, transient=c2 - c1 - float(st.get("load_time", 0.0)),
                verdict=c3 - c2, method=str(st["method"]), steps=int(st["steps"]),
                rhs=int(st["rhs_evaluations"]), samples=run.t.size, passed=verdict.passed,
                contacts=int(np.size(run.contents.datasets.get("contacts/time", []))))


def section_verdict(ctx: BenchContext) -> str:
    """The worked example's verdict: CPU seconds of statics, transient and
    verdict, and the transient without the bump stops."""
    scene = skid_scene()
    free = without_stops(scene)
    ctx.log("bench verdict: the skid's verdict, loading the compiled code ...")
    _once(scene)
    _once(free)
    repeats = 1 if ctx.quick else 3
    runs = [_once(scene) for _ in range(repeats)]
    bare = [_once(free) for _ in range(repeats)]
    keys = ("statics", "transient", "verdict")
    med = {k: statistics.median(r[k] for r in runs) for k in keys}
    med_free = {k: statistics.median(r[k] for r in bare) for k in keys}
    total = sum(med.values())
    last, last_free = runs[-1], bare[-1]
    ctx.results["verdict"] = dict(med, total=total, without_stops=med_free["transient"],
                                  **{k: last[k] for k in ("method", "steps", "samples", "passed",
                                                          "contacts")})
    rows = [["static equilibrium", f"{med['statics']:.3f}"],
            [f"transient ({last['method']}, {last['steps']:,} steps, {last['rhs']:,} "
             f"right-hand sides, {last['contacts']} contact events, {last['samples']:,} "
             f"samples)", f"{med['transient']:.3f}"],
            ["verdict (extremes, points, clearance)", f"{med['verdict']:.3f}"],
            ["**total**", f"**{total:.3f}**"],
            [f"the transient without the bump stops ({last_free['method']}, "
             f"{last_free['steps']:,} steps, {last_free['rhs']:,} right-hand sides)",
             f"{med_free['transient']:.3f}"]]
    return "\n".join([
        "## The shock verdict", "",
        f"The worked example of docs/shock-verdict.md (flexbed/scenes/skid.toml: 4 bodies, "
        f"12 mounts, 4 bump stops, a 30 g / 11 ms half-sine in z and 20 g in y, 0.25 s), "
        f"qualified as `flexbed qualify` does: CPU seconds once the compiled code is loaded, "
        f"median of {repeats}. Aim: under {AIM:g} s; "
        f"{'met' if total < AIM else 'NOT met'} ({total:.3f} s); verdict "
        f"{'PASS' if last['passed'] else 'FAIL'}. The last row: the same transient without "
        f"the stops (no contact to locate, the steps taken in chunks).", "",
        md_table(["part", "CPU [s]"], rows, "lr"), ""])

"""Report section: the cost of a shock verdict.

The worked example of ``docs/shock-verdict.md`` (``flexbed/scenes/skid.toml``:
a pump skid on four shock mounts, 12 mounts in all, a 30 g / 11 ms half-sine
in z and 20 g in y, 0.25 s sampled every 0.1 ms), qualified as
:func:`flexbed.qualify` does: the static equilibrium, the transient, and the
verdict (every mount's signed extremes, every body's and point's peak, the
clearance). CPU seconds of each, once the compiled code is loaded (a first
run, not counted, loads it), median of a few repeats. The aim: under 2 s
for the whole verdict. The scene's own ``[solver]`` (the ``auto``
integrator) is used, whatever the report's ``--t-end``.
"""

from __future__ import annotations

import statistics
import time
from importlib import resources

from flexbed.analyses.verdict import judge
from flexbed.api.equilibrium import statics
from flexbed.api.qualification import static_mounts
from flexbed.api.simulation import simulate
from flexbed.bench.context import BenchContext
from flexbed.bench.markdown import md_table
from flexbed.files.scene import load_scene

__all__ = ["section_verdict", "AIM", "skid_scene"]

#: the whole verdict's CPU time should stay below this [s]
AIM = 2.0


def skid_scene():
    """The worked example's scene (installed with flexbed)."""
    return load_scene(resources.files("flexbed") / "scenes" / "skid.toml")


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
                samples=run.t.size, passed=verdict.passed)


def section_verdict(ctx: BenchContext) -> str:
    """The worked example's verdict: CPU seconds of statics, transient and verdict."""
    scene = skid_scene()
    ctx.log("bench verdict: the skid's verdict, loading the compiled code ...")
    _once(scene)
    repeats = 1 if ctx.quick else 3
    runs = [_once(scene) for _ in range(repeats)]
    med = {k: statistics.median(r[k] for r in runs) for k in ("statics", "transient", "verdict")}
    total = sum(med.values())
    last = runs[-1]
    ctx.results["verdict"] = dict(med, total=total, **{k: last[k] for k in
                                                       ("method", "steps", "samples", "passed")})
    rows = [["static equilibrium", f"{med['statics']:.3f}"],
            [f"transient ({last['method']}, {last['steps']:,} steps, {last['samples']:,} "
             f"samples)", f"{med['transient']:.3f}"],
            ["verdict (extremes, points, clearance)", f"{med['verdict']:.3f}"],
            ["**total**", f"**{total:.3f}**"]]
    return "\n".join([
        "## The shock verdict", "",
        f"The worked example of docs/shock-verdict.md (flexbed/scenes/skid.toml: 4 bodies, "
        f"12 mounts, a 30 g / 11 ms half-sine in z and 20 g in y, 0.25 s), qualified as "
        f"`flexbed qualify` does: CPU seconds once the compiled code is loaded, median of "
        f"{repeats}. Aim: under {AIM:g} s; "
        f"{'met' if total < AIM else 'NOT met'} ({total:.3f} s); verdict "
        f"{'PASS' if last['passed'] else 'FAIL'}.", "",
        md_table(["part", "CPU [s]"], rows, "lr"), ""])

"""Report section: the cost of long load curves.

A load of curve data is a cubic spline with its two exact integrals
(:mod:`flexbed.dynamics.piecewise`), built when the scene is compiled and
evaluated by bisection in the compiled kernel: the cost of a curve of n
samples should be O(n) to build and O(log n) per evaluation, so that a
curve of 1e6 samples costs seconds, not minutes. Measured on the scene's
bodies and mounts with a rigid bed and a free base carrying the curve
(a 5 Hz sine, 1e5 N, over 1 s), for 0.05 s of motion; and the cost of
reading the same curve from a two-column CSV file (the scene reader's
``file = "…"``).
"""

from __future__ import annotations

import statistics
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from flexbed.bench.context import BenchContext
from flexbed.bench.markdown import md_table
from flexbed.dynamics.integrate import Settings, integrate
from flexbed.dynamics.scene import Base, Load
from flexbed.dynamics.time_functions import Curve
from flexbed.dynamics.system import System
from flexbed.files.drives import ShapeReader

__all__ = ["section_inputs", "SAMPLES", "QUICK_SAMPLES", "T_END"]

SAMPLES = (10_000, 100_000, 1_000_000)
QUICK_SAMPLES = (10_000, 100_000)
#: [s] of motion simulated with each curve
T_END = 0.05


def _scene(ctx: BenchContext, n: int):
    """The scene (rigid bed) with a free base carrying a curve of n samples."""
    t = np.linspace(0.0, 1.0, n)
    load = Load(2, Curve(t, 1e5 * np.sin(2 * np.pi * 5.0 * t)))
    sc = ctx.scene.scene
    return replace(sc, base=Base(motion="free", loads=(load,), support="static"))


def _read_csv(scene, repeats: int) -> float:
    """Median CPU seconds to read the scene's load curve back from a CSV
    file written with every digit (``repr``) and a header line."""
    curve = scene.base.loads[0].shape
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "load.csv"
        path.write_text("time,value\n" + "".join(
            f"{a!r},{b!r}\n" for a, b in zip(curve.time.tolist(), curve.value.tolist())))
        cpu = []
        for _ in range(repeats):
            c0 = time.process_time()
            times, _values = ShapeReader("bench.toml", Path(folder)).csv_file("load", path.name)
            cpu.append(time.process_time() - c0)
        if len(times) != curve.time.size:
            raise AssertionError("the CSV read back has another length")
    return statistics.median(cpu)


def section_inputs(ctx: BenchContext) -> str:
    """Compile and simulate with load curves of growing length: CPU seconds."""
    rows, res = [], {}
    repeats = 1 if ctx.quick else 3
    for n in (QUICK_SAMPLES if ctx.quick else SAMPLES):
        ctx.log(f"bench inputs: a curve of {n} samples ...")
        scene = _scene(ctx, n)
        builds, runs = [], []
        for _ in range(repeats):
            c0 = time.process_time()
            system = System(scene)
            c1 = time.process_time()
            run = integrate(system, system.initial_state(),
                            Settings("dop853", t_end=T_END, output_dt=1e-3, stiff_steps=0))
            c2 = time.process_time()
            builds.append(c1 - c0)
            runs.append(c2 - c1 - run.stats.load_time)
        res[n] = dict(build=statistics.median(builds), run=statistics.median(runs),
                      steps=run.stats.steps, complete=run.complete,
                      read=_read_csv(scene, repeats))
        rows.append([f"{n:,}", f"{res[n]['read']:.3f}", f"{res[n]['build']:.3f}",
                     f"{res[n]['run']:.3f}",
                     f"{run.stats.steps:,}", "yes" if run.complete else "no"])
    ctx.results["inputs"] = res
    return "\n".join([
        "## Long load curves", "",
        f"The scene's bodies and mounts, its bed rigid, a free base carrying a load curve "
        f"of n samples (a 5 Hz sine over 1 s), {T_END:g} s of motion with dop853: CPU "
        f"seconds to read the curve from a CSV file (time,value with every digit), to "
        f"compile the system (the spline and its two exact integrals) and to "
        f"integrate (compiled code loaded beforehand), median of {repeats}.", "",
        md_table(["samples", "read CSV [s CPU]", "compile [s CPU]", "integrate [s CPU]",
                  "steps", "complete"], rows, "rrrrrl"), ""])

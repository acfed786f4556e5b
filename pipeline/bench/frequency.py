"""Report section: the cost of the frequency-domain analyses (``flexbed
modal``, ``flexbed frf``) on the scene with a rigid bed and with a 6-mode
flexible bed. A ``section(ctx) -> str`` of :mod:`flexbed.bench.report`."""

from __future__ import annotations

import statistics
import time
from dataclasses import replace

import numpy as np

from flexbed.analyses.frf import frequency_response
from flexbed.analyses.modal import mounted
from flexbed.bench.context import BenchContext
from flexbed.bench.markdown import md_table
from flexbed.files.modes import read_modes_file
from flexbed.stages.simulation import equilibrium
from flexbed.stages.system import compile_scene

__all__ = ["section_frequency", "FRF_FREQUENCIES", "FLEX_MODES"]

#: frequencies of the timed FRF, log-spaced on the default band
FRF_FREQUENCIES = 2000
#: modes of the flexible bed
FLEX_MODES = 6


def _case(ctx: BenchContext, flexible: bool):
    sf = ctx.scene
    data = None
    if flexible:
        sf = replace(sf, bed=replace(sf.bed, model="flexible", modes=FLEX_MODES))
        data = read_modes_file(ctx.modes.ensure(FLEX_MODES))
    system = compile_scene(sf, modes=data)
    return sf, system, data, equilibrium(sf, system).y


def section_frequency(ctx: BenchContext) -> str:
    """CPU time of the modes (linearisation + eigen-solution) and of a
    2,000-frequency FRF (every point, mount force and the base force)."""
    repeats = 3 if ctx.quick else 7
    rows, res = [], {}
    for label, flexible in (("rigid bed", False), (f"flexible bed, {FLEX_MODES} modes", True)):
        ctx.log(f"bench frequency: {label} ...")
        sf, system, data, y_eq = _case(ctx, flexible)
        modal_t, frf_t, frf_all = [], [], []
        for _ in range(repeats):
            mt = mounted(sf, system, y_eq=y_eq, bed_modes=data)
            modal_t.append(mt.solve_time)
        lo, hi = 0.25 * float(mt.modes.frequency.min()), 2.0 * float(mt.modes.frequency.max())
        grid = np.geomspace(lo, hi, FRF_FREQUENCIES)
        for _ in range(repeats):
            t0 = time.process_time()
            r = frequency_response(sf, mt, frequencies=grid)
            frf_all.append(time.process_time() - t0)
            frf_t.append(r.solve_time)
        t0 = time.process_time()
        adaptive = frequency_response(sf, mt, band=(lo, hi))
        adaptive_t = time.process_time() - t0
        res[label] = dict(modal=statistics.median(modal_t), frf=statistics.median(frf_t),
                          frf_with_setup=statistics.median(frf_all),
                          coordinates=mt.ms.n, outputs=len(r.names),
                          adaptive=adaptive.solve_time, adaptive_frequencies=adaptive.evaluations,
                          adaptive_wall=adaptive_t)
        rows.append([label, str(mt.ms.n), f"{res[label]['modal']:.4f}", str(len(r.names)),
                     f"{res[label]['frf']:.4f} ({res[label]['frf_with_setup']:.4f})",
                     f"{adaptive.solve_time:.3f} ({adaptive.evaluations})"])
    ctx.results["frequency"] = res
    return "\n".join([
        "## The mounted system in the frequency domain", "",
        f"CPU seconds (median of {repeats}) of `flexbed modal`'s solve (the linearisation "
        "about the static equilibrium, the mount and mass matrices, the undamped and "
        f"complex eigen-solutions and the energy tables) and of an FRF at {FRF_FREQUENCIES} "
        "log-spaced frequencies from a base acceleration to every output (the scene's "
        "points, every mount axis's force, the total force on the base; in brackets with "
        "the outputs' set-up: the points' Jacobians through the point machinery); last "
        "column: the "
        "resonance-resolving grid of `flexbed frf` (400 base frequencies, each peak of each "
        "output refined to 0.1 % of its half-power bandwidth), with the frequencies it solved.",
        "",
        md_table(["case", "coordinates", "modal solve [s]", "outputs",
                  f"FRF, {FRF_FREQUENCIES} frequencies [s]", "adaptive FRF [s] (frequencies)"],
                 rows, align="lrrrrr"),
        ""])

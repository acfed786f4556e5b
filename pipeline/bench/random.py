"""Report section: the cost of a random response (``flexbed random``) of
the reference scene with a 6-mode flexible bed, 3 input axes, 2,000
frequencies and every output (points' acceleration, velocity and
displacement, mount deflections and forces, the base force). A
``section(ctx) -> str`` of :mod:`flexbed.bench.report`."""

from __future__ import annotations

import statistics

import numpy as np

from flexbed.analyses.modal import mounted
from flexbed.files.psd import psd_from_tables
from flexbed.analyses.random import random_response
from flexbed.bench.context import BenchContext
from flexbed.bench.frequency import FLEX_MODES, _case
from flexbed.bench.markdown import md_table

__all__ = ["section_random", "RANDOM_FREQUENCIES", "AIM", "PROFILE"]

#: frequencies of the timed response, log-spaced on the profile's band
RANDOM_FREQUENCIES = 2000
#: CPU seconds the response should stay below
AIM = 0.1
#: the input [Hz, g²/Hz] on each axis (MIL-STD-810-style: a plateau with
#: slopes either side), Y and X at half of Z
PROFILE = [[5.0, 0.002], [10.0, 0.01], [40.0, 0.01], [100.0, 0.002], [500.0, 0.0002]]


def section_random(ctx: BenchContext) -> str:
    """CPU time of the random response (transfer functions of 3 axes,
    response PSDs with the cross-spectra, mean squares with their error,
    Miles), median of a few repeats, and the RMS's convergence with the
    grid."""
    repeats = 3 if ctx.quick else 7
    ctx.log(f"bench random: flexible bed, {FLEX_MODES} modes ...")
    sf, system, data, y_eq = _case(ctx, True)
    mt = mounted(sf, system, y_eq=y_eq, bed_modes=data)
    half = [[f, w / 2] for f, w in PROFILE]
    psd = psd_from_tables({"x": half, "y": half, "z": PROFILE}, {"xz": 0.3}, "bench profile")
    grid = np.geomspace(PROFILE[0][0], PROFILE[-1][0], RANDOM_FREQUENCIES)
    times = []
    for _ in range(repeats):
        r = random_response(sf, mt, psd, frequencies=grid)
        times.append(r.solve_time)
    cpu = statistics.median(times)
    adaptive = random_response(sf, mt, psd, n=RANDOM_FREQUENCIES)
    fine = random_response(sf, mt, psd, n=10 * RANDOM_FREQUENCIES)
    err_true = np.abs(adaptive.rms - fine.rms) / np.maximum(fine.rms, 1e-300)
    err_stated = adaptive.rms_error / np.maximum(adaptive.rms, 1e-300)
    ctx.results["random"] = dict(cpu=cpu, outputs=len(r.names), coordinates=mt.ms.n,
                                 frequencies=grid.size,
                                 adaptive_frequencies=adaptive.frequency.size,
                                 adaptive_cpu=adaptive.solve_time,
                                 error_max=float(err_true.max()),
                                 stated_max=float(err_stated.max()))
    rows = [[f"{grid.size:,} log-spaced frequencies", f"{cpu:.4f}", "–", "–"],
            [f"resonance grid ({adaptive.frequency.size:,} frequencies: {RANDOM_FREQUENCIES:,} "
             f"log-spaced + the modes')", f"{adaptive.solve_time:.4f}", f"{err_true.max():.1e}",
             f"{err_stated.max():.1e}"]]
    return "\n".join([
        "## Random vibration", "",
        f"`flexbed random` on the reference scene with a {FLEX_MODES}-mode flexible bed "
        f"({mt.ms.n} coordinates): base acceleration PSDs on X, Y, Z (a MIL-STD-810-style "
        f"plateau, 5–500 Hz, coherence 0.3 between X and Z), {len(r.names)} outputs (every "
        f"point's acceleration, velocity and displacement, every mount's deflections and "
        f"forces, the base force). CPU seconds of the response (3 transfer functions, the "
        f"PSDs with cross-spectra, RMS with its error, Miles), median of {repeats}. "
        f"Aim: under {AIM * 1e3:g} ms; {'met' if cpu < AIM else 'NOT met'} "
        f"({cpu * 1e3:.1f} ms). Error: the largest relative RMS error of any output against "
        f"a grid of {10 * RANDOM_FREQUENCIES:,} log-spaced frequencies + the modes', and the "
        f"largest the response states (Simpson against the trapezoid).", "",
        md_table(["grid", "CPU [s]", "RMS error (max)", "stated (max)"], rows, "lrrr"), ""])

"""``flexbed synthesise SPECTRUM --axis z``: a base acceleration whose shock
response spectrum matches the design spectrum's axis within a tolerance at
every check frequency of the band (wavelets iterated,
:mod:`flexbed.dynamics.spectrum_synthesis`), with zero end velocity and
displacement; seeded, repeatable.

Writes ``PREFIX.csv`` (time [s], acceleration [m/s²]: curve data for
``[[base.drive]] shape = "curve", file = ...`` in any scene),
``PREFIX-srs.csv`` (frequency, target, achieved, error) and
``PREFIX-srs.png`` (PREFIX default ``<spectrum stem>-<axis>``). Exit 1 when
no attempt meets the tolerance (nothing written).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from flexbed.commands.arguments import number, file_name

__all__ = ["add_args", "run", "MAX_SAMPLES"]

#: the longest record written (samples): 1/f_lo of residual at 20 samples per
#: period of f_hi
MAX_SAMPLES = 5_000_000


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("A base acceleration matching a design spectrum (wavelets "
                          "iterated), written as curve data usable as a drive.")
    parser.add_argument("spectrum", metavar="SPECTRUM", help="design spectrum file (TOML)")
    parser.add_argument("--axis", default="z", help="the spectrum's axis: x, y or z (default z)")
    parser.add_argument("--band", type=number, nargs=2, default=None, metavar=("LO", "HI"),
                        help="frequencies to match [Hz] (default: the axis's first and last "
                             "breakpoints)")
    parser.add_argument("--tolerance", type=number, default=1.5, metavar="DB",
                        help="match required at every check frequency [dB] (default 1.5)")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("-o", "--output", type=file_name, default=None, metavar="PREFIX",
                        help="prefix of the files written (default: <spectrum stem>-<axis>)")
    parser.add_argument("--no-plots", action="store_true", help="write no PNG")


def check_request(spectrum, axis: str, band, tolerance: float):
    """The axis's DesignSpectrum and the band, or InputError (one line)."""
    import math

    from flexbed.errors import InputError
    from flexbed.files.spectrum import AXES

    name = spectrum.source.name
    if axis not in AXES:
        raise InputError(f"--axis {axis!r} must be one of x, y, z")
    k = AXES.index(axis)
    if k not in spectrum.axes:
        raise InputError(f"{name}: no spectrum for axis {axis} (it gives "
                         f"{', '.join(AXES[i] for i in spectrum.axes)})")
    spec = spectrum.axes[k]
    lo, hi = (float(spec.frequency[0]), float(spec.frequency[-1])) if band is None else band
    if not (math.isfinite(lo) and math.isfinite(hi) and 0.0 < lo < hi):
        raise InputError(f"--band {lo!r} {hi!r} Hz must satisfy 0 < LO < HI")
    if not (math.isfinite(tolerance) and 0.1 <= tolerance <= 6.0):
        raise InputError(f"--tolerance {tolerance!r} dB must be in [0.1, 6]")
    samples = 20.0 * hi * (0.1 + 1.0 / lo) + 11.0 * hi / lo
    if samples > MAX_SAMPLES:
        raise InputError(f"--band {lo!r} {hi!r} Hz needs about {samples:.3g} "
                         f"samples (over {MAX_SAMPLES:,}): narrow the band")
    return spec, lo, hi


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from flexbed.dynamics.pulses import STANDARD_GRAVITY
    from flexbed.dynamics.spectrum_synthesis import synthesise
    from flexbed.errors import InputError, NumericalError
    from flexbed.files.destination import check_destination, write_text
    from flexbed.files.spectrum import read_spectrum
    from flexbed.files.table_reader import MAX_SEED

    if not 0 <= args.seed <= MAX_SEED:
        raise InputError(f"--seed {args.seed}: from 0 to {MAX_SEED:,}")
    spectrum = read_spectrum(args.spectrum)
    spec, lo, hi = check_request(spectrum, args.axis, args.band, args.tolerance)
    prefix = args.output or f"{spectrum.source.stem}-{args.axis}"
    out = {"csv": ".csv", "srs": "-srs.csv"} | ({} if args.no_plots else {"png": "-srs.png"})
    out = {k: check_destination(Path(prefix + v)) for k, v in out.items()}
    syn = synthesise(spec, lo, hi, tolerance_db=args.tolerance,
                     goal_db=min(1.0, 2.0 * args.tolerance / 3.0), seed=args.seed)
    worst = int(np.argmax(np.abs(syn.error_db)))
    if not syn.converged:
        raise NumericalError(f"{spectrum.source.name}: axis {args.axis}: no synthesis within "
                             f"±{args.tolerance:g} dB: {syn.error_db[worst]:+.2f} dB at "
                             f"{syn.frequency[worst]:.4g} Hz (try another --seed or a wider "
                             f"--tolerance)")
    g = STANDARD_GRAVITY
    print(f"Synthesised '{spectrum.name}' axis {args.axis}, {lo:g}-{hi:g} Hz, damping "
          f"{syn.damping:g}, seed {args.seed}: {syn.frequency.size} wavelets, "
          f"{syn.time.size} samples every {1e6 * syn.dt:.2f} us ({1e3 * syn.time[-1]:.1f} ms)")
    print(f"worst match {syn.error_db[worst]:+.2f} dB at {syn.frequency[worst]:.4g} Hz "
          f"(tolerance ±{args.tolerance:g} dB); peak {np.abs(syn.acceleration).max() / g:.2f} g; "
          f"end velocity {syn.end_velocity:.2e} m/s, end displacement "
          f"{syn.end_displacement:.2e} m")
    rows = "\n".join(f"{t:.9g},{a:.12g}" for t, a in zip(syn.time, syn.acceleration))
    write_text(out["csv"], "time_s,acceleration_m_s2\n" + rows + "\n")
    write_text(out["srs"], "frequency_Hz,target_m_s2,achieved_m_s2,target_g,achieved_g,"
                           "error_dB\n" + "\n".join(
                               f"{f:.8g},{t:.8g},{a:.8g},{t / g:.8g},{a / g:.8g},{e:.4f}"
                               for f, t, a, e in zip(syn.frequency, syn.target, syn.achieved,
                                                     syn.error_db)) + "\n")
    if "png" in out:
        from flexbed.plots.spectrum import plot_synthesis
        plot_synthesis(out["png"], f"{spectrum.name} {args.axis}", syn, g)
    print("wrote " + ", ".join(str(p) for p in out.values()))
    return 0

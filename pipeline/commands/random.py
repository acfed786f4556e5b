"""``flexbed random [SCENE] --psd FILE``: stationary random response of the
mounted system to base acceleration PSDs (g²/Hz tables per axis, log–log
between breakpoints, optional coherences): response PSDs, RMS, 3σ and a
chosen peak factor at points (acceleration, velocity, displacement,
relative displacement), mount deflections and forces and the force on the
base, with the RMS's integration error and Miles' equation beside the
outputs one mode dominates.

Writes ``PREFIX.h5`` (``flexbed.random``), ``PREFIX-rms.csv``,
``PREFIX-psd.csv``, ``PREFIX-acceleration.png`` (the points' acceleration
PSDs with the input, g²/Hz) and ``PREFIX-deflection.png`` (the mounts'
deflection PSDs) (PREFIX default ``<scene stem>-random``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from flexbed.commands.arguments import add_scene_arg, number, file_name
from flexbed.commands.modal import load_mounted
from flexbed.commands.static import add_modes_file_arg
from flexbed.errors import InputError
from flexbed.files.destination import check_destination
from flexbed.files.scene import load_scene

__all__ = ["add_args", "run"]

#: the most mount deflections drawn (the largest RMS first; all are in the CSV)
PLOT_LINES = 12


def _kind(name: str) -> str:
    """"deflection", "force" (a mount's), "base", or a point's "a", "v", "d"."""
    last = name.rsplit(" ", 1)[-1]
    if name.startswith("base F"):
        return "base"
    if last in ("d1", "d2", "d3"):
        return "deflection"
    if last in ("f1", "f2", "f3"):
        return "force"
    return last[0]


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("Random vibration: response PSDs, RMS, 3 sigma and peaks of points, "
                          "mount deflections and forces and the base force under base "
                          "acceleration PSDs given as g^2/Hz tables.")
    add_scene_arg(parser)
    parser.add_argument("--psd", required=True, metavar="FILE",
                        help="base acceleration PSD: TOML ([x]/[y]/[z] table = [[Hz, g^2/Hz], "
                             "...], optional [coherence]) or CSV (frequency_Hz,x,y,z)")
    parser.add_argument("-o", "--output", type=file_name, default=None, metavar="PREFIX",
                        help="prefix of the files written (default: <scene stem>-random)")
    parser.add_argument("--point", action="append", default=[], metavar="NAME=BODY:x,y,z",
                        help="a point of interest (repeatable; default: the scene's [[point]] "
                             "tables, else every body's centre of mass)")
    parser.add_argument("--relative-to", default=None, metavar="BODY",
                        help="the --point motions relative to this body, in its frame")
    parser.add_argument("-n", type=int, default=2000, metavar="N",
                        help="log-spaced frequencies of the base grid (default 2000); each "
                             "damped mode in the band adds its own about its resonance")
    parser.add_argument("--peak-factor", type=number, default=3.0, metavar="K",
                        help="the peak reported besides 3 sigma is K sigma (default 3)")
    parser.add_argument("--equilibrium", default=None, metavar="FILE",
                        help="equilibrium file from 'flexbed static' (default: solve it here)")
    parser.add_argument("--no-plots", action="store_true", help="write no PNG")
    add_modes_file_arg(parser)


def run(args: argparse.Namespace) -> int:
    from flexbed.analyses.frf import MAX_GRID
    from flexbed.analyses.points import parse_point
    from flexbed.files.psd import G0, load_psd
    from flexbed.analyses.random import psd_csv, random_response, rms_csv
    from flexbed.files.destination import write_text
    from flexbed.files.random import write_random

    psd = load_psd(args.psd)
    sf = load_scene(args.scene)
    if not 2 <= args.n <= MAX_GRID:
        raise InputError(f"-n {args.n}: from 2 to {MAX_GRID:,} frequencies")
    if not (np.isfinite(args.peak_factor) and args.peak_factor > 0.0):
        raise InputError(f"--peak-factor {args.peak_factor:g}: must be finite and > 0")
    names = [b.name for b in sf.scene.bodies]
    for option, body in [("--point", parse_point(p).body) for p in args.point] + \
            [("--relative-to", args.relative_to)] * (args.relative_to is not None):
        if body not in names:
            raise InputError(f"{option}: body {body!r} is not a body of {sf.source.name} "
                             f"(bodies: {', '.join(names)})")
    points = [(parse_point(p), args.relative_to) for p in args.point] or None
    prefix = args.output or f"{sf.output_name}-random"
    out = {"h5": check_destination(Path(prefix + ".h5")),
           "rms": check_destination(Path(prefix + "-rms.csv")),
           "psd": check_destination(Path(prefix + "-psd.csv"))}
    if not args.no_plots:
        out["acc"] = check_destination(Path(prefix + "-acceleration.png"))
        out["defl"] = check_destination(Path(prefix + "-deflection.png"))
    mt = load_mounted(args, sf)
    r = random_response(sf, mt, psd, points=points, n=args.n, peak_factor=args.peak_factor)
    grms = ", ".join(f"{'XYZ'[d]} {r.input_rms[d]:.4g} g" for d in psd.axes)
    print(f"random response of '{sf.scene.name}' to {psd.source} (input RMS {grms}): "
          f"{r.frequency.size} frequencies on {r.frequency[0]:.4g}–{r.frequency[-1]:.4g} Hz, "
          f"{r.resonances.size} modes in the band")
    k = r.peak_factor
    extra = k != 3.0                                  # the chosen peak, when not 3 sigma
    print(f"  {'output':<22} {'RMS':>11} {'3 sigma':>11} " +
          (f"{f'{k:g} sigma':>11} " if extra else "") + f" {'error':>8}  Miles")
    acc = r.acceleration
    for j, (name, unit) in enumerate(zip(r.names, r.units)):
        kind = _kind(name)
        if not (kind == "deflection" or name.startswith("base F")
                or (kind == "a" and "@" not in name) or (kind == "d" and "@" in name)):
            continue
        s = 1.0 / G0 if acc[j] else (1e3 if unit == "m" else 1.0)
        u = "g" if acc[j] else ("mm" if unit == "m" else unit)
        miles = f"{r.miles.rms[j] * s:.4g} {u} ({r.miles.frequency[j]:.3g} Hz)" \
            if np.isfinite(r.miles.rms[j]) else "-"
        print(f"  {name:<22} {r.rms[j] * s:>9.4g} {u:<2}{3 * r.rms[j] * s:>9.4g} {u:<2}" +
              (f"{r.peak[j] * s:>9.4g} {u:<2}" if extra else "") +
              f" {r.rms_error[j] / max(r.rms[j], 1e-300):>8.1e}  {miles}")
    print(f"solve time: {r.solve_time:.4f} s CPU (linearisation and modes: "
          f"{mt.solve_time:.4f} s); error: the RMS's integration error, relative")
    write_random(out["h5"], sf, r)
    write_text(out["rms"], rms_csv(r))
    write_text(out["psd"], psd_csv(r))
    if "acc" in out:
        from flexbed.plots.random import plot_psd
        cols = [j for j in np.flatnonzero(acc) if "@" not in r.names[j]
                and r.rms[j] > 1e-3 * r.rms[acc].max()]
        plot_psd(out["acc"], f"{sf.scene.name}: acceleration PSDs under {psd.source}",
                 r.frequency, r.psd[:, cols] / G0**2, [r.names[j] for j in cols], "g",
                 r.rms[cols] / G0, r.input_psd[:, psd.axes], ["XYZ"[d] for d in psd.axes],
                 r.resonances)
        dc = [j for j, nm in enumerate(r.names) if _kind(nm) == "deflection"]
        dc = sorted(dc, key=lambda j: -r.rms[j])[:PLOT_LINES]
        plot_psd(out["defl"], f"{sf.scene.name}: mount deflection PSDs under {psd.source}",
                 r.frequency, r.psd[:, dc] * 1e6, [r.names[j] for j in dc], "mm",
                 r.rms[dc] * 1e3, resonances=r.resonances)
    print("wrote " + ", ".join(str(p) for p in out.values()))
    return 0

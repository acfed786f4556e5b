"""``flexbed srs RESULTS.h5 --point NAME=BODY:x,y,z [...] [--q Q] [--fmin F]
[--fmax F] [--per-octave N] [--csv DIR] [--hdf5 FILE] [--plot DIR]
[--modes-file FILE]``: shock response spectra of points' absolute
accelerations (Smallwood's ramp-invariant filter, the base's jumps taken
exactly), and for a driven base the input's spectrum beside them
(:mod:`flexbed.analyses.shock`); tables in m/s² and g; plots of the
maximax, positive and negative spectra in g and of the pseudo-velocity on
tripartite paper (:mod:`flexbed.plots.srs`); a warning when the record is
too short for the lowest frequency.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from flexbed.commands.arguments import number, output_folder, unused_modes_file
from flexbed.analyses.points import Run, parse_point
from flexbed.analyses.shock import G, SCHEMA, VERSION, spectra, spectra_datasets, \
    spectrum_csv, summary
from flexbed.errors import InputError
from flexbed.files.destination import check_destination, write_text


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("Shock response spectra (maximax absolute acceleration, positive and "
                          "negative, and pseudo-velocity) of points' absolute accelerations "
                          "along X, Y, Z, from a results file; a driven base's input beside "
                          "them.")
    parser.add_argument("results", help="results file written by simulate, compare or run")
    parser.add_argument("--point", action="append", default=[], metavar="NAME=BODY:x,y,z",
                        help="a point in a body's frame [m] (repeatable); default: the "
                             "scene's [[point]] tables")
    parser.add_argument("--q", type=number, default=10.0,
                        help="quality factor Q = 1/(2 zeta) of the oscillators (default 10)")
    parser.add_argument("--fmin", type=number, default=1.0,
                        help="lowest natural frequency [Hz] (default 1)")
    parser.add_argument("--fmax", type=number, default=None,
                        help="highest natural frequency [Hz] (default a tenth of the sampling "
                             "rate; at most a quarter)")
    parser.add_argument("--per-octave", type=int, default=12,
                        help="frequencies per octave, logarithmic grid (default 12)")
    parser.add_argument("--csv", default=None, metavar="DIR",
                        help="write one CSV file per point (srs-NAME.csv, srs-input.csv)")
    parser.add_argument("--hdf5", default=None, metavar="FILE",
                        help="write every spectrum into one HDF5 file (schema flexbed.srs)")
    parser.add_argument("--plot", default=None, metavar="DIR",
                        help="write PNGs per point: the maximax, positive and negative spectra "
                             "in g (srs-NAME.png) and the pseudo-velocity on tripartite paper "
                             "(srs-NAME-pv.png)")
    parser.add_argument("--modes-file", default=None, metavar="FILE",
                        help="the flexible bed's modes file (default: found beside the "
                             "results file, else where the run recorded it)")


def _file_name(name: str) -> str:
    return name.replace(" ", "_").replace("/", "_")


def run(args: argparse.Namespace) -> int:
    output_folder("--csv", args.csv)
    output_folder("--plot", args.plot)
    if args.hdf5:
        check_destination(Path(args.hdf5))
    points = [parse_point(text) for text in args.point]
    r = Run(args.results, modes_file=args.modes_file)
    unused_modes_file(r, args.modes_file)
    if r.incomplete:
        print(f"note: {r.path} holds an incomplete run ({r.incomplete})", file=sys.stderr)
    if not points:
        points = list(r.scene_points)
    if not points:
        raise InputError("nothing to report: give --point NAME=BODY:x,y,z (the scene has no "
                         "[[point]] tables)")
    names = [p.name for p in points]
    for i, n in enumerate(names):
        if n in names[:i]:
            raise InputError(f"point name {n!r} is used twice")
        if n == "input" and r.base_motion == "driven":
            raise InputError("point name 'input' is the driven base's own spectrum: choose "
                             "another")
    s = spectra(r, points, q=args.q, fmin=args.fmin, fmax=args.fmax,
                per_octave=args.per_octave)
    for w in s.warnings:
        print(f"flexbed srs: warning: {w}", file=sys.stderr)
    print(summary(s))
    every = list(s.points) + ([s.input] if s.input is not None else [])
    if args.csv:
        out = Path(args.csv)
        for p in every:
            f = write_text(out / f"srs-{_file_name(p.name)}.csv", spectrum_csv(s, p))
            print(f"wrote {f}")
    if args.hdf5:
        from flexbed.files.store import write_file
        ds, attrs = spectra_datasets(s, str(r.path))
        f = write_file(Path(args.hdf5), schema=SCHEMA, version=VERSION, datasets=ds, attrs=attrs)
        print(f"wrote {f}")
    if args.plot:
        for f in plot_spectra(s, Path(args.plot)):
            print(f"wrote {f}")
    return 0


def plot_spectra(s, out: Path) -> list[Path]:
    """Each point's acceleration spectra in g and its tripartite
    pseudo-velocity plot, the input's beside them; returns the paths."""
    from flexbed.plots.srs import plot_acceleration_srs, plot_tripartite  # matplotlib

    files = []
    inp = s.input
    ref = {} if inp is None else {c: inp.in_g("maximax")[:, i] for i, c in enumerate("xyz")}
    ref_pv = {} if inp is None else {c: inp.pseudo_velocity[:, i] for i, c in enumerate("xyz")}
    for p in s.points:
        name = _file_name(p.name)
        curves = {c: (p.in_g("positive")[:, i], p.in_g("negative")[:, i],
                      p.in_g("maximax")[:, i]) for i, c in enumerate("xyz")}
        files.append(plot_acceleration_srs(out / f"srs-{name}.png",
                                           f"SRS, {p.name} on {p.body}, Q = {s.q:g}",
                                           s.frequency, curves, ref, G))
        files.append(plot_tripartite(out / f"srs-{name}-pv.png",
                                     f"pseudo-velocity SRS, {p.name} on {p.body}, Q = {s.q:g}",
                                     s.frequency,
                                     {c: p.pseudo_velocity[:, i] for i, c in enumerate("xyz")},
                                     ref_pv, G))
    return files

"""``flexbed post RESULTS.h5 [--point NAME=BODY:x,y,z ...] [--relative-to BODY]
[--mounts] [--csv DIR] [--plot DIR] [--modes-file FILE]``: points of interest
and mount forces from a finished run, without running it again (paper,
section 4).

A flexible bed's modes file is found beside the results file under the name
it had when the run was made, else at the path the results file records
(relative, then absolute), each checked by the plate's input hash; a results
folder can therefore be moved or shared whole. ``--modes-file`` names it.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from flexbed.commands.arguments import output_folder, unused_modes_file
from flexbed.analyses.points import (Run, motion_csv, motion_table, mount_csv, mount_table,
                                     parse_point)
from flexbed.files.destination import write_text
from flexbed.errors import InputError


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("Motion of points of interest (absolute, or relative to a body in "
                          "its frame) and mount forces, from a results file.")
    parser.add_argument("results", help="results file written by simulate, compare or run")
    parser.add_argument("--point", action="append", default=[], metavar="NAME=BODY:x,y,z",
                        help="a point in a body's frame [m] (on the bed: the frame its "
                             "geometry is drawn in, as in the scene) (repeatable); the "
                             "scene's [[point]] tables are always included")
    parser.add_argument("--relative-to", default=None, metavar="BODY",
                        help="also give every point's motion relative to this body, in its frame")
    parser.add_argument("--mounts", action="store_true",
                        help="peak deflections and forces per mount and direction")
    parser.add_argument("--csv", default=None, metavar="DIR",
                        help="write the time series as CSV files into DIR")
    parser.add_argument("--plot", default=None, metavar="DIR",
                        help="write PNG plots of the points' displacement (and with --mounts, "
                             "of the mount forces) into DIR")
    parser.add_argument("--modes-file", default=None, metavar="FILE",
                        help="the flexible bed's modes file (default: found beside the "
                             "results file, else where the run recorded it)")


def run(args: argparse.Namespace) -> int:
    output_folder("--csv", args.csv)
    output_folder("--plot", args.plot)
    points = [parse_point(text) for text in args.point]
    r = Run(args.results, modes_file=args.modes_file)
    unused_modes_file(r, args.modes_file)
    if r.incomplete:
        print(f"note: {r.path} holds an incomplete run ({r.incomplete})", file=sys.stderr)
    points = list(r.scene_points) + points
    names = [p.name for p in points]
    for i, n in enumerate(names):
        if n in names[:i]:
            raise InputError(f"point name {n!r} is used twice")
    if args.relative_to is not None:
        r.body_index(args.relative_to, "--relative-to body")
    if not points and not args.mounts:
        raise InputError("nothing to report: give --point NAME=BODY:x,y,z or --mounts "
                         "(the scene has no [[point]] tables)")
    motions = []
    for p in points:
        motions.append(r.absolute(p))
        for ref in {p.relative_to, args.relative_to} - {None}:
            motions.append(r.relative(p, ref))
    if motions:
        print(f"points of interest, {r.path.name}, 0-{r.t[-1]:g} s "
              f"(displacement from t = 0):")
        print(motion_table(motions))
    if args.mounts:
        print(f"mounts, {r.path.name}:")
        print(mount_table(r))
    if args.csv:
        out = Path(args.csv)
        for m in motions:
            suffix = "" if m.frame == "inertial" else f"-rel-{m.frame.replace(' ', '_')}"
            f = out / f"point-{m.point.name.replace(' ', '_')}{suffix}.csv"
            write_text(f, motion_csv(r.t, m))
            print(f"wrote {f}")
        if args.mounts:
            f = out / "mounts.csv"
            write_text(f, mount_csv(r))
            print(f"wrote {f}")
    if args.plot and (motions or args.mounts):
        from flexbed.plots.runs import plot_mount_forces, plot_responses  # matplotlib
        out = Path(args.plot)
        for m in motions:
            d = 1e3 * (m.position - m.position[0])
            curves = {c: (r.t, d[:, i]) for i, c in enumerate("xyz")}
            suffix = "" if m.frame == "inertial" else f"-rel-{m.frame.replace(' ', '_')}"
            f = plot_responses(out / f"point-{m.point.name.replace(' ', '_')}{suffix}.png",
                               f"{m.point.name} on {m.point.body} ({m.frame} frame)", curves,
                               {}, "displacement from t = 0 [mm]")
            print(f"wrote {f}")
        if args.mounts and r.mount_names:
            f = plot_mount_forces(out / "mount-forces.png", f"mount forces, {r.path.name}",
                                  r.t, r.mounts["force"], r.mount_names, r.mount_body_i,
                                  r.mount_body_j)
            print(f"wrote {f}")
    return 0

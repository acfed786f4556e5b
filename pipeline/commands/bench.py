"""``flexbed bench [TARGET] [SCENE] [--quick] [-o DIR]``: the work-precision report.

Without a target: the whole report, ``DIR/benchmarks.md`` (default DIR:
``docs``) and its PNGs ``DIR/bench-*.png``, every one regenerated (see
:mod:`flexbed.bench.report`). ``--quick``: the cheaper cases, one or two
settings per integrator, fewer repeats (about a minute). A target writes a
part only, as ``DIR/benchmarks-<target>.md``:

- ``modes``: mesh density of the bed-modes stage;
- ``rigid``: the integrators on the rigid bed, and the aims;
- ``flexible``: the integrators on the flexible (2 modes, undamped) and the
  damped flexible bed (6 modes), and the aims;
- ``modelling``: modes kept, mesh density, invariants.

The report is also printed on stdout; progress goes to stderr.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from flexbed.bench.report import write_report

#: target -> (sections, integrator cases); None: the profile's
TARGETS = {
    "all": (None, None),
    "modes": (["mesh"], None),
    "rigid": (["integrators", "aims"], ("rigid",)),
    "flexible": (["integrators", "aims"], ("flexible", "damped")),
    "modelling": (["modes_count", "mesh", "invariants"], None),
}


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("Benchmarks as a work-precision report: every integrator's error "
                          "against wall time, and the error and cost of the modelling "
                          "choices, written to DIR/benchmarks.md with PNG diagrams.")
    parser.add_argument("target", nargs="?", default="all", choices=list(TARGETS),
                        help="a part of the report only (default: all)")
    parser.add_argument("scene", nargs="?", default=None,
                        help="scene file (default: the built-in reference scene)")
    parser.add_argument("--quick", action="store_true",
                        help="cheaper cases, fewer settings and repeats (about a minute)")
    parser.add_argument("-o", "--output", default="docs", metavar="DIR",
                        help="folder of the report and its PNGs (default: docs)")
    parser.add_argument("--t-end", type=float, default=None, metavar="T",
                        help="end every run at T seconds (default: the scene's; the aims "
                             "are stated for 0-3 s)")


def run(args: argparse.Namespace) -> int:
    def log(m: str) -> None:
        print(m, file=sys.stderr, flush=True)

    sections, cases = TARGETS[args.target]
    filename = "benchmarks.md" if args.target == "all" else f"benchmarks-{args.target}.md"
    words = ["flexbed bench"] + ([] if args.target == "all" else [args.target])
    words += [args.scene] if args.scene else []
    words += ["--quick"] if args.quick else []
    words += [f"--t-end {args.t_end:g}"] if args.t_end is not None else []
    report = write_report(Path(args.output), scene=args.scene, quick=args.quick,
                          sections=sections, cases=cases, t_end=args.t_end, filename=filename,
                          command=" ".join(words), log=log)
    print(report.path.read_text())
    print(f"wrote {report.path} and {len(report.figures)} PNGs in {report.elapsed:.1f} s",
          file=sys.stderr)
    return 0

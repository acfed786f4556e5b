"""``flexbed bench [modes|rigid] [SCENE] [--quick] [-o FILE]``: benchmarks,
printed as Markdown tables.

Speed is reported with the accuracy it buys.

- ``modes``: time, peak memory and frequency error of the bed-modes stage
  for 10 x 10, 40 x 40 and 100 x 100 meshes, in-process and as a whole
  command.
- ``rigid``: every integrator over a ladder of steps or tolerances on the
  scene with a rigid bed: wall time, steps, right-hand sides and the
  maximum position error against a far tighter reference; the cost of one
  right-hand-side evaluation.
- ``flexible``: the same with the bed flexible, keeping 2 and 6 modes with
  the scene's damping.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .bench_modes import benchmark_modes
from .bench_dynamics import benchmark_dynamics


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = "Benchmarks, reported as speed against error."
    parser.add_argument("target", nargs="?", default="modes", choices=["modes", "rigid", "flexible"],
                        help="what to benchmark (default: modes)")
    parser.add_argument("scene", nargs="?", default=None,
                        help="rigid: scene file (default: the built-in reference scene)")
    parser.add_argument("--quick", action="store_true", help="rigid: a shorter ladder")
    parser.add_argument("-o", "--output", default=None, metavar="FILE",
                        help="also write the table to this Markdown file")
    parser.add_argument("--repeats", type=int, default=3,
                        help="repeats of the small cases (median reported)")


def run(args: argparse.Namespace) -> int:
    log = lambda m: print(m, file=sys.stderr)  # noqa: E731
    if args.target == "modes":
        table = benchmark_modes(repeats=max(1, args.repeats), log=log)
    elif args.target == "rigid":
        table = benchmark_dynamics(args.scene, quick=args.quick, log=log)
    else:
        table = "\n".join(benchmark_dynamics(args.scene, n_modes=n, quick=args.quick, log=log)
                          for n in (2, 6))
    print(table)
    if args.output:
        path = Path(args.output)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(table + "\n")
        print(f"wrote {path}")
    return 0

"""``flexbed bench [modes] [-o FILE]``: benchmarks, printed as tables.

Speed is reported with the accuracy it buys. ``modes``: time, peak memory
and frequency error of the bed-modes stage for 10 x 10, 40 x 40 and
100 x 100 meshes, in-process and as a whole command.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from .bench_modes import benchmark_modes


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = "Benchmarks, reported as speed against error."
    parser.add_argument("target", nargs="?", default="modes", choices=["modes"],
                        help="what to benchmark (default: modes)")
    parser.add_argument("-o", "--output", default=None, metavar="FILE",
                        help="also write the table to this Markdown file")
    parser.add_argument("--repeats", type=int, default=3,
                        help="repeats of the small cases (median reported)")


def run(args: argparse.Namespace) -> int:
    table = benchmark_modes(repeats=max(1, args.repeats),
                            log=lambda m: print(m, file=sys.stderr))
    print(table)
    if args.output:
        path = Path(args.output)
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(table + "\n")
        print(f"wrote {path}")
    return 0

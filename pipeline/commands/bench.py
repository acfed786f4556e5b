"""``flexbed bench [TARGET] [SCENE] [--quick] [-o DIR] [--t-end T]``: the
work-precision report (``flexbed bench SCENE``: the whole report on a scene).

Without a target: the whole report, ``DIR/benchmarks.md`` and its PNGs
``DIR/bench-*.png`` (see :mod:`flexbed.bench.report`). DIR is
``./flexbed-bench`` unless given: the project's own report is regenerated
with ``-o docs``. Only the report and the PNGs of this run are written; no
other file is touched or deleted (a ``bench-*.png`` of an earlier report
that this one no longer draws is named on stderr and left alone).
``--quick``: the cheaper cases, one or two settings per integrator, fewer
repeats, and without the linear fast path's section (``flexbed bench linear
--quick`` runs it alone: compiling the linear path would double a fresh
install's first quick report, docs/first-run.md). A target writes a part
only, as
``DIR/benchmarks-<target>.md``:

- ``modes``: mesh density of the bed-modes stage;
- ``rigid``: the integrators on the rigid bed, and the aims;
- ``flexible``: the integrators on the flexible (2 modes, undamped) and the
  damped flexible bed (6 modes), and the aims;
- ``modelling``: modes kept, mesh density, invariants;
- ``linear``: the integrators on every case and the linear fast path
  against them at equal accuracy;
- ``beds``: the reference bed, Kirchhoff and Mindlin, against a 3D solid,
  and the modes of large Mindlin beds (grid, imported quads and triangles);
- ``verdict``: the CPU cost of the worked shock verdict (docs/shock-verdict.md);
- ``stress``: the bed's stress recovery against the transient (docs/bed-stresses.md);
- ``random``: the CPU cost of a random response (docs/random-vibration.md).
- ``response_spectrum``: response-spectrum analysis and synthesis (docs/response-spectrum.md).

The report is also printed on stdout; progress goes to stderr. A section
that raises (an internal fault) does not stop the report: its place holds
the error and its traceback, the other sections run, the report is
written, and the command then ends with one line naming the failed
sections, exit 1.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

from flexbed.commands.arguments import number, file_name
from flexbed.errors import InputError, NumericalError
from flexbed.words import count

#: the default output folder, in the current folder
DEFAULT_OUTPUT = "flexbed-bench"

#: target -> (sections, integrator cases); None: the profile's
TARGETS = {
    "all": (None, None),
    "modes": (["mesh"], None),
    "rigid": (["integrators", "aims"], ("rigid",)),
    "flexible": (["integrators", "aims"], ("flexible", "damped")),
    "modelling": (["modes_count", "mesh", "invariants"], None),
    "frequency": (["frequency"], None),
    "linear": (["integrators", "linear"], None),
    "inputs": (["inputs"], None),
    "beds": (["beds"], None),
    "scaling": (["scaling"], None),
    "verdict": (["verdict"], None),
    "stress": (["stress"], None),
    "random": (["random"], None),
    "response_spectrum": (["response_spectrum"], None),
}


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("Benchmarks as a work-precision report: every integrator's error "
                          "against wall time, and the error and cost of the modelling "
                          "choices, written to DIR/benchmarks.md with PNG diagrams.")
    parser.add_argument("target", nargs="?", default="all", metavar="TARGET",
                        help=f"a part of the report only: {', '.join(TARGETS)} (default: all); "
                             f"a scene file here is taken as SCENE")
    parser.add_argument("scene", nargs="?", default=None,
                        help="scene file (default: the built-in reference scene)")
    parser.add_argument("--quick", action="store_true",
                        help="cheaper cases, fewer settings and repeats; the linear fast "
                             "path only as the target 'linear'")
    parser.add_argument("-o", "--output", type=file_name, default=DEFAULT_OUTPUT, metavar="DIR",
                        help=f"folder of the report and its PNGs (default: ./{DEFAULT_OUTPUT}; "
                             f"'-o docs' regenerates the project's own report)")
    parser.add_argument("--t-end", type=number, default=None, metavar="T",
                        help="end every run at T seconds (default: the scene's; the aims "
                             "are stated for 0-3 s)")


def target_and_scene(target: str, scene: str | None) -> tuple[str, str | None]:
    """The positional words as (target, scene): ``flexbed bench SCENE.toml``
    is the whole report on that scene; anything else must be a target."""
    if target in TARGETS:
        return target, scene
    if scene is None and target.endswith(".toml"):
        return "all", target
    raise InputError(f"target {target!r} is not one of {', '.join(TARGETS)}")


def check_t_end(t_end: float) -> None:
    """``--t-end``, refused before any work: the report measures errors on
    a grid of ``BenchContext.output_dt`` (0.01 s), so a run needs two of
    its samples, and at most the output samples a run may store."""
    from flexbed.bench.context import BenchContext
    from flexbed.dynamics.integrate import MAX_OUTPUT_SAMPLES

    dt = BenchContext.output_dt
    if not (math.isfinite(t_end) and 2 * dt <= t_end <= dt * MAX_OUTPUT_SAMPLES):
        raise InputError(f"--t-end {t_end:g}: from {2 * dt:g} s (two of the report's "
                         f"{dt:g} s samples) to {dt * MAX_OUTPUT_SAMPLES:g} s")


def run(args: argparse.Namespace) -> int:
    from flexbed.bench.report import write_report   # NumPy, SciPy, numba, matplotlib

    def log(m: str) -> None:
        print(m, file=sys.stderr, flush=True)

    args.target, args.scene = target_and_scene(args.target, args.scene)
    if args.t_end is not None:
        check_t_end(args.t_end)
    sections, cases = TARGETS[args.target]
    filename = "benchmarks.md" if args.target == "all" else f"benchmarks-{args.target}.md"
    words = ["flexbed bench"] + ([] if args.target == "all" else [args.target])
    words += [args.scene] if args.scene else []
    words += ["--quick"] if args.quick else []
    words += [f"--t-end {args.t_end:g}"] if args.t_end is not None else []
    words += [f"-o {args.output}"] if args.output != DEFAULT_OUTPUT else []
    report = write_report(Path(args.output), scene=args.scene, quick=args.quick,
                          sections=sections, cases=cases, t_end=args.t_end, filename=filename,
                          command=" ".join(words), log=log)
    print(report.path.read_text())
    for old in report.stale:
        print(f"note: {old} is not part of this report (left in place)", file=sys.stderr)
    print(f"wrote {report.path} and {count(len(report.figures), 'PNG')} in "
          f"{report.elapsed:.1f} s", file=sys.stderr)
    if report.failed:
        names = ", ".join(name for name, _ in report.failed)
        raise NumericalError(f"{count(len(report.failed), 'section')} failed ({names}): "
                             f"{report.failed[0][1]}; the report holds the other sections "
                             f"and the traceback: {report.path}")
    return 0

"""``flexbed qualify [SCENE] [-o PREFIX] …``: the shock verdict — statics,
the transient the scene describes, and every mount, body, point of
interest and clearance judged against the scene's limits.

Prints the verdict (Markdown) and writes ``PREFIX.md``, ``PREFIX.csv`` and
``PREFIX.h5`` (``flexbed.verdict``; PREFIX default ``<scene stem>-verdict``),
and the run's results file with ``--results FILE``. Exit status: 0 PASS,
3 FAIL (:data:`flexbed.errors.EXIT_FAIL`), 1 numerical failure, 2 bad
input — nothing is written on 1 or 2.
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

from flexbed.commands.arguments import add_scene_arg, number, file_name
from flexbed.commands.compare import add_solver_args
from flexbed.commands.static import add_modes_file_arg
from flexbed.errors import EXIT_FAIL, EXIT_OK, InputError
from flexbed.files.destination import check_destination, refuse_inputs, write_text
from flexbed.files.elastomer import time_run_scene
from flexbed.files.scene import load_scene

__all__ = ["add_args", "run", "outputs"]


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("The shock verdict: static equilibrium, the transient the scene "
                          "describes, and each mount (stroke, load, force), body (fragility), "
                          "point of interest and clearance judged against the scene's limits. "
                          "Exit status 0 PASS, 3 FAIL.")
    add_scene_arg(parser)
    parser.add_argument("-o", "--output", type=file_name, default=None, metavar="PREFIX",
                        help="prefix of the files written (default: <scene stem>-verdict)")
    add_solver_args(parser)
    parser.add_argument("--output-dt", type=number, default=None, metavar="DT",
                        help="spacing of the samples the extremes are found from [s] "
                             "(default: the scene's [solver] output_dt)")
    parser.add_argument("--results", default=None, metavar="FILE",
                        help="also write the run's results file")
    add_modes_file_arg(parser)


def outputs(prefix: str, results: str | None) -> dict[str, Path]:
    """The files written, each checked before any work."""
    out = {k: check_destination(Path(prefix + v))
           for k, v in (("md", ".md"), ("csv", ".csv"), ("h5", ".h5"))}
    if results:
        out["results"] = check_destination(Path(results))
    return out


def _modes(sf, modes_file):
    """A flexible bed's modes: the file given or found where 'flexbed modes'
    writes it, else computed in memory."""
    if not sf.bed.flexible:
        return None
    from flexbed.stages.flexible_bed import load_modes_for
    from flexbed.stages.modes import default_modes_path
    path = Path(modes_file) if modes_file else default_modes_path(sf)
    if modes_file or path.exists():
        return load_modes_for(sf, path)
    return None


def run(args: argparse.Namespace) -> int:
    from flexbed.api.qualification import qualify

    t0 = time.perf_counter()
    sf = load_scene(args.scene)
    sf = time_run_scene(sf)
    settings = {k: v for k, v in (("integrator", args.integrator), ("t_end", args.t_end),
                                  ("output_dt", args.output_dt)) if v is not None}
    for key in ("t_end", "output_dt"):
        if key in settings and not (math.isfinite(settings[key]) and settings[key] > 0):
            raise InputError(f"option: --{key.replace('_', '-')} = {settings[key]!r} must be "
                             f"a finite number > 0 s")
    out = outputs(args.output or f"{sf.output_name}-verdict", args.results)
    refuse_inputs(out["h5"], sf.source, args.modes_file)
    q = qualify(sf, modes=_modes(sf, args.modes_file), **settings)
    report = q.markdown()
    print(report, end="")
    write_text(out["md"], report)
    write_text(out["csv"], q.csv())
    q.save(out["h5"])
    if "results" in out:
        q.results.save(out["results"])
    print("wrote " + ", ".join(str(p) for p in out.values()))
    print(f"verdict: {'PASS' if q.passed else 'FAIL'} ({time.perf_counter() - t0:.1f} s)")
    return EXIT_OK if q.passed else EXIT_FAIL

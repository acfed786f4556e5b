"""``flexbed optimize FILE.toml``: mount layout optimisation — design
variables by their path in the scene, objectives and constraints from the
study metrics — on the study's Dask engine, into one folder: the log of
every evaluation (a re-run reuses it), the optimum as a scene file, the
convergence plot and the initial design against the optimum.

Exit 1 when no feasible point was found (the least-violating point is
written all the same).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from flexbed.commands.arguments import count, file_name
from flexbed.files.table_reader import MAX_WORKERS
from flexbed.errors import InputError, NumericalError

__all__ = ["add_args", "run"]


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("Optimise a mount layout (an optimisation file: base scene, "
                          "variables by their path in the scene with bounds or catalogues, "
                          "objectives and constraints from the study metrics, method) on a "
                          "Dask cluster; write the optimum as a scene file, the log of every "
                          "evaluation, a convergence plot and the initial design against the "
                          "optimum.")
    parser.add_argument("file", help="optimisation file (TOML)")
    parser.add_argument("-o", "--output", type=file_name, default=None, metavar="DIR",
                        help="output folder (default: <file stem>-optimize); a re-run into "
                             "the same folder reuses the evaluations logged there")
    parser.add_argument("--scheduler", default=None, metavar="tcp://HOST:PORT",
                        help="run on this existing Dask cluster (default: a local cluster of "
                             "processes, started and stopped here)")
    parser.add_argument("--workers", type=count(MAX_WORKERS), default=None, metavar="N",
                        help="workers of the local cluster (default: one per core)")
    parser.add_argument("--no-plots", action="store_true", help="write no plots")


def run(args: argparse.Namespace) -> int:
    from flexbed.api.optimization import check_output
    from flexbed.optimization.driver import optimize_problem
    from flexbed.optimization.problem import make_problem
    from flexbed.optimization.report import write_report
    from flexbed.optimization.spec import read_optimize
    from flexbed.study.engine import cluster_client

    if args.workers is not None and args.scheduler is not None:
        raise InputError("--workers sizes the local cluster; with --scheduler the cluster's "
                         "own workers run the optimisation")
    spec = read_optimize(args.file)
    folder = check_output(args.output if args.output else f"{Path(args.file).stem}-optimize")
    problem = make_problem(spec)                  # every path and metric checked: nothing ran
    print(f"optimize '{spec.name}': {problem.n} variables, method {spec.method}"
          f"{f', {spec.starts} starts' if spec.starts > 1 else ''}, analyses "
          f"{', '.join(problem.analyses)}")
    with cluster_client(args.scheduler, args.workers, warm_scene=problem.base) as client:
        opt = optimize_problem(problem, client, folder)
    written = write_report(opt, folder, plots=not args.no_plots)
    for v, x in zip(problem.variables, opt.x):
        more = len(v.paths) - 1                   # tied, mirrored, linked: in optimum.toml
        print(f"  {v.path} = {x:.8g}" + (f" (and {more} path{'s' if more > 1 else ''} set "
                                         f"with it)" if more else ""))
    print(f"objective {opt.objective:.8g}, {opt.evaluations} evaluations "
          f"({opt.reused} reused) in {opt.wall_time:.1f} s; wrote "
          f"{', '.join(p.name for p in written)} and evaluations.csv in {folder}")
    if not opt.feasible:
        raise NumericalError(f"{spec.source.name}: no feasible point found in "
                             f"{opt.evaluations} evaluations (largest violation "
                             f"{opt.violation:.3g} of its bound at the best point, written to "
                             f"{folder / 'optimum.toml'})")
    return 0

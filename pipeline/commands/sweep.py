"""``flexbed sweep STUDY.toml``: a design study — many variants of one scene —
run on Dask, into one table (CSV and HDF5) with plots.

The only command that imports ``dask.distributed``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from flexbed.commands.arguments import count, file_name
from flexbed.files.table_reader import MAX_BATCH, MAX_WORKERS
from flexbed.errors import InputError

__all__ = ["add_args", "run"]


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("Run a design study (a study file: base scene, parameters by their "
                          "path in the scene, sampling, analyses, metrics) on a Dask cluster "
                          "and write one table with a row per point, and plots.")
    parser.add_argument("study", help="study file (TOML)")
    parser.add_argument("-o", "--output", type=file_name, default=None, metavar="DIR",
                        help="output folder (default: <study file stem>-study); a re-run "
                             "into the same folder skips the points done")
    parser.add_argument("--scheduler", default=None, metavar="tcp://HOST:PORT",
                        help="run on this existing Dask cluster (default: a local cluster of "
                             "processes, started and stopped here)")
    parser.add_argument("--workers", type=count(MAX_WORKERS), default=None, metavar="N",
                        help="workers of the local cluster (default: one per core)")
    parser.add_argument("--batch", type=count(MAX_BATCH), default=None, metavar="N",
                        help="points per Dask task (default: the study's [study] batch, else "
                             "chosen from the numbers of points and workers: large batches "
                             "first, at most 16, single points last)")
    parser.add_argument("--keep-results", action="store_true",
                        help="also write each point's results file into DIR/results")
    parser.add_argument("--retry-failed", action="store_true",
                        help="run again the points that failed in a previous run")
    parser.add_argument("--no-plots", action="store_true", help="write no plots")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar on stderr")


def run(args: argparse.Namespace) -> int:
    from flexbed.study.plan import make_plan
    from flexbed.study.runner import PlanProgress, run_plan
    from flexbed.study.spec import read_study
    from flexbed.study.table import check_folder

    if args.workers is not None and args.scheduler is not None:
        raise InputError("--workers sizes the local cluster; with --scheduler the cluster's "
                         "own workers run the study")
    study = read_study(args.study)
    folder = check_folder(args.output if args.output else f"{Path(args.study).stem}-study")
    # every path, point and metric checked: nothing ran yet
    plan = make_plan(study, PlanProgress(not args.no_progress))
    n_keys = len({p.key for p in plan.points})
    print(f"study '{study.name}': {len(plan.points)} points ({n_keys} distinct scenes), "
          f"analyses {', '.join(plan.analyses)}, {len(plan.metric_columns)} metric columns")
    table = run_plan(plan, scheduler=args.scheduler, workers=args.workers, folder=folder,
                     keep_results=args.keep_results, retry_failed=args.retry_failed,
                     progress=not args.no_progress, plots=not args.no_plots,
                     batch=args.batch, log=lambda msg: print(msg, file=sys.stderr))
    failed = int((~table.ok).sum())
    print(f"wrote {folder / 'table.csv'} and {folder / 'table.h5'} ({len(table)} rows"
          f"{f', {failed} failed' if failed else ''})")
    return 0

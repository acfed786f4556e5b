"""Mount layout optimisation as a library call (as ``flexbed optimize``);
the optimisation package (and with it ``dask.distributed``) is imported on
first call.

>>> import flexbed
>>> opt = flexbed.optimize("layout.toml", output="layout-opt")  # doctest: +SKIP
>>> opt.values, opt.feasible, opt.evaluations                     # doctest: +SKIP
"""

from __future__ import annotations

from pathlib import Path

from flexbed.threads import limited

__all__ = ["optimize"]


@limited()
def optimize(file, scheduler=None, *, output: str | Path | None = None,
             workers: int | None = None, plots: bool = True):
    """Optimise a mount layout on Dask (as ``flexbed optimize``).

    Parameters
    ----------
    file : path or flexbed.optimization.spec.OptimizeSpec
        The optimisation file (TOML; see docs/optimize.md).
    scheduler : str or distributed.Client, optional
        ``"tcp://HOST:PORT"`` of a running Dask scheduler, or a Client;
        default: a local cluster of processes, one per core, for the call
        (from a script, keep the call under ``if __name__ == "__main__":``).
    output : path, optional
        Folder for ``evaluations.csv`` (the log; a re-run into the same
        folder reuses its evaluations), ``optimum.toml``,
        ``comparison.md`` and the plots. Default: nothing written.
    workers : int, optional
        Size of the local cluster.
    plots : bool
        Write ``convergence.png`` and ``transmissibility.png``.

    BLAS pools are held to ``FLEXBED_THREADS`` threads in the call, as on
    the command line: SciPy's optimisers then round alike in both, so a
    re-run retraces the logged path and reuses its evaluations.

    Returns
    -------
    flexbed.optimization.driver.Optimum
        ``values`` (path → value), ``feasible``, ``objective``,
        ``violation``, ``evaluations``, ``scene`` (the optimum's), ``best``
        and ``initial`` (their metrics), ``history``. An optimisation that
        found no feasible point returns its least-violating point with
        ``feasible = False`` (the command exits 1).

    Raises
    ------
    InputError
        The file refused (unknown path, reversed bounds, unknown metric …)
        before anything runs.
    """
    from flexbed.api.arguments import Arguments
    from flexbed.files.table_reader import MAX_WORKERS
    from flexbed.optimization.driver import optimize_problem
    from flexbed.optimization.problem import make_problem
    from flexbed.optimization.report import write_report
    from flexbed.optimization.spec import OptimizeSpec, read_optimize
    from flexbed.study.engine import cluster_client

    check = Arguments("optimize")
    if not isinstance(file, OptimizeSpec):
        path = check.path(file, "file", optional=False)
    if not (scheduler is None or isinstance(scheduler, str) or hasattr(scheduler, "submit")):
        check.bad("scheduler", scheduler, "'tcp://HOST:PORT', a distributed.Client, or None")
    output = check.path(output, "output")
    workers = check.integer(workers, "workers", minimum=1, maximum=MAX_WORKERS, optional=True)
    plots = check.flag(plots, "plots")
    spec = file if isinstance(file, OptimizeSpec) else read_optimize(path)
    problem = make_problem(spec)
    folder = check_output(output) if output is not None else None
    with cluster_client(scheduler, workers, warm_scene=problem.base) as client:
        opt = optimize_problem(problem, client, folder)
    if folder is not None:
        write_report(opt, folder, plots=plots)
    return opt


def check_output(folder) -> Path:
    """``folder`` as a Path if an optimisation may write there; InputError
    otherwise (checked before anything runs)."""
    from flexbed.errors import InputError
    from flexbed.files.destination import check_destination
    from flexbed.optimization.evaluate import LOG
    from flexbed.optimization.report import FILES

    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise InputError(f"{folder}: is not a folder; an optimisation writes its log, optimum "
                         f"and plots into a folder (choose another name)")
    for name in (LOG,) + FILES:
        check_destination(folder / name)
    return folder

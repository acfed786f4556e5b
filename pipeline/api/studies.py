"""A design study on Dask as a library call (as ``flexbed sweep``); the
study package (and with it ``dask.distributed``) is imported on first call.

>>> import flexbed
>>> table = flexbed.sweep("study.toml", output="study-out")  # doctest: +SKIP
>>> table["peak_mount_force.M5"][table.ok]                   # doctest: +SKIP
"""

from __future__ import annotations

from pathlib import Path

__all__ = ["sweep"]


def sweep(study, scheduler=None, *, output: str | Path | None = None, workers: int | None = None,
          keep_results: bool = False, retry_failed: bool = False, progress: bool = False,
          plots: bool = True, batch: int | None = None):
    """Run a design study on Dask (as ``flexbed sweep``).

    Parameters
    ----------
    study : path or flexbed.study.spec.Study
        The study file (TOML; see "Study file" in the README).
    scheduler : str or distributed.Client, optional
        ``"tcp://HOST:PORT"`` of a running Dask scheduler, or a Client;
        default: a local cluster of processes, one per core, for the call.
        (Started from a script, the local cluster's processes import the
        script again: keep its work under ``if __name__ == "__main__":``.)
    output : path, optional
        Folder for ``table.csv``, ``table.h5``, ``plots/`` and, with
        ``keep_results``, ``results/``; a re-run with the same folder
        skips the points done. Default: nothing written.
    workers : int, optional
        Size of the local cluster.
    keep_results, retry_failed, progress, plots : bool
        As the command's ``--keep-results``, ``--retry-failed``, progress
        bar (stderr) and ``--no-plots``.
    batch : int, optional
        Points per Dask task (``--batch``; default the study's ``batch``,
        else chosen from the numbers of points and workers, at most 16).

    Returns
    -------
    flexbed.study.table.StudyTable
        A row per point: ``table["peak_mount_force.M5"]``, ``table.ok``,
        ``table.rows()``; ``complete``.

    Raises
    ------
    InputError
        The study refused (unknown parameter path, metric, …) before
        anything runs.
    """
    from flexbed.study.plan import make_plan
    from flexbed.study.runner import PlanProgress, run_plan
    from flexbed.study.spec import Study, read_study
    from flexbed.study.table import check_folder

    from flexbed.api.arguments import Arguments
    from flexbed.files.table_reader import MAX_BATCH, MAX_WORKERS

    check = Arguments("sweep")
    if not isinstance(study, Study):
        path = check.path(study, "study", optional=False)
    if not (scheduler is None or isinstance(scheduler, str) or hasattr(scheduler, "submit")):
        check.bad("scheduler", scheduler, "'tcp://HOST:PORT', a distributed.Client, or None")
    output = check.path(output, "output")
    workers = check.integer(workers, "workers", minimum=1, maximum=MAX_WORKERS, optional=True)
    keep_results, retry_failed, progress, plots = (
        check.flag(v, k) for k, v in (("keep_results", keep_results),
                                      ("retry_failed", retry_failed), ("progress", progress),
                                      ("plots", plots)))
    batch = check.integer(batch, "batch", minimum=1, maximum=MAX_BATCH, optional=True)
    if not isinstance(study, Study):
        study = read_study(path)
    plan = make_plan(study, PlanProgress(progress))
    folder = check_folder(output) if output is not None else None
    return run_plan(plan, scheduler=scheduler, workers=workers, folder=folder,
                    keep_results=keep_results, retry_failed=retry_failed, progress=progress,
                    plots=plots, batch=batch)

"""Run a planned study on Dask and gather its table.

The points already in the output folder's table (same scene hash, same
analyses and metrics) are skipped; each distinct bed's modes are one task
that every point needing them depends on; each distinct scene is one task
(keyed by its hash, so identical points run once); rows are written
(atomically) as they arrive, at most every 5 s, and once more at the
end or on Ctrl-C (then marked incomplete). A point that fails keeps its
one-line message; a point whose worker died is re-run by the scheduler on
another worker (Dask's ``allowed-failures``), and if every try is lost its
row says so.

A point's scene goes to its worker without what it shares with the base
scene (:func:`flexbed.study.point.shared_parts`: the bodies, mounts and base
a variant leaves as they are, one task whose result each worker fetches
once): a few kB a point instead of ~26 kB for the reference scene, so that
a study of thousands of points keeps the client's memory and each graph it
submits small (several submissions of at most :data:`GRAPH_BYTES`).

Several points per task: the scheduler and the client spend ~5 ms of CPU
on every task (docs/sweep-benchmark.md), so points of 0.1 s on tens of
workers would wait on them; a task runs a batch of points (the same bed's
modes) and returns a row for each; by default large batches first and
single points last (:func:`auto_sizes`), so that the study does not end
with one worker busy on a long batch and the others idle. Batches change
nothing in the rows (each point is run, timed, failed, resumed on its
own); a worker lost runs its batch again elsewhere.
"""

from __future__ import annotations

import hashlib
import math
import sys
import time
from pathlib import Path

from flexbed.errors import one_line
from flexbed.interrupts import Interrupted, held
from flexbed.study.plan import Plan, modes_scene
from flexbed.study.point import PointResult, bed_modes, pack, parts_of, run_batch, \
    shared_parts
from flexbed.study.table import Row, StudyTable, build_table, folder_lock, read_done, \
    write_table

__all__ = ["run_plan", "StudyProgress", "auto_batch", "auto_sizes", "batches"]

#: seconds between two writes of the table while the study runs, at
#: least (each write is the whole table, CSV and HDF5, atomically: ~40 ms
#: of the client's CPU for 200 rows, ~0.3 s for 10,000)...
WRITE_EVERY = 5.0
#: ... and at least this many times the last write's own time, so that
#: the writes take at most ~2 % of the client's time whatever the size
#: of the table (rows done since the last write are in memory; Ctrl-C or
#: an error writes them)
WRITE_RATIO = 50.0

#: the points' bytes a submission sends at most (the tasks go to the
#: scheduler in as few submissions as keep each under it: Dask warns of a
#: graph over 10 MB, ``distributed.admin.large-graph-warning-threshold``)
GRAPH_BYTES = 4_000_000

#: ``batch = "auto"``: each batch holds the points left divided by this
#: many per worker ...
SHARES_PER_WORKER = 2
#: ... and at most this many points
MAX_BATCH = 16


def auto_sizes(points: int, workers: int) -> list[int]:
    """Points per task, task after task, when the study does not say:
    ``ceil(points left / (SHARES_PER_WORKER × workers))``, at most
    ``MAX_BATCH`` — large batches first (few tasks: the scheduler and the
    client spend ~5 ms of CPU on each, docs/sweep-benchmark.md), shrinking
    to single points at the end, so that no worker waits long for another's
    last batch (Dask runs a study's tasks in the order submitted). 200
    points on 2 workers: 9 tasks of 16, then 14, 11, 8, 6, 5, 3, 3, 2, 1,
    1, 1, 1."""
    sizes, left, shares = [], points, SHARES_PER_WORKER * max(1, workers)
    while left > 0:
        size = max(1, min(MAX_BATCH, math.ceil(left / shares)))
        sizes.append(size)
        left -= size
    return sizes


def auto_batch(points: int, workers: int) -> int:
    """The largest (first) of :func:`auto_sizes`."""
    return auto_sizes(points, workers)[0] if points > 0 else 1


def batches(todo: dict, modes_keys: dict, size: int | None, workers: int = 1) -> list[list[str]]:
    """The distinct scenes to run (``todo``'s keys, in study order) cut into
    batches, each on one bed's modes (``modes_keys``: scene key → modes
    key or None), in the order to run them: ``size`` points each (the
    last of a bed's may be smaller), or with ``size`` None
    :func:`auto_sizes` for ``workers``."""
    groups: dict = {}
    for key in todo:
        groups.setdefault(modes_keys[key], []).append(key)
    if size is not None:
        return [keys[i:i + size] for keys in groups.values()
                for i in range(0, len(keys), size)]
    ordered = [key for keys in groups.values() for key in keys]
    out, start = [], 0
    for n in auto_sizes(len(ordered), workers):
        chunk = ordered[start:start + n]
        start += n
        cut = [chunk[:1]]                               # split where the bed changes
        for key in chunk[1:]:
            if modes_keys[key] == modes_keys[cut[-1][-1]]:
                cut[-1].append(key)
            else:
                cut.append([key])
        out.extend(cut)
    return out


class StudyProgress:
    """A progress bar on stderr: points done of the total, failures, time
    spent and an estimate of the time left (from this run's rate)."""

    def __init__(self, total: int, already: int, enabled: bool, stream=None):
        self.total, self.already = total, already
        self.enabled = enabled
        self.stream = stream if stream is not None else sys.stderr
        self.t0 = time.perf_counter()
        self.last = -1.0
        self.shown = False
        self.counts = (already, 0)

    def update(self, done: int, failed: int, force: bool = False) -> None:
        """Redraw (at most 4 times a second) with ``done`` rows of which ``failed``."""
        if not self.enabled:
            return
        self.counts = (done, failed)
        now = time.perf_counter()
        if not force and now - self.last < 0.25:
            return
        self.last = now
        spent = now - self.t0
        new = done - self.already
        left = self.total - done
        eta = f", ~{_duration(spent / new * left)} left" if new > 0 and left > 0 else ""
        frac = done / self.total if self.total else 1.0
        bar = "#" * int(round(30 * frac))
        fails = f", {failed} failed" if failed else ""
        self.stream.write(f"\rsweep [{bar:<30}] {done}/{self.total} points{fails}, "
                          f"{_duration(spent)}{eta}   ")
        self.stream.flush()
        self.shown = True

    def close(self) -> None:
        """Draw the last state and end the line."""
        if self.shown:
            self.update(*self.counts, force=True)
            self.stream.write("\n")
            self.stream.flush()


class PlanProgress:
    """``progress(i, n)`` for :func:`flexbed.study.plan.make_plan`: a line on
    stderr, drawn only when planning has taken a second, at most 4 times a
    second, ended when the last point is planned."""

    def __init__(self, enabled: bool, stream=None):
        self.enabled = enabled
        self.stream = stream if stream is not None else sys.stderr
        self.t0 = time.perf_counter()
        self.last = -1.0
        self.shown = False

    def __call__(self, i: int, n: int) -> None:
        if not self.enabled:
            return
        now = time.perf_counter()
        if i < n and (now - self.t0 < 1.0 or now - self.last < 0.25):
            return
        if i == n and not self.shown:
            return
        self.last = now
        self.stream.write(f"\rsweep: checking the points' scenes, {i}/{n}, "
                          f"{_duration(now - self.t0)}   " + ("\n" if i == n else ""))
        self.stream.flush()
        self.shown = True


def _duration(s: float) -> str:
    if s < 90:
        return f"{s:.0f} s"
    if s < 5400:
        return f"{s / 60:.0f} min"
    return f"{s / 3600:.1f} h"


def _row(plan: Plan, point, res: PointResult) -> Row:
    return Row(point.index, plan.parameter_row(point.values), tuple(res.values), res.status,
               res.message, float(res.solve_time), float(res.cpu_time), point.key)


def run_plan(plan: Plan, *, scheduler=None, workers: int | None = None,
             folder: Path | None = None, keep_results: bool = False,
             retry_failed: bool = False, progress: bool = False, plots: bool = True,
             batch: int | None = None, log=None) -> StudyTable:
    """Run the points of ``plan`` not already done; return the whole table.

    Parameters
    ----------
    plan : Plan
    scheduler : str, distributed.Client or None
        See :func:`flexbed.study.engine.cluster_client`.
    workers : int, optional
        Local cluster size (default one per core).
    folder : Path, optional
        Output folder: ``table.csv``, ``table.h5``, ``plots/``,
        ``results/`` (None: nothing written, nothing resumed).
    keep_results : bool
        Write each point's results file(s) into ``folder/results``.
    retry_failed : bool
        Run again the points that failed in a previous run.
    progress : bool
        Progress bar on stderr.
    plots : bool
        Write the plots at the end.
    batch : int, optional
        Points per task (default: the study's ``batch``, else
        :func:`auto_sizes` of the points to run and the cluster's workers).
    log : callable(str), optional
        One-line notes (points skipped, tables ignored).
    """
    if folder is None:
        return _run_plan(plan, scheduler, workers, None, keep_results, retry_failed, progress,
                         plots, batch, log)
    with folder_lock(folder):
        return _run_plan(plan, scheduler, workers, folder, keep_results, retry_failed,
                         progress, plots, batch, log)


def _run_plan(plan, scheduler, workers, folder, keep_results, retry_failed, progress, plots,
              batch, log) -> StudyTable:
    log = log or (lambda msg: None)
    done = read_done(folder, plan, log) if folder is not None else {}
    rows: dict[int, Row] = {}
    todo: dict[str, list] = {}
    for p in plan.points:
        prev = done.get(p.key)
        if prev is not None and (prev[0] == "ok" or not retry_failed):
            rows[p.index] = _row(plan, p, PointResult(*prev))
        else:
            todo.setdefault(p.key, []).append(p)
    if rows:
        log(f"{len(rows)} of {len(plan.points)} points already done in {folder / 'table.h5'}; "
            f"skipped")
    bar = StudyProgress(len(plan.points), len(rows), progress)
    last_write = [-float("inf"), WRITE_EVERY]      # when, and the next interval

    def save(complete: bool, force: bool = True) -> StudyTable | None:
        now = time.perf_counter()
        if not force and (folder is None or now - last_write[0] < last_write[1]):
            return None
        table = build_table(plan, rows, complete, folder)
        if folder is not None:
            # the table's two files are written whole, whatever the signal;
            # one that comes meanwhile is acted on once both are written
            with held() as pending:
                write_table(table, plan, folder)
            done = time.perf_counter()
            last_write[:] = [done, max(WRITE_EVERY, WRITE_RATIO * (done - now))]
            if pending:
                raise Interrupted(pending[0])
        return table

    try:
        if todo:
            _run(plan, todo, rows, scheduler, workers, folder if keep_results else None,
                 bar, lambda: save(False, force=False), batch or plan.study.batch)
    except KeyboardInterrupt:
        bar.close()
        save(False)
        raise
    bar.close()
    table = save(len(rows) == len(plan.points))
    if plots and folder is not None and len(table):
        from flexbed.plots.study import plot_study
        plot_study(table, folder / "plots")
    return table


def _run(plan, todo, rows, scheduler, workers, keep_folder, bar, checkpoint, size) -> None:
    from distributed import as_completed

    from flexbed.study.engine import cluster_client

    with cluster_client(scheduler, workers, warm_scene=plan.base) as client:
        modes = {}
        for pts in todo.values():
            p = pts[0]
            if p.modes_key is not None and p.modes_key not in modes:
                modes[p.modes_key] = client.submit(bed_modes, modes_scene(p.scene),
                                                   key=f"flexbed-modes-{p.modes_key}")
        # few graphs for all the batches (a submission each would cost the
        # scheduler several times the CPU per task), run in this order; the
        # parts the points share with the base sent to each worker once
        setup = pack((plan.analyses, plan.metrics, keep_folder is not None))
        parts = shared_parts(plan.base)
        blob = pack(parts)
        # a task holding the parts' bytes, not scattered data: the scheduler
        # can run it again on another worker if its holder is lost, and it
        # needs no worker yet when the study is submitted
        shared = client.submit(parts_of, blob, pure=True,
                               key=f"flexbed-parts-{hashlib.sha256(blob).hexdigest()[:24]}")
        groups = batches(todo, {k: pts[0].modes_key for k, pts in todo.items()}, size,
                         len(client.scheduler_info().get("workers", {})))
        names = [f"flexbed-batch-{hashlib.sha256(''.join(keys).encode()).hexdigest()[:24]}"
                 f"-{plan.signature}" for keys in groups]
        blobs = [[pack(todo[k][0].scene, parts) for k in keys] for keys in groups]
        futures = []
        for part in submissions([sum(map(len, b)) for b in blobs], GRAPH_BYTES):
            futures += client.map(run_batch, [blobs[i] for i in part], [setup] * len(part),
                                  [modes.get(todo[groups[i][0]][0].modes_key) for i in part],
                                  [shared] * len(part), key=[names[i] for i in part],
                                  retries=1)
        del blobs
        owner = dict(zip(names, groups))
        failed = sum(r.status != "ok" for r in rows.values())
        bar.update(len(rows), failed, force=True)
        try:
            for fut in as_completed(futures):
                keys = owner[fut.key]
                try:
                    results = fut.result()
                except Exception as exc:                # every try lost, or cancelled
                    lost = PointResult("failed", one_line(exc),
                                       (float("nan"),) * len(plan.metric_columns),
                                       float("nan"), float("nan"))
                    results = [lost] * len(keys)
                fut.release()
                for key, res in zip(keys, results):
                    for p in todo[key]:
                        rows[p.index] = _row(plan, p, res)
                        if keep_folder is not None and res.files:
                            _keep(keep_folder, p.index, res.files)
                        failed += res.status != "ok"
                bar.update(len(rows), failed)
                checkpoint()
        except KeyboardInterrupt:
            client.cancel(futures + list(modes.values()) + [shared])
            raise


def submissions(sizes: list, limit: float) -> list:
    """Consecutive runs of task indices whose ``sizes`` [bytes] add up to at
    most ``limit`` (a task larger than it alone), in order."""
    runs, run, total = [], [], 0
    for i, size in enumerate(sizes):
        if run and total + size > limit:
            runs.append(run)
            run, total = [], 0
        run.append(i)
        total += size
    return runs + [run] if run else runs


def _keep(folder: Path, index: int, files: dict) -> None:
    """Write a point's kept files, ``folder/results/point-NNNN-<suffix>``
    (``files``: suffix → (writer, args), :mod:`flexbed.study.analyses`)."""
    for suffix, (writer, args) in files.items():
        writer(folder / "results" / f"point-{index:04d}-{suffix}", *args)

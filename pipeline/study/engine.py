"""The Dask cluster a study runs on: a local cluster of processes started
and stopped here (one worker per core, one thread each, their BLAS and
OpenMP pools pinned to ``FLEXBED_THREADS``), an existing cluster by its
scheduler's address, or a :class:`distributed.Client` the caller holds.

Every worker warms its compiled code once (:class:`~flexbed.study.point.WarmUp`,
also on workers that join later).
"""

from __future__ import annotations

import logging
import os
from contextlib import ExitStack, contextmanager
from typing import Iterator

from flexbed.errors import InputError
from flexbed.files.scene import SceneFile
from flexbed.interrupts import Interrupted, held
from flexbed.threads import thread_count

__all__ = ["cluster_client", "worker_environment", "LOCAL_CONFIG"]


#: Dask settings of the local cluster (set with ``dask.config.set`` around
#: the cluster: the scheduler and nannies run in this process, the workers
#: get them from their nanny). Its housekeeping costs CPU that the points
#: would use (measured idle, 2 workers: 74 ms of CPU per second with Dask's
#: defaults, ~15 ms/s with these; the rest is the heartbeats, every 0.5 s,
#: which the scheduler sets): no statistical profiler sampling every
#: thread's stack every 10 ms, no GIL-contention poll (1 ms, when
#: ``gilknocker`` is installed), no disk counters, no active memory manager
#: (a study keeps no replicas); the event-loop watchdog, system monitor,
#: memory monitor and work stealing at 1-2 s instead of 20-500 ms. A
#: cluster started apart keeps its own settings, but the study's worker
#: plugin (:class:`~flexbed.study.point.WarmUp`) stops the profiler there too.
LOCAL_CONFIG = {"distributed.worker.profile.enabled": False,
                "distributed.admin.tick.interval": "1s",
                "distributed.admin.system-monitor.interval": "2s",
                "distributed.admin.system-monitor.gil.enabled": False,
                "distributed.admin.system-monitor.disk": False,
                "distributed.scheduler.active-memory-manager.start": False,
                "distributed.worker.memory.monitor-interval": "1s",
                "distributed.scheduler.work-stealing-interval": "1s"}


def worker_environment() -> dict:
    """The thread-pool variables every local worker starts with
    (:mod:`flexbed.threads`)."""
    n = str(thread_count())
    return {name: n for name in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS",
                                 "BLIS_NUM_THREADS", "VECLIB_MAXIMUM_THREADS",
                                 "FLEXBED_THREADS")}


def _has_warm_up(dask_scheduler) -> bool:
    """On the scheduler: are the workers warmed already (a client held
    across studies, a cluster that ran one)? Then a study does not warm
    them again (~40 ms of CPU a worker)."""
    from flexbed.study.point import WarmUp
    return WarmUp.name in dask_scheduler.worker_plugins


@contextmanager
def cluster_client(scheduler=None, workers: int | None = None,
                   warm_scene: SceneFile | None = None) -> Iterator:
    """A connected ``distributed.Client``.

    Parameters
    ----------
    scheduler : str, Client or None
        ``"tcp://HOST:PORT"`` of a running scheduler, a Client (used as
        is, not closed), or None: a local cluster for the duration.
    workers : int, optional
        Workers of the local cluster (default: one per core).
    warm_scene : SceneFile, optional
        Warm every worker's compiled code on this scene.
    """
    import dask
    from distributed import Client, LocalCluster

    from flexbed.study.point import Quiet, WarmUp

    def ready(client):
        if warm_scene is not None and not client.run_on_scheduler(_has_warm_up):
            client.register_plugin(WarmUp(warm_scene))
        return client

    if isinstance(scheduler, Client):
        yield ready(scheduler)
        return
    if scheduler is not None:
        if not isinstance(scheduler, str) or "://" not in scheduler:
            raise InputError(f"--scheduler {scheduler!r}: give the scheduler's address, "
                             f"e.g. tcp://127.0.0.1:8786")
        try:
            client = Client(scheduler, timeout="15s")
        except (OSError, TimeoutError) as exc:
            raise InputError(f"--scheduler {scheduler}: cannot connect "
                             f"({str(exc).splitlines()[0] if str(exc) else type(exc).__name__})"
                             ) from None
        with client:
            yield ready(client)
        return
    n = workers or os.cpu_count() or 1
    if n < 1:
        raise InputError(f"--workers = {n!r} must be >= 1")
    with dask.config.set(LOCAL_CONFIG), ExitStack() as stack:
        # a cluster interrupted half-started cannot be closed (distributed's
        # exit hook then fails on it with a traceback): a SIGINT or SIGTERM
        # waits for the start, then closes the cluster as any interrupt does
        # (a Ctrl-C at a terminal also reaches the workers starting: a start
        # that then fails was interrupted)
        pending: list = []
        try:
            with held() as pending:
                cluster = stack.enter_context(
                    LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                                 dashboard_address=":0", env=worker_environment(),
                                 silence_logs=logging.CRITICAL))
                client = stack.enter_context(Client(cluster))
        except Exception:
            if not pending:
                raise
        if pending:
            raise Interrupted(pending[0])
        client.register_plugin(Quiet())
        yield ready(client)

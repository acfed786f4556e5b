"""What a Dask worker runs: a batch of points (each point's analyses and
metrics, one after another), a bed's modes, and the warm-up of a worker's
compiled code.

A point never raises: a failure (no equilibrium, a run that stops early,
anything else) comes back as its one-line message, so the study goes on.
"""

from __future__ import annotations

import io
import logging
import math
import pickle
import signal
import threading
import time
from dataclasses import dataclass, field

from distributed.diagnostics.plugin import WorkerPlugin

import numpy as np

from flexbed.errors import NumericalError, one_line
from flexbed.files.scene import SceneFile
from flexbed.study.analyses import ANALYSES
from flexbed.threads import limited

__all__ = ["PointResult", "run_point", "run_batch", "pack", "unpack", "shared_parts",
           "parts_of", "bed_modes", "Quiet", "WarmUp", "warm"]


@dataclass(frozen=True)
class PointResult:
    """status : "ok" or "failed"; message : str (one line; "" when ok);
    values : tuple of float (the metrics' cells; NaN when failed);
    solve_time, cpu_time : float [s] — wall-clock time and CPU time of the
    analyses on the worker (the CPU time of the thread that ran them, so
    not the worker's own housekeeping threads); files : dict suffix → (writer,
    args), the point's kept files (:mod:`flexbed.study.analyses`)."""

    status: str
    message: str
    values: tuple
    solve_time: float
    cpu_time: float
    files: dict = field(default_factory=dict)


def run_point(scene: SceneFile, analyses: tuple, metrics: tuple, modes=None,
              keep: bool = False) -> PointResult:
    """Run ``analyses`` (names, in order) on ``scene`` and evaluate ``metrics``.

    Parameters
    ----------
    scene : SceneFile
    analyses : tuple of str
    metrics : tuple of metric objects (:mod:`flexbed.study.metrics`)
    modes : ModesData, optional
        The bed's modes (flexible bed, or an analysis that needs them).
    keep : bool
        Return the analyses' results files' contents.
    """
    n = sum(len(m.columns) for m in metrics)
    t0, c0 = time.perf_counter(), time.thread_time()
    try:
        if isinstance(modes, Exception):             # the bed's modes failed
            raise modes
        outcomes = {}
        # a value that overflows is caught below as a failed point, not as a
        # RuntimeWarning line on the worker's stderr; the thread pools limited
        # once for the point's API calls (flexbed.threads.limited)
        with np.errstate(all="ignore"), limited():
            for name in analyses:
                outcomes[name] = ANALYSES[name].run(scene, outcomes, modes)
            values = tuple(v for m in metrics for v in m.values(outcomes))
        columns = [c for m in metrics for c in m.columns]
        for c, v in zip(columns, values):
            if not math.isfinite(v):
                raise NumericalError(f"metric {c} = {v!r}: not a finite number")
    except Exception as exc:                       # the study goes on
        return PointResult("failed", one_line(exc), (float("nan"),) * n,
                           time.perf_counter() - t0, time.thread_time() - c0)
    wall, cpu = time.perf_counter() - t0, time.thread_time() - c0
    files = {}
    if keep:
        for name in analyses:
            if ANALYSES[name].files is not None:
                files.update(ANALYSES[name].files(outcomes[name]))
    return PointResult("ok", "", values, wall, cpu, files)


def pack(obj, shared: tuple = ()) -> bytes:
    """``obj`` pickled once on the client: Dask ships bytes as they are,
    where it would pickle a scene's ~130 dataclass objects with
    cloudpickle's pure-Python pickler at every submission (5 ms of CPU a
    task, measured; 0.3 ms this way). Objects of ``shared`` (by identity)
    are written as their index in it (:func:`unpack` takes them from
    there): a study's points send only what is their own."""
    if not shared:
        return pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL)
    index = {id(o): i for i, o in enumerate(shared)}
    out = io.BytesIO()
    writer = pickle.Pickler(out, protocol=pickle.HIGHEST_PROTOCOL)
    writer.persistent_id = lambda o: index.get(id(o))     # None: pickled as usual
    writer.dump(obj)
    return out.getvalue()


def unpack(blob: bytes, shared: tuple = ()):
    """The object :func:`pack` wrote, with the same ``shared`` objects (or
    equal ones: a copy unpickled on a worker)."""
    reader = pickle.Unpickler(io.BytesIO(blob))
    reader.persistent_load = shared.__getitem__
    return reader.load()


def shared_parts(base: SceneFile) -> tuple:
    """The parts of a study's base scene that its points' scenes hold as
    they are (the same objects: the scene reader keeps an entry a variant
    does not change, :mod:`flexbed.files.scene`): its bodies, mounts and
    base (with its inputs' samples, most of a scene's bytes). Fetched by
    each worker once (:func:`parts_of`), and left out of every point's
    :func:`pack`."""
    sc = base.scene
    return tuple(sc.bodies) + tuple(sc.mounts) + (sc.base,)


def parts_of(blob: bytes) -> bytes:
    """The task that holds ``pack(shared_parts(base))`` on the cluster (its
    result is its argument): a result the scheduler can compute again where
    scattered data would be lost with its worker."""
    return blob


def run_batch(scenes: list, setup: bytes, modes=None, shared: bytes | None = None) -> list:
    """:func:`run_point` of each ``pack(scene, parts)`` in ``scenes`` with
    ``pack((analyses, metrics, keep))``, one after another: the task a
    worker runs; ``shared`` is ``pack(parts)`` (None: no parts). Returns a
    list of PointResult, one per scene (each point keeps its own times and
    its own failure)."""
    analyses, metrics, keep = pickle.loads(setup)
    parts = pickle.loads(shared) if shared is not None else ()
    with limited():                     # once for the batch, not per point
        return [run_point(unpack(scene, parts), analyses, metrics, modes, keep)
                for scene in scenes]


def bed_modes(scene: SceneFile):
    """The modes of the scene's bed (computed once per plate request by the
    runner, then handed to every point that needs them); an exception is
    returned, not raised, so that the points fail with its message."""
    from flexbed.api import modes
    try:
        return modes(scene)
    except Exception as exc:
        return exc


def warm(scene: SceneFile) -> None:
    """Load the compiled right-hand side and steppers (numba's cache) and
    run the statics of the scene with its bed rigid, and load the
    metrics' compiled peaks (a point's positions from a state's rows, the
    peaks of norms), so that the first point a worker runs is timed like
    the others. Failures are ignored (the first point then pays)."""
    import dataclasses

    from flexbed.api import statics
    from flexbed.dynamics.sample_passes import point_path
    from flexbed.dynamics.integrate import warm_up
    from flexbed.study.metrics import peak_norm
    try:
        rigid = dataclasses.replace(scene, bed=dataclasses.replace(scene.bed, model="rigid")) \
            if scene.bed.flexible else scene
        st = statics(rigid)
        warm_up(st.system, st.equilibrium.y)
        Y = np.tile(st.equilibrium.y, (2, 1))
        parts = st.system.layout.split(Y)
        if st.system.n_rigid:                        # the types a point's metrics pass
            r, p = parts["r"][:, 0], parts["p"][:, 0]
            point_path(r, p, np.zeros(3), r, p, True)
        peak_norm(np.zeros((2, 3)))
        peak_norm(np.zeros((2, 4, 9))[:, :, 3:6])
    except Exception:
        pass


class Quiet(WorkerPlugin):
    """For the local cluster's workers: they ignore Ctrl-C (the terminal
    sends it to every process of its group; the study's own process stops
    them, and a worker's ``KeyboardInterrupt`` traceback would only clutter
    the terminal) and log nothing below CRITICAL (a point's failure is
    reported in the study's table; Dask's WARNING lines, such as a worker
    "still alive after 4.0 seconds, killing" at shutdown, are its
    housekeeping)."""

    name = "flexbed-quiet"

    def setup(self, worker) -> None:
        if threading.current_thread() is threading.main_thread():
            signal.signal(signal.SIGINT, signal.SIG_IGN)
        for name in ("distributed", "tornado", "asyncio"):
            logging.getLogger(name).setLevel(logging.CRITICAL)


class WarmUp(WorkerPlugin):
    """Runs :func:`warm` once on every worker, joining now or later, and
    stops the worker's statistical profiler (Dask samples every thread's
    stack every 10 ms by default, ``distributed.worker.profile``; the local
    cluster starts without it, a cluster started apart may not): the
    dashboard's profile page of a study's workers stays empty."""

    name = "flexbed-warm-up"

    def __init__(self, scene: SceneFile):
        self.scene = scene

    def setup(self, worker) -> None:
        for name in ("profile", "profile-cycle"):
            callback = getattr(worker, "periodic_callbacks", {}).pop(name, None)
            if callback is not None:
                callback.stop()
        warm(self.scene)

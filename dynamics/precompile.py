"""A fresh install's first compiling, in two processes at once.

The right-hand side (:func:`flexbed.dynamics.kernel.rhs_function`, one C
function) and the compiled steppers (:mod:`flexbed.dynamics.steppers`)
need nothing of each other's machine code: a stepper calls the right-hand
side through a function pointer it receives as an argument. So on a first
run (the right-hand side not yet in numba's on-disk cache)
:func:`compile_in_parallel` starts a second Python process that compiles
the right-hand side into the cache while this one compiles the steppers
(and the batch evaluations) for the argument types every run passes them,
with a stand-in for the pointer (:func:`stand_in_kernel`, never called);
it then waits for the child, and the first call of the right-hand side
loads it from the cache. A linear run (``--model linear``) compiles the
linear path's functions here instead (:func:`compile_linear_path`: by
their argument types, without calling them). On two cores that saves wall time, not CPU time:
the same functions are compiled, once each, the two halves side by side.

The two processes write different cache files (numba keeps an index and
data files per function), each written to a temporary name and renamed
into place (``numba.core.caching``), so a reader sees a whole file or none;
a child that fails or is stopped leaves at worst a function this process
compiles itself later, as it would have anyway.

Signals: the child ends at once on SIGINT or SIGTERM (their default
action: nothing printed; a cache file it was writing stays a temporary
one that numba never reads). If this process is interrupted while it
compiles or waits, it stops the child (SIGTERM, then SIGKILL after
:data:`STOP_WAIT` seconds) and waits for it before the interrupt goes
on, so no process is left behind. Python acts on a signal between two
bytecodes: inside numba's LLVM stage that can be seconds later, for this
process as for any first run.

Run as ``python -m flexbed.dynamics.precompile`` it is the child: it
compiles the right-hand side and exits (0, or 1 if compiling failed).
"""

from __future__ import annotations

import math
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from .jitcache import cache_dir
from .kernel import evaluate_batch, evaluate_many, rhs_function
from .kernel.rhs import PROTOTYPE, rhs_loaded
from .steppers import N_COUNTS, dop853_segment, radau_segment, radau_workspace, rk4_segment

__all__ = ["rhs_cached", "stand_in_kernel", "compile_callers", "compile_linear_path",
           "compile_statics", "compile_in_parallel",
           "likely_steppers", "LINEAR_MAPS", "STEPPERS", "STOP_WAIT", "SWITCH"]

#: the compiled steppers by method name
STEPPERS = {"rk4": rk4_segment, "dop853": dop853_segment, "radau": radau_segment}
#: seconds a stopped child is given to leave before it is killed
STOP_WAIT = 5.0
#: environment variable: "0" compiles everything in this process, one
#: function after another (as before; for measuring, or where starting a
#: second Python process is not wanted)
SWITCH = "FLEXBED_COMPILE_ASIDE"

_RHS_SOURCE = Path(__file__).resolve().parent / "kernel" / "rhs.py"


def rhs_cached() -> bool:
    """Whether this process holds the compiled right-hand side, or numba's
    cache does (its data file ``rhs.evaluate-*.nbc`` is in the cache folder
    of :mod:`flexbed.dynamics.kernel.rhs`); True also where that folder is
    unknown (a child could not hand it over: this process compiles it)."""
    if rhs_loaded():
        return True
    folder = cache_dir(_RHS_SOURCE)
    return not folder or any(Path(folder).glob("rhs.evaluate-*.nbc"))


def _never_called(t, seg_end, y, dy, F, I):   # noqa: E741 - the kernel's names
    raise AssertionError("the stand-in right-hand side was called")


_STAND_IN = PROTOTYPE(_never_called)


def stand_in_kernel(ny: int) -> tuple:
    """A kernel tuple ``(function, F, I)`` of the types of
    :attr:`flexbed.dynamics.system.System.kernel` (the pointer of
    :data:`flexbed.dynamics.kernel.PROTOTYPE`, float64 and int64 storage)
    whose function is a stand-in: for compiling callers without the
    right-hand side, by calls that evaluate nothing."""
    return (_STAND_IN, np.zeros(ny), np.zeros(8 + ny, dtype=np.int64))


def compile_callers(methods=tuple(STEPPERS), ny: int = 13) -> None:
    """Compile (or load) the compiled steppers ``methods`` and the batch
    evaluations for the argument types the integrators pass them
    (:func:`flexbed.dynamics.integrate.integrate`), by calls over an empty
    interval that take no step: the right-hand side is neither needed nor
    compiled (:func:`stand_in_kernel`). ny: any state size."""
    kernel = stand_in_kernel(ny)
    z, shift = np.zeros(ny), np.zeros(ny)
    atol = np.full(ny, 1e-9)
    grid, Y = np.zeros(1), np.empty((1, ny))
    p_idx = np.zeros((1, 4), dtype=np.int64)
    counts = np.zeros(N_COUNTS, dtype=np.int64)
    for method in methods:
        work = radau_workspace(ny) if method == "radau" else ()
        STEPPERS[method](0.0, 0.0, z, shift, kernel, 1e-6, atol, 0.0, math.inf, grid, Y, 1, 1,
                         p_idx, ny, counts, work)
    # as System.rhs_batch and the benchmark's kernel timing call them
    evaluate_batch(kernel, math.inf, np.zeros(0), np.zeros((0, ny)), np.zeros((0, ny)),
                   np.zeros(0, dtype=np.int64), np.zeros((0, 0)))
    evaluate_many(0, 0.0, math.inf, z, np.empty_like(z), kernel)


def compile_statics() -> None:
    """Compile (or load) the statics' compiled Newton pieces for scenes of
    rigid bodies (:mod:`flexbed.dynamics.rigid_statics`) for the argument
    types :func:`flexbed.dynamics.statics.solve_statics` passes them, by
    calls on a stand-in of one mount between the base and a body (C
    arrays of float64 and int64, the System's own read-only;
    ``tests/test_jitcache.py`` checks that the reference scene's statics
    then add no signature)."""
    from .rigid_statics import rigid_tangent, step_state
    m, nb = 1, 2
    A = np.zeros((nb, 3, 3))
    A[:] = np.eye(3)
    U, body_i, body_j = (np.zeros((m, 3, 3)), np.zeros(m, dtype=np.int64),
                         np.ones(m, dtype=np.int64))
    for a in (U, body_i, body_j):              # the System's arrays are read-only
        a.flags.writeable = False
    rigid_tangent(A, np.zeros((2 * m, 3)), np.zeros((2 * m, 3)), np.zeros((m, 3)),
                  np.zeros((m, 3)), U, np.zeros(3 * m), body_i, body_j, np.zeros((6, 6)))
    y = np.zeros(7)
    y[3] = 1.0
    step_state(y, 0, 1, np.zeros(6), np.empty(7))


def _linear_signatures() -> dict:
    """The linear path's compiled functions (:mod:`flexbed.dynamics.linear`)
    and the one signature each is called with (``tests/test_jitcache.py``
    checks that a real linear run adds none): name → argument types."""
    from numba import typeof, types

    def arr(dtype, ndim, readonly=False):
        return types.Array(dtype, ndim, "C", readonly=readonly)

    f8, i8 = types.float64, types.int64
    F1, F2, F3 = arr(f8, 1), arr(f8, 2), arr(f8, 3)
    I1, I2 = arr(i8, 1), arr(i8, 2)
    I1r, I2r = arr(i8, 1, True), arr(i8, 2, True)
    F1r, F2r = arr(f8, 1, True), arr(f8, 2, True)
    kernel = typeof(stand_in_kernel(1))
    coords = types.Tuple((F1, I2r, I2r, I2r, I2r, F2, I2r, F2))
    return {
        "defect.cubic_misses": (F1, F2, F1, F2, F1, F1),
        "defect.cubic_pieces": (F1, F2, F3),
        "defect.defect_rows": (kernel, f8, F1, F2, I1, coords, F1, F2, F2, i8, F2),
        "defect.defect_sweep": (F3, F3, I1, F3, F1, F1, F2),
        "defect.error_peaks": (F1, I1, F2, F2, F2, F2, I1r),
        "defect.hermite_peak": (F1, I1, F2, F2),
        "defect.largest_motion": (F2, I1, F2),
        "defect.pieces_at": (F1, F1, F3, F2),
        "defect.pieces_integral_at": (F1, F1, F3, F2),
        "defect.point_rows": (I1, F2, F2, I2r, I2r, F3),
        "defect.refine_nodes": (kernel, f8, F1, F2, F2, coords, F1, F2, F2, i8, I1, f8, f8, F2),
        "defect._group_peak": (F1, I1, I1, I2, F3, f8),
        "phi.exp_and_phi_columns": (F2, F2, f8, F2, F3),
        "phi.phi_double": (F2, F3, F2, F1),
        "phi.phi_functions": (F2, F3),
        "sweep.deviations_to_states": (F2, F1, I2r, I2r, I2r, I2r, F2, F2),
        "sweep.few_distinct": (F1, I1, I1, i8),
        "sweep.linear_sweep": (F3, I1, F2, F1, F2),
        "sweep.merge_cuts": (F1, F1, f8, F1),
        "sweep.poly_derivatives": (F2r, F1r, I1, F1, F1, F2),
        "sweep.rates_of_states": (F2, I2r, I2r, I2r, F2, F2),
        "sweep.states_to_deviations": (F2, F1, I2r, I2r, I2r, I2r, F2, F2),
    }


#: the linear model's maps between states and deviations
#: (:mod:`flexbed.dynamics.linear.model`), which more than the linear runs use
LINEAR_MAPS = ("sweep.deviations_to_states", "sweep.rates_of_states")


def compile_linear_path(names=None) -> None:
    """Compile (or load) the linear fast path's functions for the argument
    types a linear run passes them, without calling them (numba's
    ``Dispatcher.compile``): nothing of the right-hand side is needed.
    ``names``: ``"module.function"`` keys, e.g. :data:`LINEAR_MAPS`
    (default: every one)."""
    import importlib
    table = _linear_signatures()
    for key in table if names is None else names:
        argtypes = table[key]
        module, name = key.split(".")
        fn = getattr(importlib.import_module(f"{__package__}.linear.{module}"), name)
        fn.compile(argtypes)


def likely_steppers(integrator: str) -> tuple:
    """The compiled steppers a run with ``integrator`` will most likely
    need: itself, dop853 for "auto" (its usual choice,
    :func:`flexbed.dynamics.method_choice.auto_method`), none for SciPy's
    adams and bdf."""
    if integrator in STEPPERS:
        return (integrator,)
    return ("dop853",) if integrator == "auto" else ()


def _stop(child: subprocess.Popen) -> None:
    if child.poll() is None:
        child.terminate()
        try:
            child.wait(STOP_WAIT)
        except subprocess.TimeoutExpired:
            child.kill()
            child.wait()


def compile_in_parallel(methods=tuple(STEPPERS), log=lambda m: None,
                        linear=False) -> float:
    """On a first run, compile the right-hand side in a child process and
    the steppers ``methods`` (and the linear path's functions ``linear``,
    and the statics' compiled pieces, :func:`compile_statics`) here, at the
    same time; else nothing.

    Parameters
    ----------
    methods : names of :data:`STEPPERS`
    linear : bool or tuple of str
        True: every function of the linear path; a tuple: those
        (:func:`compile_linear_path`'s keys); False: none.
    log : callable(str)
        One progress line when it compiles.

    Returns
    -------
    float
        Wall time spent [s] (0 when nothing was done: the right-hand side
        cached, no stepper asked for, or :data:`SWITCH` set to "0").
    """
    if not (methods or linear) or os.environ.get(SWITCH, "1") == "0" or rhs_cached():
        return 0.0
    t0 = time.perf_counter()
    log("compiling the right-hand side and the integrators (first run; cached afterwards) ...")
    child = subprocess.Popen([sys.executable, "-m", __name__], stdin=subprocess.DEVNULL,
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        if methods:
            compile_callers(methods)
        if linear:
            compile_linear_path(None if linear is True else linear)
        compile_statics()
        child.wait()
    finally:
        _stop(child)
    rhs_function()                   # loads it from the cache (compiles it if the child failed)
    return time.perf_counter() - t0


def _child() -> int:
    # stopped at once, even inside LLVM (where a Python handler would wait):
    # nothing of the child's is worth finishing, and numba's files are only
    # ever whole (renamed into place) or absent
    for s in (signal.SIGINT, signal.SIGTERM):
        signal.signal(s, signal.SIG_DFL)
    try:
        rhs_function()
    except Exception:   # noqa: BLE001 - the parent compiles it then
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(_child())

"""flexbed's own thread pools: BLAS and OpenMP limited to ``FLEXBED_THREADS``
threads (default 1).

flexbed's linear algebra is small or banded (the bed's shift-invert eigen
step factors a banded matrix of bandwidth ~4 (nx + 1)); a BLAS that starts
one thread per core gains nothing there, and on a machine busy with other
work its threads wait for each other: the modes stage was seen to take 10 s
instead of 0.3 s. The parallelism that pays is one process per core (a
study's points), so each process keeps to one thread.

- The command line sets ``OPENBLAS_NUM_THREADS``, ``OMP_NUM_THREADS``,
  ``MKL_NUM_THREADS`` and ``BLIS_NUM_THREADS`` before NumPy is loaded
  (:func:`pin_environment`), so that every pool starts at that size.
- The Python API, called where NumPy and SciPy are already loaded, limits
  the loaded pools for the duration of each call (:func:`limited`, with
  threadpoolctl) and restores them afterwards.
"""

from __future__ import annotations

import os
import sys
import threading
from contextlib import contextmanager
from typing import Iterator

__all__ = ["thread_count", "pin_environment", "limited"]

_VARIABLES = ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS",
              "BLIS_NUM_THREADS", "VECLIB_MAXIMUM_THREADS")


def thread_count() -> int:
    """Threads per pool: ``FLEXBED_THREADS`` if it is an integer ≥ 1, else 1."""
    try:
        n = int(os.environ.get("FLEXBED_THREADS", "1"))
    except ValueError:
        return 1
    return n if n >= 1 else 1


def pin_environment() -> None:
    """Set the pools' environment variables to :func:`thread_count` (before
    NumPy, SciPy or numba are imported; later imports start their pools
    at that size)."""
    n = str(thread_count())
    for name in _VARIABLES:
        os.environ[name] = n


#: [calls inside limited() now, in any thread; the threadpoolctl limiter they share]
_HELD: list = [0, None]
_LOCK = threading.Lock()


@contextmanager
def limited() -> Iterator[None]:
    """Limit every loaded BLAS and OpenMP pool to :func:`thread_count`
    threads inside the ``with`` block (or, as the decorator ``@limited()``,
    inside each call of the function).

    The pools are process-wide: the first call to enter sets the limits,
    the last to leave restores what was there before; calls inside it (an
    API function calling another, a study's points inside their batch)
    only count themselves in and out (setting and restoring the limits
    costs some 0.1 ms, as much as a small study point's statics' checks)."""
    with _LOCK:
        if _HELD[0] == 0:
            _HELD[1] = _controller().limit(limits=thread_count())
        _HELD[0] += 1
    try:
        yield
    finally:
        with _LOCK:
            _HELD[0] -= 1
            if _HELD[0] == 0:
                limiter, _HELD[1] = _HELD[1], None
                limiter.restore_original_limits()


_FOUND: list = [-1, None]          # [len(sys.modules) when found, ThreadpoolController]


def _controller():
    """The loaded pools (a ``threadpoolctl.ThreadpoolController``), found
    again when ``sys.modules`` has grown since."""
    if _FOUND[0] != len(sys.modules):
        from threadpoolctl import ThreadpoolController
        _FOUND[1] = ThreadpoolController()
        _FOUND[0] = len(sys.modules)
    return _FOUND[1]

"""flexbed's own heap: freed memory kept for the next run (glibc only).

A run allocates and frees arrays of 0.1–10 MB (a linear path on 1 ms
samples: its states, 1 MB each). glibc serves them from the heap once one
has been freed, but gives the heap's free top back to the system as soon
as it exceeds twice the largest such array; the next run then touches
fresh pages, one minor page fault per 4 KiB. At one stage of its
development the linear path on the reference scene's 3,001 samples took
574 page faults a call when called again and again (and none when its
calls alternated with an integrator's, which kept the heap's top in use);
its fastest call of 100 was 7.1 and 9.8 ms against 5.0 and 5.5 ms with
the thresholds fixed, two runs of each. Whether a given version of a
calculation falls into the pattern depends on the order of its
allocations; three 1 MiB arrays made and freed again and again do
(480 faults a round here; tests/test_heap.py).

:func:`keep_freed_memory` fixes glibc's thresholds instead of letting them
float: arrays under 32 MiB from the heap (glibc's own ceiling for its
floating threshold), and up to 64 MiB of free heap kept. Elsewhere than
glibc it does nothing. The setting is the whole process's: the command
line makes it (flexbed's own process); a program that calls the Python
API decides for itself (``flexbed.heap.keep_freed_memory()``).
"""

from __future__ import annotations

import ctypes

__all__ = ["keep_freed_memory"]

#: mallopt's parameters (malloc.h)
_M_TRIM_THRESHOLD = -1
_M_MMAP_THRESHOLD = -3
#: arrays below this come from the heap [bytes]
MMAP_THRESHOLD = 32 << 20
#: free heap kept at its top [bytes]
TRIM_THRESHOLD = 64 << 20

_done = False


def keep_freed_memory() -> bool:
    """Set glibc's thresholds (once per process); True if they were set."""
    global _done
    if _done:
        return True
    try:
        mallopt = ctypes.CDLL(None).mallopt          # the process's own C library
    except (OSError, AttributeError, TypeError):      # no C library by that name (Windows)
        return False
    mallopt.argtypes = (ctypes.c_int, ctypes.c_int)
    _done = bool(mallopt(_M_MMAP_THRESHOLD, MMAP_THRESHOLD)) and bool(
        mallopt(_M_TRIM_THRESHOLD, TRIM_THRESHOLD))
    return _done

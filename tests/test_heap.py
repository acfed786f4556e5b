"""Freed memory is kept for the next run (flexbed.heap, glibc): arrays of a
few MiB allocated, touched and freed again and again take fresh pages each
time under glibc's floating thresholds (it gives the heap's free top back
once it exceeds twice the largest array freed) and none once flexbed has
fixed them; checked in fresh interpreters by the process's own count of
minor page faults."""

import subprocess
import sys

import pytest

PROBE = """
import resource, sys
import numpy as np
from flexbed.heap import keep_freed_memory
if sys.argv[1] == "keep":
    assert keep_freed_memory()
def work():
    a = [np.ones(131072) for _ in range(3)]        # three 1 MiB arrays, every page touched
    return sum(float(x[-1]) for x in a)
for _ in range(5):
    work()
before = resource.getrusage(resource.RUSAGE_SELF).ru_minflt
for _ in range(20):
    work()
print((resource.getrusage(resource.RUSAGE_SELF).ru_minflt - before) / 20)
"""


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="glibc's thresholds")
def test_repeated_allocations_take_no_fresh_pages():
    faults = {}
    for mode in ("keep", "default"):
        p = subprocess.run([sys.executable, "-c", PROBE, mode], capture_output=True, text=True,
                           timeout=300)
        assert p.returncode == 0, p.stderr
        faults[mode] = float(p.stdout.split()[-1])
    assert faults["default"] > 200.0                  # seen 480: the pattern does fault
    assert faults["keep"] < 5.0                       # seen 0

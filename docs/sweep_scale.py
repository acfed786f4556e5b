"""`flexbed sweep` of a large study measured from the outside: wall time,
points per second, the client process's CPU (its own user + system time:
the command's main thread, the scheduler and the nannies, which a local
cluster runs in this process) per point, the peak resident memory of the
client and of each worker, and every warning printed.

Usage: ``python docs/sweep_scale.py POINTS [WORKERS]`` (default 2
workers): writes ``sweep-scale-POINTS.toml`` (``docs/sweep-study.toml``
with ``samples = POINTS``) in the current folder, runs
``flexbed sweep`` on it in this process (``flexbed.cli.main``, into
``sweep-scale-POINTS-study``, removed first), and prints one line of
Markdown table: points, wall [s], points/s, client CPU per point [ms]
(the whole process, and its main thread alone: the command's own work,
without the scheduler's and the nannies' threads), peak RSS of the client
and of the largest worker [MB], warnings.

The workers' memory is sampled every 0.2 s (psutil, the client's child
processes); the client's peak is its own ``ru_maxrss``.
"""

from __future__ import annotations

import io
import re
import resource
import shutil
import sys
import threading
import time
import warnings
from contextlib import redirect_stderr
from pathlib import Path

import psutil

HERE = Path(__file__).resolve().parent


def study_file(points: int) -> Path:
    """``docs/sweep-study.toml`` with ``samples = points``, here."""
    text = (HERE / "sweep-study.toml").read_text()
    path = Path(f"sweep-scale-{points}.toml")
    path.write_text(re.sub(r"(?m)^samples = \d+$", f"samples = {points}", text))
    return path


class Peaks(threading.Thread):
    """The largest RSS [B] of any child process of this one, sampled."""

    def __init__(self):
        super().__init__(daemon=True)
        self.peak, self.stop = 0, threading.Event()

    def run(self) -> None:
        me = psutil.Process()
        while not self.stop.wait(0.2):
            for child in me.children(recursive=True):
                try:
                    self.peak = max(self.peak, child.memory_info().rss)
                except psutil.Error:
                    pass


def main(points: int, workers: int = 2) -> str:
    from flexbed.cli import main as flexbed

    study = study_file(points)
    out = Path(f"sweep-scale-{points}-study")
    shutil.rmtree(out, ignore_errors=True)
    peaks = Peaks()
    peaks.start()
    err = io.StringIO()
    u0 = resource.getrusage(resource.RUSAGE_SELF)
    t0, c0 = time.perf_counter(), time.thread_time()
    with warnings.catch_warnings(record=True) as caught, redirect_stderr(err):
        warnings.simplefilter("always")
        code = flexbed(["sweep", str(study), "-o", str(out), "--workers", str(workers),
                        "--no-plots", "--no-progress"])
    wall, main_cpu = time.perf_counter() - t0, time.thread_time() - c0
    u1 = resource.getrusage(resource.RUSAGE_SELF)
    peaks.stop.set()
    peaks.join()
    cpu = (u1.ru_utime - u0.ru_utime) + (u1.ru_stime - u0.ru_stime)
    said = [str(w.message).splitlines()[0][:70] for w in caught]
    said += [line[:70] for line in err.getvalue().splitlines() if "arning" in line]
    return (f"| {points} | {wall:.1f} | {points / wall:.1f} | {1e3 * cpu / points:.2f} | "
            f"{1e3 * main_cpu / points:.2f} | "
            f"{u1.ru_maxrss / 1024:.0f} | {peaks.peak / 2**20:.0f} | "
            f"{'; '.join(sorted(set(said))) or 'none'} |" + ("" if code == 0 else f" exit {code}"))


if __name__ == "__main__":
    print(main(int(sys.argv[1]), int(sys.argv[2]) if len(sys.argv) > 2 else 2), flush=True)

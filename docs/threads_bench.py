"""The thread pools measured: ``flexbed modes --force`` and ``flexbed bench
--quick`` with FLEXBED_THREADS = 1 (flexbed's default) and 2 (what OpenBLAS
takes by itself on a 2-core machine), without and with background load (two
busy processes). The two settings are interleaved run by run; medians of
the modes stage's own time and of the wall times. Prints a Markdown table.

Usage: ``python docs/threads_bench.py [REPEATS] [modes] [bench]`` (default 5,
both), with ``flexbed`` on the PATH. Takes a few minutes.
"""
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

def run(cmd, env):
    t0 = time.perf_counter()
    cp = subprocess.run(cmd, env=env, capture_output=True, text=True)
    assert cp.returncode == 0, cp.stderr
    wall = time.perf_counter() - t0
    m = re.search(r"; ([0-9.]+) s\)", cp.stdout)
    return wall, float(m.group(1)) if m else float("nan")

def busy(n):
    return [subprocess.Popen([sys.executable, "-c", "while True: pass"]) for _ in range(n)]

def env_for(threads):
    env = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    env["FLEXBED_THREADS"] = threads
    return env

tmp = tempfile.mkdtemp()
reps = int(sys.argv[1]) if len(sys.argv) > 1 else 5
what = sys.argv[2:] or ["modes", "bench"]
rows = []
for load in (0, 2):
    procs = busy(load)
    time.sleep(1.0)
    try:
        if "modes" in what:
            res = {"1": [], "2": []}
            for _ in range(reps):
                for threads in ("1", "2"):
                    res[threads].append(run(["flexbed", "modes", "--force", "-o", f"{tmp}/m.h5"],
                                            env_for(threads)))
            for threads, ts in res.items():
                rows.append(("modes --force", load, threads, statistics.median(w for w, _ in ts),
                             statistics.median(s for _, s in ts), len(ts)))
        if "bench" in what:
            for threads in ("1", "2"):
                w, _ = run(["flexbed", "bench", "--quick", "-o", f"{tmp}/b{threads}"],
                           env_for(threads))
                rows.append(("bench --quick", load, threads, w, float("nan"), 1))
    finally:
        for p in procs:
            p.kill()
print("| command | background load | FLEXBED_THREADS | wall [s] | the stage's own [s] | runs |")
print("|---|---|---|---|---|---|")
for r in rows:
    own = "" if r[4] != r[4] else f"{r[4]:.2f}"
    print(f"| `flexbed {r[0]}` | {'2 busy processes' if r[1] else 'none'} | {r[2]} | "
          f"{r[3]:.2f} | {own} | {r[5]} |")

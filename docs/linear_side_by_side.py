"""The linear fast path against dop853 at the same accuracy, side by side.

The reference scene with a rigid bed (0–3 s, from its static equilibrium):
the linear path (its error estimate included, 3.4e-9 m) and dop853 at
rtol = 1e-8, atol = 1e-11 (8.6e-10 m; rtol 1e-7 misses 3.4e-9 m), both on
output samples DT apart, in N interleaved pairs in one process, so that
both see the same load on a shared machine. Prints the medians of the CPU
seconds (time.process_time) of whole calls and the median of the pairwise
ratios (the issue's aim: at most 1/3).

    OPENBLAS_NUM_THREADS=1 python docs/linear_side_by_side.py DT [N]
"""

from __future__ import annotations

import os
import statistics
import sys
import time

from flexbed.dynamics.integrate import Settings, integrate
from flexbed.dynamics.linear import run_linear
from flexbed.dynamics.statics import solve_statics
from flexbed.files.scene import load_scene
from flexbed.stages.system import compile_scene


def main(dt: float, n: int) -> str:
    system = compile_scene(load_scene(None))
    y = solve_statics(system, tol=1e-11).y
    linear = Settings("rk4", t_end=3.0, output_dt=dt)
    dop = Settings("dop853", t_end=3.0, output_dt=dt, rtol=1e-8, atol=1e-11)
    for _ in range(5):                 # compiled code loaded, caches warm
        run_linear(system, y, y, linear)
        integrate(system, y, dop)
    tl, ti = [], []
    for _ in range(n):
        c0 = time.process_time()
        run_linear(system, y, y, linear)
        c1 = time.process_time()
        integrate(system, y, dop)
        c2 = time.process_time()
        tl.append(c1 - c0)
        ti.append(c2 - c1)
    ratio = statistics.median(a / b for a, b in zip(tl, ti))
    return (f"output_dt {dt:g} s (load {os.getloadavg()[0]:.1f}): linear "
            f"{statistics.median(tl) * 1e3:.2f} ms, dop853 {statistics.median(ti) * 1e3:.2f} ms "
            f"of CPU (medians of {n} pairs), pairwise ratio {ratio:.3f}")


if __name__ == "__main__":
    print(main(float(sys.argv[1]), int(sys.argv[2]) if len(sys.argv) > 2 else 41))

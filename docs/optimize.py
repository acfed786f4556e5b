"""Worked example of docs/optimize.md: the eight equipment mounts of the
reference bed optimised for decoupling, frequency placement and static
deflection, with the bed rigid and then flexible, on a local Dask
cluster of two workers.

    python docs/optimize.py            # writes docs/optimize-out-{rigid,flexible}/

Each folder gets the log (``evaluations.csv``; a re-run reuses it), the
optimum as a scene file, ``comparison.md`` (the before/after tables) and
the plots; the convergence and transmissibility plots are copied to
``docs/optimize-*.png``. The layout file is ``docs/optimize-layout.toml``.
"""

from __future__ import annotations

import dataclasses
import shutil
import time
from pathlib import Path

import flexbed
from flexbed.optimization.spec import read_optimize

HERE = Path(__file__).resolve().parent


def main() -> None:
    spec = read_optimize(HERE / "optimize-layout.toml")
    flexible = dataclasses.replace(
        spec, name="lee1999-layout-flexible",
        fixed=spec.fixed + (("bed.model", "flexible"),))
    for tag, s in (("rigid", spec), ("flexible", flexible)):
        out = HERE / f"optimize-out-{tag}"
        t0, c0 = time.perf_counter(), time.process_time()
        opt = flexbed.optimize(s, workers=2, output=out)
        print(f"{tag} bed: {'feasible' if opt.feasible else 'NOT feasible'}, objective "
              f"{opt.objective:.6f}, {opt.evaluations} evaluations ({opt.reused} reused), "
              f"optimisation {opt.wall_time:.1f} s, call {time.perf_counter() - t0:.1f} s wall "
              f"({time.process_time() - c0:.1f} s CPU in this process)")
        for path, value in opt.values.items():
            print(f"    {path} = {value:.6g}")
        for name in ("convergence", "transmissibility"):
            if (out / f"{name}.png").is_file():
                shutil.copyfile(out / f"{name}.png", HERE / f"optimize-{name}-{tag}.png")


if __name__ == "__main__":
    main()

"""Worked example of docs/optimize.md: the eight equipment mounts of the
reference bed optimised for decoupling, frequency placement and static
deflection, with the bed rigid and then flexible, on one local Dask
cluster of two workers.

    python docs/optimize.py [FOLDER] [--max-evaluations N]

writes FOLDER/optimize-out-{rigid,flexible}/ (default FOLDER: ``docs``,
the page's own runs; its figures come from the full budget of the layout
file, 600 evaluations a bed, several minutes). Each folder gets the log
(``evaluations.csv``; a re-run reuses it), the optimum as a scene file,
``comparison.md`` (the before/after tables) and the plots; the
convergence and transmissibility plots are copied to
``FOLDER/optimize-*.png``. The layout file is ``docs/optimize-layout.toml``.
``--max-evaluations N`` stops each run after N evaluations (the tests run
the example so, in seconds).
"""

from __future__ import annotations

import argparse
import dataclasses
import shutil
import time
from pathlib import Path

import flexbed
from flexbed.optimization.spec import read_optimize
from flexbed.study.engine import cluster_client

HERE = Path(__file__).resolve().parent


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", nargs="?", type=Path, default=HERE)
    parser.add_argument("--max-evaluations", type=int, default=None)
    args = parser.parse_args(argv)
    spec = read_optimize(HERE / "optimize-layout.toml")
    if args.max_evaluations is not None:
        spec = dataclasses.replace(spec, max_evaluations=args.max_evaluations)
    flexible = dataclasses.replace(
        spec, name="lee1999-layout-flexible",
        fixed=spec.fixed + (("bed.model", "flexible"),))
    with cluster_client(workers=2) as client:              # one local cluster for both runs
        for tag, s in (("rigid", spec), ("flexible", flexible)):
            out = args.folder / f"optimize-out-{tag}"
            t0, c0 = time.perf_counter(), time.process_time()
            opt = flexbed.optimize(s, client, output=out)
            print(f"{tag} bed: {'feasible' if opt.feasible else 'NOT feasible'}, objective "
                  f"{opt.objective:.6f}, {opt.evaluations} evaluations ({opt.reused} reused), "
                  f"optimisation {opt.wall_time:.1f} s, call {time.perf_counter() - t0:.1f} s "
                  f"wall ({time.process_time() - c0:.1f} s CPU in this process)")
            for path, value in opt.values.items():
                print(f"    {path} = {value:.6g}")
            for name in ("convergence", "transmissibility"):
                if (out / f"{name}.png").is_file():
                    shutil.copyfile(out / f"{name}.png",
                                    args.folder / f"optimize-{name}-{tag}.png")


if __name__ == "__main__":
    main()

"""``flexbed compare [SCENE] [-o DIR] [--integrator NAME] [--t-end T] [--force]``:
the scene with a rigid bed, a flexible bed (α = β = 0) and a damped flexible
bed (the scene's damping), compared per piece of equipment, with plots (the
paper's Figs. 10–12); and the verdict's figures (peak g per body, stroke used
and peak force per mount, points of interest relative to their bodies,
clearances, PASS/FAIL) per case, with a plot per point of interest and axis
of its motion relative to its ``relative_to`` body."""

from __future__ import annotations

import argparse
import math
import time
from dataclasses import replace
from pathlib import Path

from flexbed.commands.arguments import add_scene_arg, number, file_name
from flexbed.analyses.compare import (CASES, LABELS, comparison_rows, csv_table, markdown_table,
                                      relative_vertical, run_case)
from flexbed.analyses.compare_verdict import verdict_csv, verdict_markdown, verdict_rows
from flexbed.files.destination import make_folder, write_text
from flexbed.errors import InputError
from flexbed.files.elastomer import time_run_scene
from flexbed.files.scene import SceneFile, load_scene
from flexbed.plots.runs import plot_responses, plot_series
from flexbed.stages.modes import ensure_modes


def add_solver_args(parser: argparse.ArgumentParser) -> None:
    """``--integrator`` and ``--t-end``, as on ``flexbed simulate``."""
    from flexbed.dynamics.integrate import METHODS
    parser.add_argument("--integrator", choices=METHODS, default=None,
                        help="time integrator of every run (default: the scene's [solver] "
                             "integrator)")
    parser.add_argument("--t-end", type=number, default=None, metavar="T",
                        help="end time of every run [s] (default: the scene's [solver] t_end)")


def with_solver_options(sf: SceneFile, integrator: str | None, t_end: float | None) -> SceneFile:
    """The scene with ``--integrator`` and ``--t-end`` applied to its
    ``[solver]`` (None keeps the scene's); InputError on a bad value."""
    if t_end is not None and not (math.isfinite(t_end) and t_end > 0):
        raise InputError(f"option: --t-end = {t_end!r} must be > 0 s")
    changes = {k: v for k, v in (("integrator", integrator), ("t_end", t_end)) if v is not None}
    if not changes:
        return sf
    solver = replace(sf.solver, **changes)
    try:
        solver.settings()
    except ValueError as exc:
        raise InputError(f"option: {exc}") from None
    return replace(sf, solver=solver)


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("Run the scene with a rigid, a flexible and a damped flexible bed "
                          "and compare the equipment's motion.")
    add_scene_arg(parser)
    parser.add_argument("-o", "--output", type=file_name, default="flexbed-compare", metavar="DIR",
                        help="output folder (default: ./flexbed-compare)")
    add_solver_args(parser)
    parser.add_argument("--force", action="store_true", help="recompute the modes file")


def compare_scene(sf: SceneFile, out: Path, *, force: bool = False, log=print) -> dict:
    """Run the three cases into ``out``; return the rows and the files written."""
    import numpy as np

    make_folder(out)
    name = sf.output_name
    data, reused = ensure_modes(sf, out / f"{name}-modes.h5", force=force,
                                log=lambda m: log(f"  {m}"))
    log(f"  modes: {'reused' if reused else 'computed'} {data.path.name}")
    runs = {case: run_case(sf, data, case, out / f"{name}-{case}.h5", log=log)
            for case in CASES}
    bodies = list(range(len(sf.scene.bodies)))
    bed = sf.bed.body or sf.scene.bodies[1].name
    names = [b.name for b in sf.scene.bodies]
    equipment = [i for i in bodies[1:] if names[i] != bed]
    rows = comparison_rows(runs, names, equipment)
    files = []
    table = markdown_table(rows)
    write_text(out / f"{name}-compare.csv", csv_table(rows))
    files.append(out / f"{name}-compare.csv")
    for i in equipment:
        curves = {c: (runs[c].t, 1e3 * relative_vertical(runs[c], i)) for c in CASES}
        safe = names[i].replace(" ", "_")
        files.append(plot_responses(out / f"{name}-{safe}-z.png",
                                    f"{names[i]}: vertical motion relative to the base",
                                    curves, LABELS, "z − z_base − static [mm]"))
    verdicts = verdict_rows({c: runs[c].verdict for c in CASES}, CASES)
    write_text(out / f"{name}-compare-verdict.csv", verdict_csv(verdicts, CASES))
    files.append(out / f"{name}-compare-verdict.csv")
    for point in runs["rigid"].relative:
        curves = {c: (runs[c].t, 1e3 * (runs[c].relative[point] - runs[c].relative[point][0]))
                  for c in CASES}
        safe = point.replace(" ", "_")
        reach = np.max([np.abs(d).max(axis=0) for _, d in curves.values()], axis=0)   # (3,)
        for k, axis in enumerate("xyz"):
            if reach[k] <= RELATIVE_FLOOR * reach.max():
                continue        # no motion along this axis but round-off: nothing to draw
            files.append(plot_responses(
                out / f"{name}-{safe}-relative-{axis}.png",
                f"{point}: {axis} motion relative to {_relative_to(sf, point)}",
                {c: (t, d[:, k]) for c, (t, d) in curves.items()}, LABELS,
                f"{axis} − {axis}(0), {_relative_to(sf, point)}'s frame [mm]"))
    rigid = runs["rigid"]
    files.append(plot_series(out / f"{name}-base-acceleration.png",
                             "base: vertical acceleration", rigid.t,
                             rigid.base_acceleration[:, 2], "z acceleration [m/s²]"))
    return {"rows": rows, "table": table, "runs": runs, "files": files, "modes": data,
            "verdict_rows": verdicts,
            "verdict_table": verdict_markdown(verdicts, CASES, LABELS)}


#: an axis of a point's relative motion is drawn when its largest motion
#: reaches this share of the largest axis's (the reference scene's x motion
#: is 1e-14 of its z, round-off of a symmetric scene)
RELATIVE_FLOOR = 1e-9


def _relative_to(sf: SceneFile, point: str) -> str:
    return next(p.relative_to for p in sf.points if p.name == point)


def run(args: argparse.Namespace) -> int:
    t0 = time.perf_counter()
    sf = with_solver_options(load_scene(args.scene), args.integrator, args.t_end)
    sf = time_run_scene(sf)
    out = Path(args.output)
    print(f"compare '{sf.scene.name}': rigid, flexible and damped flexible bed, "
          f"0-{sf.solver.t_end:g} s, {sf.solver.integrator} -> {out}/")
    res = compare_scene(sf, out, force=args.force)
    print(res["table"])
    print("\nThe verdict's figures (against the scene's limits, if it gives any):")
    print(res["verdict_table"])
    for f in res["files"]:
        print(f"wrote {f}")
    print(f"done in {time.perf_counter() - t0:.1f} s")
    return 0

"""``flexbed run [SCENE] [-o DIR] [--integrator NAME] [--t-end T] [--force]``:
the whole pipeline on one scene.

Stages, each with a progress line: the bed's modes (reused when the folder
already holds a matching modes file) and their shapes for ParaView → the
static equilibrium (the paper's Table 2, rigid bed) → the simulations with a
rigid, a flexible and a damped flexible bed and their comparison (tables
and plots) → the scene's points of interest (CSV) → a summary in Markdown.
Everything goes into one folder.
"""

from __future__ import annotations

import argparse
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from flexbed.commands.arguments import add_scene_arg, file_name
from flexbed.analyses.compare import LABELS
from flexbed.analyses.points import Run, bed_motion, motion_csv, motion_table, mount_peaks_csv
from flexbed.analyses.summary import modes_csv, summary_markdown
from flexbed.commands.compare import add_solver_args, compare_scene, with_solver_options
from flexbed.commands.modes import auto_line, modes_table
from flexbed.commands.static import equilibrium_csv, equilibrium_table
from flexbed.dynamics.precompile import compile_in_parallel, likely_steppers
from flexbed.dynamics.statics import solve_statics
from flexbed.files.destination import make_folder, write_text
from flexbed.errors import NumericalError
from flexbed.fem.export import write_modes_vtu
from flexbed.files.modes import ModesData
from flexbed.files.results import write_equilibrium
from flexbed.files.elastomer import time_run_scene
from flexbed.files.scene import load_scene
from flexbed.files.xdmf import write_bed_motion
from flexbed.plots.runs import plot_mount_forces
from flexbed.stages.modes import ensure_modes
from flexbed.stages.plausibility import check_equilibrium, mount_csv, mount_statics, mount_table
from flexbed.stages.simulation import checked
from flexbed.stages.system import compile_scene
from flexbed.words import count

STAGES = 5
FRAME_DT = 0.01        # s between frames of the bed's motion for ParaView


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = "Run the pipeline on a scene and write everything into one folder."
    add_scene_arg(parser)
    parser.add_argument("-o", "--output", type=file_name, default="flexbed-out", metavar="DIR",
                        help="output folder (default: ./flexbed-out)")
    add_solver_args(parser)
    parser.add_argument("--force", action="store_true", help="recompute the modes file")


def run(args: argparse.Namespace) -> int:
    t_start = time.perf_counter()
    sf = with_solver_options(load_scene(args.scene), args.integrator, args.t_end)
    sf = time_run_scene(sf)
    out = Path(args.output)
    make_folder(out)
    name = sf.output_name
    print(f"scene '{name}' ({sf.source}) -> {out}/")

    t0 = time.perf_counter()
    data, reused = ensure_modes(sf, out / f"{name}-modes.h5", force=args.force,
                                log=lambda m: print(f"  {m}"))
    vtu = write_modes_vtu(out / f"{name}-modes.vtu", data.nodes, data.cells,
                          data.translation, data.rotation, data.frequency)
    print(f"[1/{STAGES}] modes: {'reused' if reused else 'computed'} "
          f"{count(data.n_modes, 'elastic mode')} ({time.perf_counter() - t0:.2f} s) -> "
          f"{data.path.name}, {vtu.name}")
    if sf.bed.auto:
        print(f"  {auto_line(sf.bed)}")
    print(modes_table(data))

    t0 = time.perf_counter()
    rigid_sf = replace(sf, bed=replace(sf.bed, model="rigid"))
    system = compile_scene(rigid_sf)
    compile_in_parallel(likely_steppers(sf.solver.integrator))   # a first run (docs/first-run.md)
    eq = solve_statics(system, tol=sf.solver.static_tol)
    if not eq.success:
        raise NumericalError(f"{sf.source.name}: {eq.message}")
    eq = checked(system, eq)
    check_equilibrium(sf, system, eq)
    if eq.instability is not None:
        print(f"flexbed run: warning: {sf.source.name}: {eq.instability.line()}",
              file=sys.stderr)
    eq_path = write_equilibrium(out / f"{name}-equilibrium.h5", rigid_sf, system, eq)
    table2 = equilibrium_table(system, eq.y)
    statics = mount_statics(system, eq.y)
    print(f"[2/{STAGES}] static equilibrium (rigid bed): "
          f"{count(eq.iterations, 'Newton iteration')}, "
          f"residual {eq.residual:.1e} ({time.perf_counter() - t0:.2f} s) -> "
          f"{Path(eq_path).name}")
    print(table2)
    print(mount_table(statics))

    t0 = time.perf_counter()
    print(f"[3/{STAGES}] simulations: rigid, flexible and damped flexible bed, "
          f"0-{sf.solver.t_end:g} s, {sf.solver.integrator}")
    res = compare_scene(sf, out, log=print)
    print(f"[3/{STAGES}] simulations done ({time.perf_counter() - t0:.2f} s)")
    print(res["table"])

    # CSV of the stages' tables; per run the mount forces and the bed's motion for ParaView
    write_text(out / f"{name}-modes.csv", modes_csv(data))
    write_text(out / f"{name}-equilibrium.csv", equilibrium_csv(system, eq.y))
    write_text(out / f"{name}-static-mounts.csv", mount_csv(statics))
    res["files"] += [out / f"{name}-modes.csv", out / f"{name}-equilibrium.csv",
                     out / f"{name}-static-mounts.csv"]
    for case, cr in res["runs"].items():
        res["files"] += _run_files(out, name, case, Run(cr.path), data)

    t0 = time.perf_counter()
    point_tables = []
    if sf.points:
        for case, cr in res["runs"].items():
            files, table = _point_files(out, name, case, Run(cr.path))
            res["files"] += files
            point_tables.append((case, table))
        print(f"[4/{STAGES}] points of interest: {count(len(sf.points), 'point')} x "
              f"{count(len(res['runs']), 'run')} ({time.perf_counter() - t0:.2f} s) -> CSV")
    else:
        print(f"[4/{STAGES}] points of interest: none in the scene")

    summary = out / f"{name}-summary.md"
    files = [data.path, vtu, Path(eq_path)] + [r.path for r in res["runs"].values()] + \
        res["files"]
    write_text(summary, summary_markdown(
        name, sf.source, modes_table=modes_table(data), equilibrium_table=table2,
        mount_table=mount_table(statics),
        t_end=sf.solver.t_end, integrator=sf.solver.integrator, comparison_table=res["table"],
        point_tables=point_tables, files=files))
    print(f"[5/{STAGES}] summary -> {summary.name}")
    print(f"done in {time.perf_counter() - t_start:.1f} s; outputs in {out}/")
    return 0


def _run_files(out: Path, name: str, case: str, r: Run, data: ModesData) -> list[Path]:
    """One compared run's mount forces (peaks as CSV, a plot) and, with the
    bed flexible, the bed's motion for ParaView; returns the paths."""
    files = []
    if r.mount_names:
        f = out / f"{name}-{case}-mounts.csv"
        write_text(f, mount_peaks_csv(r))
        files += [f, plot_mount_forces(
            out / f"{name}-{case}-mount-forces.png", f"mount forces ({LABELS[case]})",
            r.t, r.mounts["force"], r.mount_names, r.mount_body_i, r.mount_body_j)]
    if case != "rigid":
        pos, defl = bed_motion(r, data.nodes, r.translation)
        stride = max(1, int(round(FRAME_DT / float(np.mean(np.diff(r.t))))))
        frames = slice(None, None, stride)
        files.append(write_bed_motion(
            out / f"{name}-{case}-bed.xdmf", pos[0], data.cells, r.t[frames],
            (pos - pos[0])[frames], defl[frames]))
    return files


def _point_files(out: Path, name: str, case: str, r: Run) -> tuple[list[Path], str]:
    """The scene's points of interest in one compared run, absolute and
    relative to their ``relative_to`` body: a CSV each; returns the paths and
    the table of their peaks."""
    motions = []
    for p in r.scene_points:
        motions.append(r.absolute(p))
        if p.relative_to:
            motions.append(r.relative(p, p.relative_to))
    files = []
    for m in motions:
        suffix = "" if m.frame == "inertial" else f"-rel-{m.frame.replace(' ', '_')}"
        f = out / f"{name}-{case}-point-{m.point.name.replace(' ', '_')}{suffix}.csv"
        write_text(f, motion_csv(r.t, m))
        files.append(f)
    return files, motion_table(motions)

"""``flexbed run [SCENE] [-o DIR]``: the whole pipeline on one scene.

Stages: the bed's modes (reused when the folder already holds a matching
modes file) with their shapes for ParaView → the static equilibrium → the
simulation with a rigid bed. Every file goes into one folder.
"""

from __future__ import annotations

import argparse
import time
from dataclasses import replace
from pathlib import Path

from dynamics.integrate import integrate
from dynamics.statics import solve_statics
from fem.export import write_modes_vtu

from .cmd_modes import ensure_modes, modes_table
from .cmd_static import compile_scene, equilibrium_table
from .errors import NumericalError
from .results_file import write_equilibrium, write_results
from .scene_file import load_scene

STAGES = 3


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = "Run the pipeline on a scene and write everything into one folder."
    parser.add_argument("scene", nargs="?", default=None,
                        help="scene file (TOML); default: the built-in reference scene")
    parser.add_argument("-o", "--output", default="flexbed-out", metavar="DIR",
                        help="output folder (default: ./flexbed-out)")
    parser.add_argument("--force", action="store_true", help="recompute cached stages")


def run(args: argparse.Namespace) -> int:
    t_start = time.perf_counter()
    sf = load_scene(args.scene)
    out = Path(args.output)
    out.mkdir(parents=True, exist_ok=True)
    name = sf.scene.name
    print(f"scene '{name}' ({sf.source}) -> {out}/")

    t0 = time.perf_counter()
    modes_path = out / f"{name}-modes.h5"
    data, reused = ensure_modes(sf, modes_path, force=args.force,
                                log=lambda m: print(f"  {m}"))
    vtu = write_modes_vtu(out / f"{name}-modes.vtu", data.nodes, data.cells,
                          data.translation, data.rotation, data.frequency)
    print(f"[1/{STAGES}] modes: {'reused' if reused else 'computed'} {data.n_modes} elastic "
          f"modes ({time.perf_counter() - t0:.2f} s) -> {modes_path.name}, {vtu.name}")
    print(modes_table(data))

    t0 = time.perf_counter()
    rigid_sf = replace(sf, bed=replace(sf.bed, model="rigid"))
    system = compile_scene(rigid_sf)
    eq = solve_statics(system, tol=sf.solver.static_tol)
    if not eq.success:
        raise NumericalError(f"{sf.source.name}: {eq.message}")
    eq_path = write_equilibrium(out / f"{name}-equilibrium.h5", sf, system, eq)
    print(f"[2/{STAGES}] static equilibrium: {eq.iterations} Newton iterations, residual "
          f"{eq.residual:.1e} ({time.perf_counter() - t0:.2f} s) -> {Path(eq_path).name}")
    print(equilibrium_table(system, eq.y))

    t0 = time.perf_counter()
    settings = sf.solver.settings()
    y0 = eq.y if sf.solver.start == "equilibrium" else system.initial_state()
    result = integrate(system, y0, settings)
    res_path = out / f"{name}-rigid.h5"
    write_results(res_path, rigid_sf, system, result, start=sf.solver.start,
                  equilibrium=eq if sf.solver.start == "equilibrium" else None)
    st = result.stats
    print(f"[3/{STAGES}] simulate (rigid bed, {settings.method}): 0-{result.t[-1]:g} s, "
          f"{st.steps} steps, {st.rhs_evaluations} right-hand sides "
          f"({time.perf_counter() - t0:.2f} s) -> {res_path.name}")
    if not result.complete:
        raise NumericalError(f"{result.message}; the samples up to t = {result.t_reached:.6g} s "
                             f"are in {res_path} (marked incomplete)")
    print(f"done in {time.perf_counter() - t_start:.2f} s; outputs in {out}/")
    return 0

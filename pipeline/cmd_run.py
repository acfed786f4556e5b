"""``flexbed run [SCENE] [-o DIR]``: the whole pipeline on one scene.

Stages so far: the bed's modes (reused when the folder already holds a
matching modes file) with the mode shapes for ParaView.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from fem.export import write_modes_vtu

from .cmd_modes import ensure_modes, modes_table
from .scene_file import load_scene


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
    print(f"[1/1] modes: {'reused' if reused else 'computed'} {data.n_modes} elastic modes "
          f"({time.perf_counter() - t0:.2f} s) -> {modes_path.name}, {vtu.name}")
    print(modes_table(data))
    print(f"done in {time.perf_counter() - t_start:.2f} s; outputs in {out}/")
    return 0

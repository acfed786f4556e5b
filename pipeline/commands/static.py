"""``flexbed static [SCENE] [-o FILE]``: the static equilibrium (paper Table 2).

Prints positions and roll/pitch/yaw per body, the Newton–Raphson iterations
and residual, the mounts' static loads [N] and deflections [mm] per
direction, and writes the equilibrium file that ``flexbed simulate
--equilibrium FILE`` reads. An implausible equilibrium (exit 2) or an
unstable one (exit 1, unless ``--allow-unstable``) is refused before
anything is written (:mod:`flexbed.stages.plausibility`).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

from flexbed.commands.arguments import add_scene_arg, number, file_name
from flexbed.dynamics.rotation import angles_from_p
from flexbed.dynamics.statics import solve_statics
from flexbed.dynamics.system import System

from flexbed.files.destination import check_destination, refuse_inputs
from flexbed.errors import InputError, NumericalError
from flexbed.stages.system import compile_scene
from flexbed.files.results import write_equilibrium
from flexbed.files.scene import load_scene
from flexbed.interrupts import Interrupted, held, kept
from flexbed.stages.plausibility import check_equilibrium, mount_statics, mount_table
from flexbed.stages.simulation import checked

__all__ = ["add_args", "run", "equilibrium_table"]


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("Static equilibrium of the mount system by Newton–Raphson "
                          "(base held), printed as the paper's Table 2 and written to a file.")
    add_scene_arg(parser)
    parser.add_argument("-o", "--output", type=file_name, default=None, metavar="FILE",
                        help="equilibrium file to write "
                             "(default: <scene file stem>-equilibrium.h5)")
    parser.add_argument("--tol", type=number, default=None, metavar="TOL",
                        help="Newton–Raphson tolerance (default: the scene's static_tol)")
    add_modes_file_arg(parser)
    parser.add_argument("--allow-unstable", action="store_true",
                        help="write an unstable equilibrium (a warning) instead of stopping "
                             "(exit 1); as [solver] allow_unstable = true")


def add_modes_file_arg(parser: argparse.ArgumentParser) -> None:
    """The option that says where a flexible bed's modes file is."""
    parser.add_argument("--modes-file", default=None, metavar="FILE",
                        help="modes file of a flexible bed (default: where 'flexbed modes' "
                             "writes it for this scene)")


def equilibrium_table(system: System, y: np.ndarray) -> str:
    """Table 2: x, y, z [m], roll, pitch, yaw [deg] per body."""
    pos, p = system.poses(y)
    ang = np.degrees(angles_from_p(p))
    names = [b.name for b in system.scene.bodies]
    w = max(4, max(len(n) for n in names))
    lines = [f"{'body':>4}  {'name':<{w}}  {'x [m]':>14}  {'y [m]':>14}  {'z [m]':>14}  "
             f"{'roll [deg]':>11}  {'pitch [deg]':>11}  {'yaw [deg]':>11}"]
    for i, n in enumerate(names):
        x, yy, z = (float(v) + 0.0 for v in np.round(pos[i], 12))
        r, pi, ya = (float(v) + 0.0 for v in np.round(ang[i], 9))
        lines.append(f"{i + 1:>4}  {n:<{w}}  {x:>14.9f}  {yy:>14.9f}  {z:>14.9f}  "
                     f"{r:>11.6f}  {pi:>11.6f}  {ya:>11.6f}")
    return "\n".join(lines)


def equilibrium_csv(system: System, y: np.ndarray) -> str:
    """Table 2 as CSV: body, name, x, y, z [m], roll, pitch, yaw [deg]."""
    lines = ["body,name,x_m,y_m,z_m,roll_deg,pitch_deg,yaw_deg"]
    for row in equilibrium_table(system, y).splitlines()[1:]:
        parts = row.split()
        body, rest = parts[0], parts[1:]
        name = " ".join(rest[:-6])
        lines.append(",".join([body, name] + rest[-6:]))
    return "\n".join(lines) + "\n"


def run(args: argparse.Namespace) -> int:
    sf = load_scene(args.scene)
    out = Path(args.output) if args.output else Path(f"{sf.output_name}-equilibrium.h5")
    check_destination(out)          # refused before any work, not after
    refuse_inputs(out, sf.source, args.modes_file)
    system = compile_scene(sf, args.modes_file)
    tol = sf.solver.static_tol if args.tol is None else args.tol
    if not (math.isfinite(tol) and tol > 0):
        raise InputError(f"--tol = {tol!r} must be a finite number > 0")
    eq = solve_statics(system, tol=tol, sag=sf.bed.static_sag)
    if not eq.success:
        raise NumericalError(f"{sf.source.name}: {eq.message}")
    eq = checked(system, eq)
    check_equilibrium(sf, system, eq, allow_unstable=args.allow_unstable or None)
    if eq.instability is not None:
        print(f"flexbed static: warning: {sf.source.name}: {eq.instability.line()}",
              file=sys.stderr)
    print(f"Static equilibrium of '{sf.scene.name}' (Newton–Raphson, tolerance {tol:g}, "
          f"base held)")
    print(equilibrium_table(system, eq.y))
    print(f"iterations: {eq.iterations}   residual: {eq.residual:.3e} (scaled by weight)   "
          f"last step: {eq.step:.3e}   right-hand sides: {eq.rhs_evaluations}")
    print("Mounts at rest (directions u1, u2, u3 of each mount; extension positive):")
    print(mount_table(mount_statics(system, eq.y)))
    with held() as pending:         # the equilibrium found is written whole
        write_equilibrium(out, sf, system, eq)
    print(f"wrote {out}")
    if pending:
        raise kept(Interrupted(pending[0]), f"after the equilibrium was found; it is in {out}")
    return 0

"""``flexbed modes [SCENE] [-o FILE] [--modes N | --fmax HZ] [--vtu DIR] [--force] [--show FILE]``.

Computes the common bed's free–free modes and modal invariants and writes
the modes file, or reuses it when it was made from the same plate inputs
(hash match) and holds the modes asked for.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

from flexbed.commands.arguments import add_scene_arg, number, file_name
from flexbed.files.bed_section import AUTO_TOLERANCE, check_mode_count
from flexbed.files.destination import check_destination, refuse_inputs
from flexbed.errors import FlexbedWarning, InputError
from flexbed.files.modes import ModesData, read_modes_file
from flexbed.files.scene import load_scene
from flexbed.stages.modes import default_modes_path, ensure_modes, require_bed
from flexbed.words import count


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("Free-free modes and modal invariants of the common bed "
                          "(scikit-fem Kirchhoff plate), written to the modes file.")
    add_scene_arg(parser)
    parser.add_argument("-o", "--output", type=file_name, default=None, metavar="FILE",
                        help="modes file to write (default: the scene's modes_file, "
                             "else <scene file stem>-modes.h5 in the current folder)")
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--modes", type=int, default=None, metavar="N",
                       help="number of elastic modes to keep (default: the scene's)")
    group.add_argument("--fmax", type=number, default=None, metavar="HZ",
                       help="keep every elastic mode below this frequency [Hz]")
    parser.add_argument("--vtu", default=None, metavar="DIR",
                        help="also write the mode shapes as DIR/<name>-modes.vtu for ParaView")
    parser.add_argument("--force", action="store_true",
                        help="recompute even when the file matches the inputs")
    parser.add_argument("--show", default=None, metavar="FILE",
                        help="only read and check an existing modes file and print its table")


def auto_line(bed) -> str:
    """One line saying how ``modes = "auto"`` chose its cut-off."""
    f_cut, f_in, f_sus = bed.auto
    return (f"modes = \"auto\": inputs up to {f_in:.3g} Hz, suspension up to {f_sus:.3g} Hz; "
            f"keeping the modes below {bed.auto_factor:g} x {max(f_in, f_sus):.3g} = "
            f"{f_cut:.3g} Hz (at least one)")


def modes_table(data: ModesData) -> str:
    """The frequency table printed by the command (with each mode's
    estimated discretisation error when the file has one)."""
    acc = data.accuracy
    theory = acc is not None and acc.theory_error is not None
    lines = [f"{'mode':>4}  {'f [Hz]':>10}  {'shape':<16}  sym" + ("  err [%]" if acc else "")
             + ("  theory [%]" if theory else ""),
             f"{'-' * 4}  {'-' * 10}  {'-' * 16}  ---" + ("  -------" if acc else "")
             + ("  ----------" if theory else "")]

    def cell(e: float, width: int) -> str:
        return f"  {100 * e:>+{width}.3f}" if e == e else f"  {'-':>{width}}"

    for k, (f, label, sym) in enumerate(zip(data.frequency, data.labels, data.symmetry)):
        err = cell(acc.error[k], 7) if acc is not None else ""
        err += cell(acc.theory_error[k], 10) if theory else ""
        lines.append(f"{k + 1:>4}  {f:>10.4f}  {label:<16}  {sym}{err}")
    if acc is not None:
        lines.append(acc.summary())
    return "\n".join(lines)


def print_summary(data: ModesData) -> None:
    """Print the plate, its solid mass properties and the frequency table."""
    p = data.plate
    print(f"bed: {p.length_x:g} x {p.length_y:g} x {p.thickness:g} m, E = {p.young:g} Pa, "
          f"nu = {p.poisson:g}, rho = {p.density:g} kg/m^3, "
          + (f"{p.nx} x {p.ny} elements " if p.is_rectangle
             else f"{data.cells.shape[0]} elements ("
             + ("element_size = \"auto\"" if p.auto_mesh else
                "outline, cut-outs, zones or mesh file") + ") ")
          + f"({data.nodes.shape[0]} nodes)"
          + (", Mindlin shell (MITC4)" if p.theory == "mindlin" else ""))
    inv = data.invariants
    print(f"mass {inv.mass:.6g} kg; inertia Jxx, Jyy, Jzz = {inv.inertia[0, 0]:.6g}, "
          f"{inv.inertia[1, 1]:.6g}, {inv.inertia[2, 2]:.6g} kg m^2 "
          + ("(from the model)" if inv.model_mass else "(solid plate)"))
    print(modes_table(data))
    acc = data.accuracy
    if acc is not None and p.theory == "mindlin" and not p.auto_mesh and acc.worst > AUTO_TOLERANCE:
        warnings.warn(f"the estimated error reaches {100 * acc.worst:.2g} % on this mesh; "
                      f"element_size = \"auto\" chooses the mesh for a tolerance "
                      f"(mesh_tolerance, default {100 * AUTO_TOLERANCE:g} %)", FlexbedWarning,
                      stacklevel=2)
    if data.n_modes and abs(data.next_frequency - data.frequency[-1]) <= 1e-6 * data.next_frequency:
        warnings.warn(f"mode {data.n_modes} and the first mode left out share the frequency "
                      f"{data.next_frequency:.4f} Hz; keep one more mode so the pair stays "
                      f"whole", FlexbedWarning, stacklevel=2)


def run(args: argparse.Namespace) -> int:
    if args.modes is not None and args.modes < 1:
        raise InputError(f"--modes {args.modes}: at least one elastic mode is needed")
    if args.fmax is not None and not args.fmax > 0:
        raise InputError(f"--fmax {args.fmax}: must be > 0 Hz")
    if args.show:
        data = read_modes_file(args.show)
        print_summary(data)
        print(f"{data.path}: {count(data.n_modes, 'elastic mode')}; made by {data.creator} "
              f"on {data.created}; input hash {data.input_hash[:12]}")
        return 0
    sf = load_scene(args.scene)
    path = Path(args.output) if args.output else default_modes_path(sf)
    check_destination(path)          # refused before any work, not after
    refuse_inputs(path, sf.source)
    require_bed(sf)
    if args.modes is not None:
        check_mode_count(sf.bed.plate, args.modes, f"{sf.source.name}: --modes {args.modes}")
    t0 = time.perf_counter()
    data, reused = ensure_modes(sf, path, n_modes=args.modes, fmax=args.fmax, force=args.force,
                                log=lambda m: print(m, file=sys.stderr))
    elapsed = time.perf_counter() - t0
    print_summary(data)
    if sf.bed.auto and args.modes is None and args.fmax is None:
        print(auto_line(sf.bed))
    asked = (f"{args.modes} asked" if args.modes else
             f"all below {args.fmax:g} Hz asked" if args.fmax else "")
    held = count(data.n_modes, "elastic mode") + (f", {asked}" if asked else "")
    print(f"{'reused' if reused else 'wrote'} {path} ({held}; {elapsed:.2f} s)")
    if args.vtu:
        from flexbed.fem.export import write_modes_vtu      # meshio
        vtu = write_modes_vtu(Path(args.vtu) / f"{sf.output_name}-modes.vtu", data.nodes,
                              data.cells, data.translation, data.rotation, data.frequency)
        print(f"wrote {vtu}")
    return 0

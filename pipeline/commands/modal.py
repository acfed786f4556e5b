"""``flexbed modal [SCENE]``: the mounted system's modes about its static
equilibrium (base held): natural frequencies, damping ratios, the kinetic
energy (decoupling) table, strain energy per mount, modal effective masses.

Writes ``PREFIX.h5`` (``flexbed.modal``), ``PREFIX-modes.csv``,
``PREFIX-energy.csv``, ``PREFIX-strain.csv``, ``PREFIX-effective-mass.csv``,
``PREFIX-energy.png`` and the mode shapes for ParaView,
``PREFIX-shapes.xdmf`` over ``PREFIX-shapes.h5`` (``flexbed.mode_shapes``)
(PREFIX default ``<scene stem>-modal``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from flexbed.commands.arguments import add_scene_arg, file_name
from flexbed.analyses.modal import effective_mass_text, energy_text, modes_text
from flexbed.commands.static import add_modes_file_arg
from flexbed.files.destination import check_destination
from flexbed.files.scene import load_scene
from flexbed.words import count

__all__ = ["add_args", "run", "load_mounted", "outputs"]


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("Modes of the mounted system about its static equilibrium (base "
                          "held): frequencies, damping ratios, kinetic energy decoupling "
                          "table, strain energy per mount, effective masses.")
    add_scene_arg(parser)
    parser.add_argument("-o", "--output", type=file_name, default=None, metavar="PREFIX",
                        help="prefix of the files written (default: <scene stem>-modal)")
    parser.add_argument("--equilibrium", default=None, metavar="FILE",
                        help="equilibrium file from 'flexbed static' (default: solve it here)")
    parser.add_argument("--no-plots", action="store_true", help="write no PNG")
    add_modes_file_arg(parser)


def load_mounted(args, sf):
    """The scene's Mounted (modes file and equilibrium file from the options)."""
    from flexbed.analyses.modal import mounted
    from flexbed.stages.flexible_bed import load_modes_for
    from flexbed.stages.modes import default_modes_path
    from flexbed.stages.system import compile_scene
    data = None
    if sf.bed.flexible:
        data = load_modes_for(sf, args.modes_file or default_modes_path(sf))
    system = compile_scene(sf, modes=data)
    return mounted(sf, system, equilibrium_file=args.equilibrium, bed_modes=data)


def outputs(prefix: str, plots: bool) -> dict[str, Path]:
    names = {"h5": ".h5", "modes": "-modes.csv", "energy": "-energy.csv",
             "strain": "-strain.csv", "mass": "-effective-mass.csv",
             "xdmf": "-shapes.xdmf", "shapes_h5": "-shapes.h5"}
    if plots:
        names["png"] = "-energy.png"
    return {k: check_destination(Path(prefix + v)) for k, v in names.items()}


def run(args: argparse.Namespace) -> int:
    from flexbed.analyses.modal import effective_mass_csv, energy_csv, modes_csv, strain_csv
    from flexbed.files.destination import write_text
    from flexbed.files.frequency import write_modal

    sf = load_scene(args.scene)
    out = outputs(args.output or f"{sf.output_name}-modal", not args.no_plots)
    mt = load_mounted(args, sf)
    ms, md = mt.ms, mt.modes
    names = [b.name for b in mt.system.scene.bodies]
    print(f"Modes of '{sf.scene.name}' about its static equilibrium ({mt.source}), base held: "
          f"{count(ms.n, 'coordinate')}, {'damped (complex modes)' if ms.damped else 'undamped'}")
    print(modes_text(ms, md))
    if md.overdamped_rates.size:
        print(f"overdamped (real roots, no modes): decay rates "
              f"{', '.join(f'{r:.4g}' for r in md.overdamped_rates)} 1/s")
    print("\nKinetic energy distribution [%] (the decoupling table):")
    print(energy_text(ms, md, names))
    print("\nModal effective mass, base translation (undamped modes):")
    print(effective_mass_text(md))
    print(f"\nsolve time: {mt.solve_time:.4f} s CPU (linearisation, "
          f"{count(ms.evaluations, 'right-hand side')}, and eigen-solution)")
    write_modal(out["h5"], sf, mt)
    write_text(out["modes"], modes_csv(md))
    write_text(out["energy"], energy_csv(ms, md))
    write_text(out["strain"], strain_csv([m.name for m in mt.system.scene.mounts], md))
    write_text(out["mass"], effective_mass_csv(md))
    from flexbed.analyses.mode_shapes import mode_shape_meshes
    from flexbed.files.mode_shapes import write_mode_shapes
    write_mode_shapes(out["xdmf"], mode_shape_meshes(sf, mt), md.frequency, md.damping_ratio)
    if "png" in out:
        from flexbed.plots.frequency import plot_energy
        plot_energy(out["png"], f"{sf.scene.name}: kinetic energy per mode", ms.labels,
                    md.frequency, md.energy)
    print("wrote " + ", ".join(str(p) for p in out.values()))
    return 0

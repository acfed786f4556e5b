"""``flexbed rsa [SCENE] --spectrum FILE``: the response-spectrum analysis
of a scene against a design spectrum file (:mod:`flexbed.files.spectrum`):
per base axis the spectrum gives, each mode's participation, effective
mass and spectral acceleration, and the peaks of the mount deflections and
forces, the points' accelerations and displacements relative to the base
and the base force, combined by NRL (closely spaced modes, within 10 %,
summed first), SRSS, CQC and ABS.

Writes ``PREFIX.h5`` (``flexbed.response_spectrum``) and ``PREFIX.csv``
(PREFIX default ``<scene stem>-rsa``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

from flexbed.commands.arguments import add_scene_arg, number, file_name
from flexbed.commands.static import add_modes_file_arg

__all__ = ["add_args", "run"]


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("Response-spectrum analysis against a design spectrum: modal "
                          "peaks of mounts, points and base force combined by NRL, SRSS, "
                          "CQC and ABS.")
    add_scene_arg(parser)
    parser.add_argument("--spectrum", required=True, metavar="FILE",
                        help="design spectrum file (TOML: damping, units, [x]/[y]/[z] tables "
                             "or tripartite levels)")
    parser.add_argument("--damping", type=number, default=None, metavar="ZETA",
                        help="damping ratio of the modes (must be the spectrum's; default: it)")
    parser.add_argument("--rule", default=None, metavar="RULE",
                        help="print only this combination: nrl, srss, cqc or abs "
                             "(all are written)")
    parser.add_argument("--max-frequency", type=number, default=None, metavar="HZ",
                        help="leave out the modes above this frequency [Hz]")
    parser.add_argument("-o", "--output", type=file_name, default=None, metavar="PREFIX",
                        help="prefix of the files written (default: <scene stem>-rsa)")
    parser.add_argument("--equilibrium", default=None, metavar="FILE",
                        help="equilibrium file from 'flexbed static' (default: solve it here)")
    add_modes_file_arg(parser)


def run(args: argparse.Namespace) -> int:
    import math

    from flexbed.analyses.response_spectrum import modal_text, response_spectrum, rsa_csv, \
        rsa_text
    from flexbed.commands.modal import load_mounted
    from flexbed.dynamics.frequency.response_spectrum import RULES
    from flexbed.errors import InputError
    from flexbed.files.destination import check_destination, write_text
    from flexbed.files.response_spectrum import write_rsa
    from flexbed.files.scene import load_scene
    from flexbed.files.spectrum import check_damping, read_spectrum

    if args.rule is not None and args.rule not in RULES:
        raise InputError(f"--rule {args.rule!r} is not a combination rule (one of "
                         f"{', '.join(RULES)})")
    if args.max_frequency is not None and not (math.isfinite(args.max_frequency)
                                               and args.max_frequency > 0):
        raise InputError(f"--max-frequency {args.max_frequency!r} must be a frequency > 0 "
                         f"[Hz]")
    spectrum = read_spectrum(args.spectrum)
    check_damping(spectrum, args.damping)
    sf = load_scene(args.scene)
    prefix = args.output or f"{sf.output_name}-rsa"
    h5 = check_destination(Path(prefix + ".h5"))
    csv = check_destination(Path(prefix + ".csv"))
    mt = load_mounted(args, sf)
    r = response_spectrum(sf, mt, spectrum, damping=args.damping,
                          max_frequency=args.max_frequency)
    print(f"Response-spectrum analysis of '{sf.scene.name}' against '{spectrum.name}' "
          f"(damping {r.damping:g}, {len(r.frequency)} modes, base held)")
    print(modal_text(r))
    print()
    text = rsa_text(r)
    if args.rule is not None:
        text = _one_rule(text, RULES.index(args.rule))
    print(text)
    print(f"\nNRL: modes within 10 % of a group's first mode summed absolutely first.\n"
          f"solve time: {1e3 * r.solve_time:.2f} ms CPU (the modes not included)")
    write_rsa(h5, sf, r)
    write_text(csv, rsa_csv(r))
    print(f"wrote {h5}, {csv}")
    return 0


def _one_rule(text: str, k: int) -> str:
    """The Markdown tables cut to the output column and rule ``k``'s."""
    out = []
    for line in text.splitlines():
        if line.startswith("|"):
            cells = line.strip("|").split("|")
            line = "|" + cells[0] + "|" + cells[1 + k] + "|"
        out.append(line)
    return "\n".join(out)

"""``flexbed frf [SCENE]``: transmissibility of the mounted system about its
static equilibrium: magnitude and phase from a base acceleration (or a
force on a body) to points of interest, to every mount's forces and to the
total force on the base, on a grid that resolves every resonance.
``--input 'load NAME'`` takes a scene's ``[[load]]`` (per N or N m) or
``[[unbalance]]`` (per newton of its rotating force) as the input.

Writes ``PREFIX.h5`` (``flexbed.frf``), ``PREFIX.csv``,
``PREFIX-bode.png`` (the points' accelerations along the input's axis) and
``PREFIX-forces.png`` (the force on the base)
(PREFIX default ``<scene stem>-frf``).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from flexbed.commands.arguments import add_scene_arg, file_name
from flexbed.commands.modal import load_mounted
from flexbed.commands.static import add_modes_file_arg
from flexbed.errors import InputError
from flexbed.files.destination import check_destination
from flexbed.files.scene import load_scene
from flexbed.words import count

__all__ = ["add_args", "run"]


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("Transmissibility (magnitude, phase) of the mounted system from a "
                          "base acceleration or a force to points, mount forces and the force "
                          "on the base, with every resonance in the band resolved.")
    add_scene_arg(parser)
    parser.add_argument("-o", "--output", type=file_name, default=None, metavar="PREFIX",
                        help="prefix of the files written (default: <scene stem>-frf)")
    parser.add_argument("--input", default="base z", metavar="WHAT",
                        help="'base x|y|z': unit base acceleration (default 'base z'); "
                             "'force x|y|z' with --force-at: unit force; 'load NAME': the "
                             "scene's [[load]] NAME per N (N m), or its [[unbalance]] NAME "
                             "per newton of rotating force")
    parser.add_argument("--force-at", default=None, metavar="BODY:x,y,z",
                        help="where the force of --input force acts (body frame) [m]")
    parser.add_argument("--point", action="append", default=[], metavar="NAME=BODY:x,y,z",
                        help="a point of interest (repeatable; default: the scene's [[point]] "
                             "tables, else every body's centre of mass)")
    parser.add_argument("--relative-to", default=None, metavar="BODY",
                        help="the --point motions relative to this body, in its frame")
    parser.add_argument("--band", default=None, metavar="FMIN,FMAX",
                        help="frequency band [Hz] (default: a quarter of the lowest natural "
                             "frequency to twice the highest)")
    parser.add_argument("-n", type=int, default=400, metavar="N",
                        help="log-spaced frequencies of the base grid (default 400); each "
                             "resonance adds its own")
    parser.add_argument("--quantity", default="acceleration",
                        choices=("acceleration", "velocity", "displacement"),
                        help="the points' quantity (default acceleration; displacement of a "
                             "point --relative-to a body: the relative displacement)")
    parser.add_argument("--deflections", action="store_true",
                        help="also every mount's deflection along its three axes")
    parser.add_argument("--equilibrium", default=None, metavar="FILE",
                        help="equilibrium file from 'flexbed static' (default: solve it here)")
    parser.add_argument("--no-plots", action="store_true", help="write no PNG")
    add_modes_file_arg(parser)


def _band(text):
    if text is None:
        return None
    try:
        lo, hi = (float(v) for v in text.split(","))
    except ValueError:
        raise InputError(f"--band {text!r}: expected FMIN,FMAX in Hz") from None
    if not (np.isfinite(lo) and np.isfinite(hi) and 0.0 < lo < hi):
        raise InputError(f"--band {text!r}: needs 0 < FMIN < FMAX")
    return lo, hi


def run(args: argparse.Namespace) -> int:
    from flexbed.analyses import frf_loads
    from flexbed.analyses.frf import MAX_GRID, QUANTITIES, check_request, frequency_response, \
        frf_csv, parse_input
    from flexbed.analyses.points import parse_point
    from flexbed.files.destination import write_text
    from flexbed.files.frequency import write_frf

    sf = load_scene(args.scene)
    kind, axis = parse_input(args.input)
    band = _band(args.band)
    if not 2 <= args.n <= MAX_GRID:
        raise InputError(f"-n {args.n}: from 2 to {MAX_GRID:,} frequencies")
    if band is not None:
        check_request(band, args.n, None)
    force_at = load = None
    if kind == "load":
        load = frf_loads.scene_load(sf, frf_loads.load_name(args.input),
                                    f"--input {args.input!r}")
        if args.force_at is not None:
            raise InputError(f"--force-at {args.force_at!r}: applies to --input force only "
                             f"(a load acts where the scene puts it)")
        axis = load.directions[0]
    if kind == "base" and args.force_at is not None:
        raise InputError(f"--force-at {args.force_at!r}: applies to --input force only "
                         f"(--input {args.input!r} moves the base)")
    if kind == "force":
        if args.force_at is None:
            raise InputError("--input force needs --force-at BODY:x,y,z")
        try:
            force_at = parse_point(f"force={args.force_at}")
        except InputError:
            raise InputError(f"--force-at {args.force_at!r}: expected BODY:x,y,z (metres, "
                             f"body frame)") from None
    names = [b.name for b in sf.scene.bodies]
    for option, body in ([("--force-at", force_at.body)] if force_at else []) + \
            [("--point", parse_point(p).body) for p in args.point] + \
            [("--relative-to", args.relative_to)] * (args.relative_to is not None):
        if body not in names:
            raise InputError(f"{option}: body {body!r} is not a body of {sf.source.name} "
                             f"(bodies: {', '.join(names)})")
    points = [(parse_point(p), args.relative_to) for p in args.point] or None
    prefix = args.output or f"{sf.output_name}-frf"
    out = {"h5": check_destination(Path(prefix + ".h5")),
           "csv": check_destination(Path(prefix + ".csv"))}
    if not args.no_plots:
        out["bode"] = check_destination(Path(prefix + "-bode.png"))
        out["forces"] = check_destination(Path(prefix + "-forces.png"))
    mt = load_mounted(args, sf)
    r = frequency_response(sf, mt, input=args.input, force_at=force_at, points=points,
                           band=band, n=args.n, quantity=args.quantity,
                           deflections=args.deflections)
    print(f"FRF of '{sf.scene.name}': {r.input}; {r.frequency.size} frequencies on "
          f"{r.frequency[0]:.4g}–{r.frequency[-1]:.4g} Hz, {count(r.resonances.size, 'mode')} "
          f"in the band, {count(r.peaks.shape[0], 'peak')}, each located to 0.1 % of its "
          f"mode's half-power bandwidth")
    iso_cols = np.flatnonzero(r.isolation_columns)
    for j in iso_cols:
        f_iso = r.isolation_from[j] if np.isfinite(r.isolation_from[j]) else None
        peak = int(np.argmax(r.magnitude[:, j]))
        print(f"  {r.names[j]}: peak |T| {r.magnitude[peak, j]:.4g} at "
              f"{r.frequency[peak]:.4f} Hz; " +
              (f"isolation (|T| < 1) above {f_iso:.6g} Hz, "
               f"{100 * (1 - r.magnitude[-1, j]):.2f} % at {r.frequency[-1]:.4g} Hz"
               if f_iso is not None else "no isolation in the band"))
    if load is not None:
        _print_load(sf, mt, r, load, args)
    print(f"solve time: {r.solve_time:.4f} s CPU for {r.evaluations} frequencies "
          f"(linearisation and modes: {mt.solve_time:.4f} s)")
    write_frf(out["h5"], sf, r)
    write_text(out["csv"], frf_csv(r))
    if "bode" in out:
        from flexbed.plots.frequency import plot_bode
        # along the input's axis (the cross-axis responses are in the CSV and HDF5)
        _, letter, u_base, u_force = QUANTITIES[args.quantity]
        acc = [j for j, (u, n) in enumerate(zip(r.units, r.names))
               if u in (u_base, u_force) and n.endswith(f" {letter}{'xyz'[axis]}")]
        top = max((float(r.magnitude[:, j].max()) for j in acc), default=0.0)
        acc = [j for j in acc if r.magnitude[:, j].max() >= 1e-6 * top]    # not round-off
        unit = r.units[acc[0]] if acc else "1"
        iso = r.isolation[:, iso_cols[0]] if iso_cols.size else None
        plot_bode(out["bode"], f"{sf.scene.name}: {r.input}", r.frequency, r.H[:, acc],
                  [r.names[j] for j in acc], unit, r.resonances, iso)
        fb = [r.names.index(f"base F{c}") for c in "XYZ"]
        plot_bode(out["forces"], f"{sf.scene.name}: force on the base, {r.input}",
                  r.frequency, r.H[:, fb], [r.names[j] for j in fb], r.units[fb[0]],
                  r.resonances)
    print("wrote " + ", ".join(str(p) for p in out.values()))
    return 0


def _print_load(sf, mt, r, load, args) -> None:
    """The force into the base per unit load, each axis's largest; at the
    load's running frequency (an unbalance, a harmonic), solved there, the
    force it puts into the base: amplitude [N] and level of its RMS
    [dB re 1 N]."""
    from flexbed.analyses.frf import frequency_response
    fb = [r.names.index(f"base F{c}") for c in "XYZ"]
    top = float(r.magnitude[:, fb].max())
    for c, j in zip("XYZ", fb):
        k = int(np.argmax(r.magnitude[:, j]))
        if r.magnitude[k, j] >= 1e-6 * top:                          # not round-off
            print(f"  base F{c} per unit load: largest {r.magnitude[k, j]:.4g} [{r.units[j]}] "
                  f"at {r.frequency[k]:.4f} Hz")
    if load.running is None:
        return
    at = frequency_response(sf, mt, input=args.input, points=[],
                            frequencies=np.array([load.running]))
    F = abs(load.amplitude) * np.abs(at.H[0, [at.names.index(f"base F{c}") for c in "XYZ"]])
    level = 20.0 * np.log10(np.maximum(F / np.sqrt(2.0), 1e-300))       # of the RMS
    shown = F >= 1e-9 * F.max()                                          # not round-off
    print(f"  at its running frequency {load.running:.6g} Hz, {abs(load.amplitude):.4g} "
          f"{load.per}: base force amplitude " +
          ", ".join(f"F{c} {v:.4g} N ({db:.1f} dB re 1 N RMS)"
                    for c, v, db, s in zip("XYZ", F, level, shown) if s))

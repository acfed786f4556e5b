"""``flexbed stress RESULTS.h5 [--modes-file FILE] [--csv DIR] [--plot DIR]
[--xdmf FILE] [--every N]``: the flexible bed's stresses over a run by
modal superposition (:mod:`flexbed.analyses.bed_stress`): the peak von
Mises stress in the plate and the peak |σ| at each stiffener's extreme
fibres, with place and time, and the plate's stresses at t = 0 (the static
sag when the run starts from equilibrium); a CSV of each element's peak, a
PNG map of it, and an XDMF time series for ParaView.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from flexbed.analyses.bed_stress import BedStresses, run_stress, superpose
from flexbed.errors import InputError
from flexbed.files.destination import check_destination, write_text


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = ("Stresses in a flexible bed over a run (modal superposition of the "
                          "modes file's stress fields): peak von Mises in the plate and peak "
                          "stress in each stiffener, with place and time.")
    parser.add_argument("results", help="results file of a flexible-bed run")
    parser.add_argument("--modes-file", default=None, metavar="FILE",
                        help="the bed's modes file (default: found beside the results file, "
                             "else where the run recorded it)")
    parser.add_argument("--csv", default=None, metavar="DIR",
                        help="write bed-stress-peaks.csv (each element's peak) into DIR")
    parser.add_argument("--plot", default=None, metavar="DIR",
                        help="write the peak map bed-stress-peak.png into DIR")
    parser.add_argument("--xdmf", default=None, metavar="FILE",
                        help="write the stress time series FILE.xdmf + FILE.h5 for ParaView")
    parser.add_argument("--every", type=int, default=1, metavar="N",
                        help="with --xdmf: every N-th frame (default 1)")


def summary(s: BedStresses, origin: np.ndarray) -> str:
    """The peaks as a table, places in the drawing frame [m], MPa and Pa."""
    o = np.asarray(origin, dtype=float)[:2]
    rows = [("plate, peak over the run", s.bed), ("plate at t = 0", s.initial_peak)]
    rows += [(f"stiffener {name!r}", p) for name, p in s.stiffeners]
    lines = [f"{'where':<30} {'stress [MPa]':>12} {'[Pa]':>12} {'x [m]':>8} {'y [m]':>8} "
             f"{'t [s]':>9}  at"]
    for what, p in rows:
        lines.append(f"{what:<30} {p.value / 1e6:12.4g} {p.value:12.4e} {p.x + o[0]:8.4g} "
                     f"{p.y + o[1]:8.4g} {p.time:9.4g}  {p.where}")
    return "\n".join(lines)


def _bed_mount_points(results) -> np.ndarray:
    """The mount points on the bed (drawing frame) from the run's scene, (m, 3) [m]."""
    import tomllib

    from flexbed.files.results import read_results
    c = read_results(results)
    try:
        scene = tomllib.loads(str(c.datasets.get("scene/toml", "")))
    except tomllib.TOMLDecodeError:
        return np.zeros((0, 3))
    names = [b.get("name") for b in scene.get("body", [])]
    bed = scene.get("bed", {}).get("body") or (names[1] if len(names) > 1 else None)
    pts = [m[f"point_{k}"] for m in scene.get("mount", []) for k in "ij"
           if m.get(f"body_{k}") == bed and f"point_{k}" in m]
    return np.array(pts, dtype=float).reshape(-1, 3)


def run(args: argparse.Namespace) -> int:
    if isinstance(args.every, bool) or args.every < 1:
        raise InputError(f"--every {args.every}: must be an integer >= 1")
    for option, value in (("--csv", args.csv), ("--plot", args.plot)):
        if value is not None and Path(value).exists() and not Path(value).is_dir():
            raise InputError(f"{option} {value}: is not a folder (it names an existing file "
                             f"or device); give a folder for the output files")
    if args.xdmf:
        for suffix in (".xdmf", ".h5"):
            check_destination(Path(args.xdmf).with_suffix(suffix))
    stress, a, t, data = run_stress(args.results, args.modes_file)
    s = superpose(stress, a, t)
    print(f"bed stresses by modal superposition ({stress.n_modes} coordinates), "
          f"{Path(args.results).name}, {t[0]:g}-{t[-1]:g} s; von Mises in the plate, |stress| "
          f"at the stiffeners' extreme fibres; places in the scene's drawing frame")
    print(summary(s, data.origin))
    o = np.asarray(data.origin, dtype=float)[:2]
    if args.csv:
        lines = ["element,x_m,y_m,peak_von_mises_Pa,peak_von_mises_MPa"]
        for e, ((x, y), v) in enumerate(zip(s.centres + o, s.peak_map)):
            lines.append(f"{e},{x:.6g},{y:.6g},{v:.6e},{v / 1e6:.6g}")
        f = write_text(Path(args.csv) / "bed-stress-peaks.csv", "\n".join(lines) + "\n")
        print(f"wrote {f}")
    if args.plot:
        from flexbed.plots.stress import plot_peak_map     # matplotlib
        lines = tuple((st.start, st.end) for st in data.plate.stiffeners)
        f = plot_peak_map(Path(args.plot) / "bed-stress-peak.png",
                          f"peak von Mises stress over the run, {Path(args.results).name}",
                          data.nodes, data.cells, s.peak_map, (s.bed.x, s.bed.y), data.origin,
                          mounts=_bed_mount_points(args.results), lines=lines)
        print(f"wrote {f}")
    if args.xdmf:
        from flexbed.fem.stresses import principal, von_mises
        from flexbed.files.stress_xdmf import write_stress_series
        pick = np.arange(0, t.size, args.every)
        faces = stress.faces(a[pick])                       # (k, ne, 2, 3)
        vm = von_mises(faces)
        fields = {"von_mises_top": vm[..., 0], "von_mises_bottom": vm[..., 1],
                  "principal_max": principal(faces)[..., 0].max(axis=-1)}
        f = write_stress_series(Path(args.xdmf).with_suffix(".xdmf"), data.nodes, data.cells,
                                t[pick], fields, s.peak_map)
        print(f"wrote {f} (+ .h5)")
    return 0

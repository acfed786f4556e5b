"""Stiffener models against 3D solids (issue 26, part 2): the figures of
docs/stiffeners.md.

Three structures with flat bars 100 × 20 mm welded under a steel plate,
each against its own converged scikit-fem solid (27-node hexahedra,
:mod:`flexbed.fem.solid`; Richardson in the plane and through the
thickness, :func:`docs.solid_reference.reference`):

* the reference stiffened bed (0.8 × 4.8 × 0.1 m, bars at x = ±0.2 m);
* the same bed on a 0.04 m plate (the web 2.5 times the plate);
* a strip 0.2 × 3 × 0.02 m with one bar (a T-beam).

The Mindlin shell with the stiffener as ``model = "hinged"`` (the default:
its own section rotation, hinged at the plate's face), ``"timoshenko"``
(the section on the plate's normal, the default before),
``"euler-bernoulli"`` (the model before that) and a Timoshenko beam
without the web's shear (``shear_area`` → 0), modes matched to the
solid's by MAC. Solids are cached in docs/stiffeners.json (delete it to
recompute them: ≈ 4 min CPU); the shells (≈ 4 min CPU) are always run.

    OPENBLAS_NUM_THREADS=1 python docs/stiffeners.py
"""

from __future__ import annotations

import json
import sys
import time
from dataclasses import replace
from pathlib import Path

import numpy as np

from flexbed.fem.bed import compute_bed_modes
from flexbed.fem.solid import SolidBed, Web, solid_modes
from flexbed.fem.solid_check import (match, sample_points, shell_shapes, shell_spec, solid_bed,
                                     solid_shapes)
from flexbed.fem.spec import PlateSpec
from flexbed.fem.stiffeners import Stiffener, section_of

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from solid_reference import label, reference  # noqa: E402

N = 10                                       # elastic modes compared
MESHES = [(0, 1), (1, 1), (0, 2), (0, 4), (1, 2), (2, 1), (1, 4)]
BEDS = ("0.1", "0.04")                       # plate thickness [m]
SIZES = (0.1, 0.05, 0.025)
VARIANTS = ("hinged", "timoshenko", "euler-bernoulli", "no web shear")
STRIP = dict(b=0.2, L=3.0, t=0.02)


def solid_runs(t: float) -> dict:
    """The stiffened bed on a plate of thickness t: the solids of MESHES,
    matched to the level-2 one's first N modes (their shapes kept)."""
    bed = replace(solid_bed("stiffened"), thickness=t)
    pts = sample_points("stiffened")
    runs = {}
    for level, nz in MESHES:
        c = time.process_time()
        runs[level, nz] = (solid_modes(bed, level, nz, n_modes=N + 4), time.process_time() - c)
        print("solid", t, level, nz, f"{runs[level, nz][1]:.1f} s", flush=True)
    ref = solid_shapes(runs[2, 1][0], pts)[:N]
    rows = {}
    for (level, nz), (m, cpu) in runs.items():
        j, q = match(ref, solid_shapes(m, pts))
        rows[f"{level},{nz}"] = dict(level=level, nz=nz, dofs=int(m.dofs), cpu=cpu,
                                     f=m.frequency[j].tolist(), mac=q.tolist())
    return dict(rows=rows, shapes=[[float(f"{x:.5g}") for x in r] for r in ref],
                labels=[label(r, pts) for r in ref])


def strip_solid() -> dict:
    s = SolidBed(length_x=STRIP["b"], length_y=STRIP["L"], thickness=STRIP["t"],
                 webs=(Web(0.0, 0.02, 0.1),), h0=0.1)
    return {f"{lv},{nz}": solid_modes(s, lv, nz, n_modes=2).frequency[0]
            for lv, nz in ((0, 1), (1, 1), (2, 1), (1, 2))}


def variant(st: Stiffener, name: str) -> Stiffener:
    if name == "no web shear":
        return replace(st, model="timoshenko",
                       section=replace(st.section, shear_area=1e-12))
    return replace(st, model=name)


def bed_spec(t: float, h: float | None, name: str) -> PlateSpec:
    """The shell of the bed on a t plate: h the grid's element side, None:
    element_size = "auto" (tolerance 0.5 %)."""
    spec = shell_spec("stiffened", h or 0.05)
    sts = tuple(variant(replace(st, offset=-(t / 2 + st.section.centroid)), name)
                for st in spec.stiffeners)
    spec = replace(spec, thickness=t, stiffeners=sts)
    return replace(spec, nx=10, ny=10, mesh_tolerance=0.005) if h is None else spec


def shells(t: float, shapes: np.ndarray) -> dict:
    pts = sample_points("stiffened")
    out = {}
    cases = [(name, h) for name in VARIANTS for h in SIZES] + [
        ("hinged", 0.0125), ("timoshenko", 0.0125), ("hinged", None), ("timoshenko", None)]
    for name, h in cases:
        if h == 0.0125 and t != 0.1:
            continue
        c = time.process_time()
        b = compute_bed_modes(bed_spec(t, h, name), n_modes=N + 4)
        cpu = time.process_time() - c
        j, q = match(shapes, shell_shapes(b, pts))
        key = f"{name} {h or 'auto'}"
        out[key] = dict(f=b.modes.frequency[j].tolist(), mac=q.tolist(), cpu=cpu,
                        elements=int(b.cells.shape[0]))
        if h is None:
            out[key]["estimate"] = b.accuracy.error[j].tolist()
            out[key]["summary"] = b.accuracy.summary()
        print("shell", t, key, f"{cpu:.1f} s", flush=True)
    return out


def strip_shells() -> dict:
    b, L, t = STRIP["b"], STRIP["L"], STRIP["t"]
    sec = section_of("flat", height=0.1, width=0.02)
    st = Stiffener("bar", (0.0, -L / 2), (0.0, L / 2), sec, -(t / 2 + sec.centroid))
    out = {}
    for name in VARIANTS:
        for nx, ny in ((4, 60), (8, 120), (16, 240)):
            spec = PlateSpec(length_x=b, length_y=L, thickness=t, theory="mindlin", nx=nx,
                             ny=ny, stiffeners=(variant(st, name),))
            out[f"{name} {L / ny:g}"] = compute_bed_modes(spec, n_modes=3).modes.frequency[0]
    return out


def pct(f, ref) -> str:
    return f"{100 * (f / ref - 1):+.2f}"


def tables(data: dict) -> str:
    lines = []
    for t in BEDS:
        d = data["beds"][t]
        refs = [reference(d["rows"], k) for k in range(N)]
        sh = d["shells"]
        keys = [f"{n} {h}" for n in VARIANTS for h in SIZES] + (
            ["hinged 0.0125", "timoshenko 0.0125"] if t == "0.1" else []) + [
            "hinged auto", "timoshenko auto"]
        lines += [f"### Plate {t} m", "",
                  "| mode | solid [Hz] | bound | " + " | ".join(keys) + " |",
                  "|---|---:|---:|" + "---:|" * len(keys)]
        for k in range(N):
            r = refs[k]
            cells = [f"{r['value']:.3f}", f"{100 * r['bound'] / r['value']:.2f} %"]
            cells += [pct(sh[key]["f"][k], refs[k]["value"]) for key in keys]
            lines.append(f"| {k + 1} ({d['labels'][k]}) | " + " | ".join(cells) + " |")
        lines += ["| smallest MAC | | | " + " | ".join(f"{min(sh[key]['mac']):.3f}" for key in keys)
                  + " |", "| CPU [s] | | | " + " | ".join(f"{sh[key]['cpu']:.1f}" for key in keys)
                  + " |", "", f"auto: {sh['hinged auto']['summary']}; its estimate per mode "
                  "[%]: " + ", ".join(f"{100 * e:.3f}" for e in sh["hinged auto"]["estimate"]),
                  ""]
        if t == "0.1":
            lines += ["converged shell (0.025 and 0.0125 m, rate 2) against the solid [%]: "
                      + "; ".join(name + " " + ", ".join(
                          pct(f2 + (f2 - f1) / 3, refs[k]["value"]) for k, (f1, f2) in
                          enumerate(zip(sh[f"{name} 0.025"]["f"], sh[f"{name} 0.0125"]["f"])))
                          for name in ("hinged", "timoshenko")), ""]
    s, f = data["strip"]["solid"], data["strip"]["shell"]
    lines += ["### Strip", "", "solid, first bending [Hz]: " + ", ".join(
        f"level {k}: {v:.3f}" for k, v in s.items()), "",
        "| model | " + " | ".join(f"h = {h:g} m" for h in (0.05, 0.025, 0.0125)) + " |",
        "|---|---:|---:|---:|"]
    ref = s["2,1"]
    for name in VARIANTS:
        lines.append(f"| {name} | " + " | ".join(
            f"{f[f'{name} {h:g}']:.3f} ({pct(f[f'{name} {h:g}'], ref)} %)"
            for h in (0.05, 0.025, 0.0125)) + " |")
    return "\n".join(lines) + "\n"


def main() -> None:
    raw = HERE / "stiffeners.json"
    data = json.loads(raw.read_text()) if raw.exists() else {}
    data.setdefault("beds", {})
    for t in BEDS:
        if "rows" not in data["beds"].get(t, {}):
            data["beds"][t] = solid_runs(float(t))
        data["beds"][t]["shells"] = shells(float(t), np.array(data["beds"][t]["shapes"]))
    strip = data.setdefault("strip", {})
    if "solid" not in strip:
        strip["solid"] = strip_solid()
    strip["shell"] = strip_shells()
    raw.write_text(json.dumps(data, indent=1) + "\n")
    print(tables(data))


if __name__ == "__main__":
    main()

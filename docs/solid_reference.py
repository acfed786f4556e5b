"""The 3D-solid reference of a stiffened bed and a bed with a cut-out
(issue 14): scikit-fem triquadratic hexahedra on three nested meshes, the
observed convergence rates and Richardson estimates in the plane and
through the thickness, and the Mindlin shell against it, modes matched by
shape. Writes docs/solid-reference.md (and
docs/solid-reference.json, the raw figures).

Run from the repository, in its venv (≈ 2 min CPU; the
largest model is the stiffened bed at level 2, 92,061 DOFs, and the
slowest the stiffened bed at level 1 with 4 elements through the
thickness, ≈ 30 s):

    OPENBLAS_NUM_THREADS=1 python docs/solid_reference.py
    OPENBLAS_NUM_THREADS=1 python docs/solid_reference.py --table-only   # from the JSON
"""

from __future__ import annotations

import json
import math
import sys
import time
from pathlib import Path

import numpy as np

from flexbed.fem.bed import compute_bed_modes
from flexbed.fem.solid import solid_mesh, solid_modes
from flexbed.fem.solid_check import (match, sample_points, shell_shapes, shell_spec, solid_bed,
                                     solid_shapes)

HERE = Path(__file__).resolve().parent
CASES = ("stiffened", "cutout", "plain")
LEVELS = (0, 1, 2)
N_MODES = 8            # elastic modes of the finest solid in the table
ISSUE_PLAIN = [23.144, 63.807, 80.281, 124.997, 163.317, 169.63, 206.168]


def label(shape: np.ndarray, points: np.ndarray) -> str:
    """bending / torsion / in-plane from mid-surface translations (3P,)."""
    s = shape.reshape(-1, 3)
    if np.sum(s[:, :2] ** 2) > np.sum(s[:, 2] ** 2):
        return "in-plane"
    key = {(round(x, 6), round(y, 6)): i for i, (x, y) in enumerate(points)}
    pairs = [(i, key[(round(-x, 6), round(y, 6))]) for i, (x, y) in enumerate(points)
             if (round(-x, 6), round(y, 6)) in key]
    w = s[:, 2]
    even = sum((w[i] + w[j]) ** 2 for i, j in pairs)
    odd = sum((w[i] - w[j]) ** 2 for i, j in pairs)
    return "bending" if even > odd else "torsion"


def compute() -> dict:
    out = {}
    for case in CASES:
        bed = solid_bed(case)
        pts = sample_points(case)
        runs = {}
        for level, nz in [(lv, 1) for lv in LEVELS] + [(0, 2), (0, 4), (1, 2), (1, 4)]:
            t = time.process_time()
            m = solid_modes(bed, level, nz, n_modes=N_MODES + 3)
            cpu = time.process_time() - t
            runs[(level, nz)] = (m, cpu)
            print(case, level, nz, m.dofs, f"{cpu:.1f} s", np.round(m.frequency, 3), flush=True)
        fine, _ = runs[(LEVELS[-1], 1)]
        ref = solid_shapes(fine, pts)[:N_MODES]
        rows = {}
        for (level, nz), (m, cpu) in runs.items():
            j, q = match(ref, solid_shapes(m, pts))
            rows[f"{level},{nz}"] = dict(level=level, nz=nz, dofs=int(m.dofs), cpu=cpu,
                                         cells=int(solid_mesh(bed, level, nz).nelements),
                                         f=m.frequency[j].tolist(), mac=q.tolist())
        shells = {}
        for h in (0.05, 0.025):
            t = time.process_time()
            b = compute_bed_modes(shell_spec(case, h), n_modes=N_MODES + 4)
            cpu = time.process_time() - t
            j, q = match(ref, shell_shapes(b, pts))
            shells[str(h)] = dict(f=b.modes.frequency[j].tolist(), mac=q.tolist(), cpu=cpu,
                                  elements=int(b.cells.shape[0]))
            print(case, "shell", h, np.round(b.modes.frequency[j], 3), np.round(q, 3), flush=True)
        out[case] = dict(solid=rows, shell=shells,
                         labels=[label(r, pts) for r in ref])
    return out


def richardson(f0: float, f1: float, f2: float) -> tuple[float, float, float]:
    """(observed order p, extrapolated value, its error bound) for three
    meshes refined by 2; p = nan (value f2, bound |f1 − f2|) when the
    differences change sign."""
    d1, d2 = f0 - f1, f1 - f2
    if d1 * d2 <= 0 or d2 == 0:
        return math.nan, f2, abs(d2)
    p = math.log2(d1 / d2)
    if p <= 0.5:
        return p, f2, abs(d2)
    ext = f2 - d2 / (2 ** p - 1)
    return p, ext, abs(ext - f2)


def reference(rows: dict, k: int) -> dict:
    """The converged estimate of mode k: the in-plane series (levels 0, 1, 2
    at nz = 1) extrapolated, plus the thickness correction (nz = 1, 2, 4 at
    level 1, extrapolated, minus nz = 1); its bound adds both bounds and the
    change of the thickness correction between levels 0 and 1 (how far the
    two refinements are from additive)."""
    f = lambda level, nz: rows[f"{level},{nz}"]["f"][k]        # noqa: E731
    p, ext, b1 = richardson(*(f(lv, 1) for lv in LEVELS))
    corr = []
    for level in (0, 1):
        q, tz, b2 = richardson(f(level, 1), f(level, 2), f(level, 4))
        corr.append((q, tz - f(level, 1), b2))
    (_, c0, _), (q, c1, b2) = corr
    value = ext + c1
    return dict(p=p, q=q, inplane=ext, correction=c1, value=value,
                bound=b1 + b2 + abs(c1 - c0))


def table(data: dict) -> str:
    lines = ["# 3D-solid reference: a stiffened bed and a bed with a cut-out", "",
             "Generated by `OPENBLAS_NUM_THREADS=1 python docs/solid_reference.py` "
             "(raw figures in docs/solid-reference.json; `--table-only` rewrites this "
             "file from them). Issue 14.", "",
             "**Solid model** (`flexbed.fem.solid`): scikit-fem triquadratic 27-node "
             "hexahedra (`ElementHex2`), linear elasticity, consistent mass, 3 × 3 × 3 Gauss "
             "points (exact on these boxes), free–free modes by shift-invert Lanczos "
             "(SciPy `eigsh`, SuperLU with minimum-degree ordering). Plate and webs are "
             "one conforming mesh: a tensor grid through every face of plate, hole and "
             "webs, cells outside the solid removed. Level n halves the base grid's cell "
             "sides (0.2 m in the plane, the web's height 0.1 m) n times; nz elements go "
             "through the plate's thickness; one element across a web's 20 mm. Steel "
             "E = 210 GPa, ν = 0.3, ρ = 7800 kg/m³.", "",
             "**Beds**: the reference bed 0.8 × 4.8 × 0.1 m, free–free; *stiffened*: two "
             "flat bars 100 × 20 mm welded under it along its whole length, centred at "
             "x = ±0.2 m (they raise the vertical bending modes by 22–24 %); *cut-out*: a "
             "0.2 × 0.8 m rectangular hole through it, x from 0 to 0.2 m, y from 0.6 to "
             "1.4 m; *plain*: the reference bed itself (checks the solid against the "
             "issue's 171,963-DOF model).", "",
             "**Modes matched by shape**: every mesh's modes are matched to those of the "
             "finest in-plane mesh (level 2, nz = 1) by the MAC of the mid-surface "
             "translations (u, v, w) at the points x ∈ {0, ±0.2, ±0.4} m, y every 0.2 m "
             "(nodes of every mesh; points inside the hole left out). Labels from that "
             "shape: *in-plane* (u, v dominate), else *bending* (w even in x) or "
             "*torsion* (w odd in x; in the stiffened bed the torsion modes carry the "
             "bars' sideways motion too).", "",
             "**Convergence and reference**: two refinements, each extrapolated by "
             "Richardson from three meshes refined by 2: in the plane (levels 0, 1, 2 at "
             "nz = 1; observed order p = log2((f0 − f1) / (f1 − f2)), extrapolated "
             "f2 − (f1 − f2) / (2^p − 1)) and through the thickness (nz = 1, 2, 4 at "
             "level 1, order q; the *thickness correction* is its extrapolated value "
             "minus nz = 1). Reference = in-plane extrapolation + thickness correction. "
             "Bound = |extrapolated − finest| of both series + the change of the "
             "thickness correction from level 0 to level 1 (how far the two refinements "
             "are from additive). When a series' differences change sign or its order "
             "is ≤ 0.5 its finest value is taken, bound its last difference.", "",
             "The Mindlin shell (`theory = \"mindlin\"`, the bars as flat-bar "
             "stiffeners: eccentric Euler–Bernoulli beams on the plate's lower face, "
             "offset −0.1 m) against the reference; MAC of its mode against the "
             "solid's.", ""]
    for case, d in data.items():
        rows = d["solid"]
        n = len(d["labels"])
        lines += [f"## {case}", "",
                  "| mode | level 0 | level 1 | level 2 | p | nz = 2 (level 1) | nz = 4 "
                  "(level 1) | q | thickness correction | reference [Hz] | bound | "
                  + " | ".join(f"shell {h} m" for h in d["shell"]) + " |",
                  "|---|" + "---:|" * (10 + len(d["shell"]))]
        refs = []
        for k in range(n):
            r = reference(rows, k)
            refs.append(r["value"])
            cells = [f"{rows[f'{lv},1']['f'][k]:.3f}" for lv in LEVELS]
            cells.append("–" if math.isnan(r["p"]) else f"{r['p']:.2f}")
            cells += [f"{rows[f'1,{z}']['f'][k]:.3f}" for z in (2, 4)]
            cells.append("–" if math.isnan(r["q"]) else f"{r['q']:.2f}")
            cells += [f"{100 * r['correction'] / r['value']:+.3f} %", f"**{r['value']:.3f}**",
                      f"{100 * r['bound'] / r['value']:.3f} %"]
            for s in d["shell"].values():
                cells.append(f"{s['f'][k]:.3f} ({100 * (s['f'][k] / r['value'] - 1):+.2f} %, "
                             f"MAC {s['mac'][k]:.3f})")
            lines.append(f"| {k + 1} ({d['labels'][k]}) | " + " | ".join(cells) + " |")
        cols = [rows[f"{lv},1"] for lv in LEVELS]
        lines.append("| DOFs | " + " | ".join(f"{r['dofs']:,}" for r in cols)
                     + f" | | {rows['1,2']['dofs']:,} | {rows['1,4']['dofs']:,} | | | | | "
                     + " | ".join(f"{s['elements']:,} elements" for s in d["shell"].values())
                     + " |")
        lines.append("| CPU [s] | " + " | ".join(f"{r['cpu']:.1f}" for r in cols)
                     + f" | | {rows['1,2']['cpu']:.1f} | {rows['1,4']['cpu']:.1f} | | | | | "
                     + " | ".join(f"{s['cpu']:.2f}" for s in d["shell"].values()) + " |")
        worst = min(min(r["mac"]) for r in rows.values())
        lines += ["", "Thickness series at level 0 (nz = 1, 2, 4): " + "; ".join(
            ", ".join(f"{rows[f'0,{z}']['f'][k]:.3f}" for z in (1, 2, 4)) for k in range(n))
            + " Hz.", "",
            f"Smallest MAC of any solid mesh's mode against the level-2 mode: {worst:.3f}.", ""]
        if case == "plain":
            lines += ["Plain bed, reference against the issue's 171,963-DOF model: "
                      + ", ".join(f"{a:.3f} against {b} ({100 * (a / b - 1):+.3f} %)"
                                  for a, b in zip(refs, ISSUE_PLAIN)) + ".", ""]
        else:
            lines += ["For tests/test_solid_reference.py: `" + case.upper() + " = ("
                      + ", ".join(f"{v:.3f}" for v in refs) + ")`", ""]
    return "\n".join(lines) + "\n"


def main() -> None:
    raw = HERE / "solid-reference.json"
    if "--table-only" in sys.argv:
        data = json.loads(raw.read_text())
    else:
        data = compute()
        raw.write_text(json.dumps(data, indent=1) + "\n")
    (HERE / "solid-reference.md").write_text(table(data))
    print(table(data))


if __name__ == "__main__":
    main()

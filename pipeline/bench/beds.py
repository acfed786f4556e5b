"""Beds as built: the plate theories against a 3D solid, and the cost of the
modes of large Mindlin beds (grid, imported quads, imported triangles with
the triangle element, and split in quads as before it).

Accuracy: the reference bed (0.8 × 4.8 × 0.1 m steel, free–free) against
the first seven elastic modes of a 171,963-DOF hexahedral 3D-solid model
(issue 14). The Kirchhoff plate has no in-plane mode: its modes are matched
to the solid's out-of-plane ones in order, the Mindlin shell's by their
label ("in-plane" against the solid's in-plane mode). Cost: CPU seconds
(``time.process_time``) of :func:`flexbed.fem.bed.compute_bed_modes`
(mesh, assembly, eigen-solution, invariants), median of repeats.
"""

from __future__ import annotations

import statistics
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from flexbed.bench.context import BenchContext
from flexbed.bench.markdown import md_table
from flexbed.fem.bed import BedModes, compute_bed_modes
from flexbed.fem.geometry import BedGeometry
from flexbed.fem.mesher import split_triangles
from flexbed.fem.shell import grid_mesh
from flexbed.fem.spec import PlateSpec

__all__ = ["SOLID", "SOLID_IN_PLANE", "STIFFENED", "BedRun", "accuracy_runs", "size_runs",
           "stiffened_run", "section_beds"]

#: the 3D solid's first seven elastic frequencies of the reference bed [Hz]
SOLID = (23.144, 63.807, 80.281, 124.997, 163.317, 169.63, 206.168)
#: which of them is in-plane (index into SOLID)
SOLID_IN_PLANE = 5

#: (label, theory, nx, ny) of the accuracy table; quick: the first of each theory;
#: "triangle": the Mindlin shell on the nx × ny grid halved into triangles,
#: read from a mesh file; "auto": the Mindlin default, element_size = "auto"
ACCURACY = (("Kirchhoff 10 x 10 (default)", "kirchhoff", 10, 10),
            ("Mindlin element_size = \"auto\" (default)", "auto", 0, 0),
            ("Kirchhoff 40 x 40", "kirchhoff", 40, 40),
            ("Mindlin 8 x 48", "mindlin", 8, 48),
            ("Mindlin 16 x 96", "mindlin", 16, 96),
            ("Mindlin triangles 2 x 16 x 96", "triangle", 16, 96))
QUICK_ACCURACY = (ACCURACY[0], ACCURACY[1], ACCURACY[3])
#: the stiffened bed's (two flat bars 100 x 20 mm, docs/stiffeners.md) first ten
#: elastic modes, converged 3D solid [Hz], and their kinds in the shell's words
STIFFENED = (28.683, 78.590, 78.969, 152.650, 160.713, 169.389, 249.211, 251.208, 350.721,
             366.601)
STIFFENED_KINDS = ("bending about x", "bending about x", "torsion", "bending about x", "torsion",
                   "in-plane", "bending about x", "torsion", "torsion", "bending about x")
#: modes solved in the size table
SIZE_MODES = 20


@dataclass
class BedRun:
    """One modes solve: its label, elements, DOFs, CPU s (median), runs and
    the result of the last run."""

    label: str
    elements: int
    dofs: int
    cpu: float
    runs: int
    bed: BedModes


def timed(label: str, spec: PlateSpec, n_modes: int, repeats: int) -> BedRun:
    """``compute_bed_modes(spec, n_modes)`` ``repeats`` times: CPU s, median."""
    cpu, bed = [], None
    for _ in range(repeats):
        t0 = time.process_time()
        bed = compute_bed_modes(spec, n_modes=n_modes)
        cpu.append(time.process_time() - t0)
    dofs = (5 if spec.theory == "mindlin" else 4) * bed.nodes.shape[0]
    return BedRun(label, bed.cells.shape[0], dofs, statistics.median(cpu), repeats, bed)


def matched(bed: BedModes) -> list[float | None]:
    """The bed's frequencies [Hz] matched to :data:`SOLID` (None: no such mode)."""
    f = bed.modes.frequency
    in_plane = [lab == "in-plane" for lab in bed.modes.labels]
    out = iter(float(x) for x, p in zip(f, in_plane) if not p)
    inp = iter(float(x) for x, p in zip(f, in_plane) if p)
    return [next(inp, None) if k == SOLID_IN_PLANE else next(out, None)
            for k in range(len(SOLID))]


def accuracy_runs(quick: bool, repeats: int, log=lambda m: None,
                  folder: Path | None = None, tolerance: float = 0.005) -> list[BedRun]:
    """The reference bed on each mesh of :data:`ACCURACY` (10 modes each;
    ``folder``: where the triangle mesh file is written; ``tolerance``: the
    "auto" bed's ``mesh_tolerance``)."""
    runs = []
    for label, theory, nx, ny in (QUICK_ACCURACY if quick else ACCURACY):
        log(f"bench beds: {label} ...")
        if theory == "triangle":
            path = _mesh_file(Path(folder), nx, ny, "triangle")
            spec = PlateSpec(theory="mindlin", geometry=BedGeometry(mesh_file=str(path)))
        elif theory == "auto":
            spec = PlateSpec(theory="mindlin", mesh_tolerance=tolerance)
        else:
            spec = PlateSpec(theory=theory, nx=nx, ny=ny)
        runs.append(timed(label, spec, 10, repeats))
    return runs


def stiffened_run(repeats: int, tolerance: float = 0.005) -> tuple[BedRun, np.ndarray]:
    """The stiffened bed with ``element_size = "auto"`` (``tolerance``: the
    default 0.5 %), hinged stiffeners (the default): its run and its error against
    :data:`STIFFENED` (10,), modes matched kind by kind in order (the
    second bending and the first torsion mode lie within 0.5 %)."""
    from dataclasses import replace

    from flexbed.fem.solid_check import shell_spec
    spec = replace(shell_spec("stiffened", 0.05), nx=10, ny=10,
                   mesh_tolerance=tolerance)
    run = timed("stiffened bed, element_size = \"auto\"", spec, 10, repeats)
    labels = list(run.bed.modes.labels)
    pools = {k: [i for i, lab in enumerate(labels) if lab == k] for k in set(STIFFENED_KINDS)}
    order = [pools[k].pop(0) if pools[k] else None for k in STIFFENED_KINDS]
    err = np.array([np.nan if i is None else run.bed.modes.frequency[i] / f - 1
                    for i, f in zip(order, STIFFENED)])
    return run, err


def _mesh_file(folder: Path, nx: int, ny: int, kind: str) -> Path:
    """The reference bed's nx × ny grid written with meshio as quads, as
    two triangles per quad (``"triangle"``), or as those triangles each
    split in three quads (``"split"``: what flexbed did with triangles
    before it had a triangle element)."""
    import meshio
    nodes, cells = grid_mesh(PlateSpec(nx=nx, ny=ny))
    if kind in ("triangle", "split"):
        cells = np.vstack([cells[:, [0, 1, 2]], cells[:, [0, 2, 3]]])
    if kind == "split":
        nodes, cells = split_triangles(nodes, cells)
    path = folder / f"bed-{kind}-{nx}x{ny}.vtu"
    meshio.write(path, meshio.Mesh(np.column_stack([nodes, np.zeros(len(nodes))]),
                                   [("triangle" if kind == "triangle" else "quad", cells)]))
    return path


def size_runs(folder: Path, quick: bool, repeats: int, log=lambda m: None) -> list[BedRun]:
    """Large Mindlin beds (quick: small ones): a grid, imported quads,
    imported triangles (the triangle element) and the same triangles split
    in three quads each (the route before the triangle element),
    :data:`SIZE_MODES` modes each."""
    # full: the triangles 40 x 160 (12,800), whose split into 38,400 quads has
    # 194,005 unknowns: within the meshes' limit (MAX_DOFS = 250,000), which
    # 50 x 200's split (302,505) is not
    grid, quads, tris = ((10, 40), (10, 40), (10, 20)) if quick else \
        ((50, 200), (100, 200), (40, 160))
    cases = [(f"Mindlin grid {grid[0]} x {grid[1]}",
              PlateSpec(theory="mindlin", nx=grid[0], ny=grid[1]))]
    for kind, (nx, ny) in (("quad", quads), ("triangle", tris), ("split", tris)):
        n = nx * ny * (1 if kind == "quad" else 2)
        path = _mesh_file(folder, nx, ny, kind)
        label = {"quad": f"imported mesh, {n:,} quads",
                 "triangle": f"imported mesh, {n:,} triangles (ES-MITC3)",
                 "split": f"the same {n:,} triangles split in {3 * n:,} quads (before)"}[kind]
        cases.append((label, PlateSpec(theory="mindlin",
                                       geometry=BedGeometry(mesh_file=str(path)))))
    out = []
    for label, spec in cases:
        log(f"bench beds: {label} ...")
        out.append(timed(label, spec, SIZE_MODES, repeats))
    return out


def _cell(f: float | None, ref: float) -> str:
    return "missing" if f is None else f"{f:.3f} ({100 * (f / ref - 1):+.2f} %)"


def section_beds(ctx: BenchContext) -> str:
    """The reference bed against the 3D solid, and modes of large beds."""
    repeats = 1 if ctx.quick else 3
    tol = ctx.profile.auto_tolerance
    acc = accuracy_runs(ctx.quick, repeats, ctx.log, ctx.workdir, tol)
    size = size_runs(ctx.workdir, ctx.quick, repeats, ctx.log)
    ctx.log("bench beds: stiffened bed, auto ...")
    stiff, stiff_err = stiffened_run(repeats, tol)
    ctx.results["beds"] = {"accuracy": acc, "size": size, "stiffened": (stiff, stiff_err),
                           "matched": {r.label: matched(r.bed) for r in acc}}
    head = ["mode", "3D solid [Hz]"] + [r.label for r in acc]
    rows = []
    for k, ref in enumerate(SOLID):
        name = f"{k + 1}" + (" (in-plane)" if k == SOLID_IN_PLANE else "")
        rows.append([name, f"{ref:.3f}"] + [_cell(ctx.results["beds"]["matched"][r.label][k], ref)
                                            for r in acc])
    rows.append(["elements", ""] + [f"{r.elements:,}" for r in acc])
    rows.append(["modes solve, CPU [s]", ""] + [f"{r.cpu:.3f}" for r in acc])
    size_rows = [[r.label, f"{r.elements:,}", f"{r.dofs:,}", f"{r.cpu:.2f}"] for r in size]
    auto = [f"`element_size = \"auto\"` (its CPU includes the meshes it tried): "
            f"{r.bed.accuracy.summary()}; meshes tried: {r.bed.accuracy.history}."
            for r in acc if r.bed.accuracy is not None and r.bed.spec.auto_mesh]
    return "\n".join([
        "## Beds as built", "",
        "The reference bed (0.8 × 4.8 × 0.1 m steel, free–free): frequencies and error "
        "against the first seven elastic modes of a 171,963-DOF hexahedral 3D-solid model "
        "(issue 14). The Kirchhoff plate (`theory = \"kirchhoff\"`, BFS elements) has no "
        "in-plane mode; the Mindlin shell (`theory = \"mindlin\"`, MITC4 with an "
        "incompatible-mode membrane) has" + ("" if ctx.quick else
        "; the last column is the shell on the 16 x 96 grid halved into triangles (one "
        "diagonal direction), read from a mesh file: the three-node element (MITC3 shear "
        "with stabilisation, edge-smoothed membrane and bending) on the same nodes") + "."
        " Modes solve: `compute_bed_modes` (mesh, assembly, "
        "eigen-solution, invariants; 10 modes), CPU seconds (`time.process_time`), median "
        f"of {repeats}.", "",
        md_table(head, rows, align="lr" + "r" * len(acc)), ""] + auto + [""] * bool(auto) + [
        "The stiffened bed (two flat bars 100 × 20 mm under it, hinged stiffeners; "
        "docs/stiffeners.md), `element_size = \"auto\"`: "
        f"{stiff.cpu:.2f} s CPU (median of {repeats}, with the meshes it tried), "
        f"{stiff.elements:,} elements; against its 3D solid's first ten modes "
        + ", ".join(f"{100 * e:+.2f}" for e in stiff_err) + " %; "
        f"{stiff.bed.accuracy.summary()}.", "",
        f"Modes of larger Mindlin beds, {SIZE_MODES} modes each, CPU seconds, median of "
        f"{repeats}. Imported "
        "meshes: the reference bed's grid written with meshio (VTU), as quads and as two "
        "triangles per quad, which the three-node shell element (MITC3 shear, edge-smoothed "
        "membrane and bending) takes as they are; the last row is the route before that "
        "element, each triangle split in three quadrilaterals (written as such to the file)."
        + (" Quick report: small meshes only." if ctx.quick else ""), "",
        md_table(["bed", "elements", "DOFs", "modes, CPU [s]"], size_rows, align="lrrr"), ""])

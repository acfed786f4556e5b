"""Meshes of a bed's outline, cut-outs and thickness zones, or of a mesh
file.

Three routes, all ending in counter-clockwise cells with a thickness per
cell (quadrilaterals, and triangles from a mesh file):

* **Rectilinear** (outline, cut-outs and zones all made of axis-parallel
  edges): a tensor grid whose lines pass through every vertex, spacing at
  most ``element_size``; the cells inside the outline and outside the
  cut-outs are kept. The meshed area is the exact area.
* **General** (circles, slanted edges): boundary points at most 2 h apart,
  a hexagonal lattice of interior points kept h away from the boundaries,
  Delaunay triangles (SciPy) inside the outline and outside the holes, each
  split into three quadrilaterals at its centroid and edge mid-points
  (quads of side about h). The triangles' area is checked against the
  polygons' (the boundary must come out conforming).
* **Mesh file** (meshio, :mod:`flexbed.fem.mesh_file`): its quads and its
  triangles as they are (linear triangles stored as (a, b, c, c),
  :mod:`flexbed.fem.cells`; the shell has a triangle element,
  :mod:`flexbed.fem.triangle_shell`).

Before meshing, the outline and cut-outs are checked
(:mod:`flexbed.fem.mesh_checks`) and the size of the mesh asked for is
estimated from the areas and the element size (:func:`estimated_nodes`): a
mesh past the solver's limit (``MAX_DOFS`` of :mod:`flexbed.fem.spec`) is
refused before anything is allocated, and after meshing on its exact count.
Every mesh is then checked as a mesh (one piece, sound cells), and every
thickness zone must hold at least one cell.

Pure NumPy/SciPy (no scikit-fem): the scene reader meshes to know the
bed's mass properties.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .cells import centres, is_triangle
from .geometry import BedGeometry, GeometryError, inside, signed_area
from .mesh_checks import MIN_CORNER_ANGLE, check_cells, check_cutouts, check_size
from .mesh_file import read_mesh_file
from .shell import DOFS_PER_NODE
from .spec import MAX_DOFS


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """z-component of the cross product of 2-vectors (…, 2)."""
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def _rectilinear(poly: np.ndarray) -> bool:
    d = np.roll(poly, -1, axis=0) - poly
    return bool(np.all((np.abs(d[:, 0]) <= 1e-12 * np.abs(d).max())
                       | (np.abs(d[:, 1]) <= 1e-12 * np.abs(d).max())))


def _lines(coords: np.ndarray, h: float) -> np.ndarray:
    """Sorted unique coordinates with every gap split to at most h."""
    c = np.unique(np.round(coords, 12))
    out = [c[:1]]
    for lo, hi in zip(c[:-1], c[1:]):
        k = max(1, int(math.ceil((hi - lo) / h - 1e-9)))
        out.append(lo + (hi - lo) * np.arange(1, k + 1) / k)
    return np.concatenate(out)


def _compact(nodes: np.ndarray, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    used, inverse = np.unique(cells.ravel(), return_inverse=True)
    return nodes[used], inverse.reshape(cells.shape)


def _grid(outline, holes, zone_polys, h):
    allpts = np.vstack([outline] + holes + zone_polys)
    xs, ys = _lines(allpts[:, 0], h), _lines(allpts[:, 1], h)
    X, Y = np.meshgrid(xs, ys)
    nodes = np.column_stack([X.ravel(), Y.ravel()])
    i, j = np.meshgrid(np.arange(xs.size - 1), np.arange(ys.size - 1))
    n0 = (i + j * xs.size).ravel()
    cells = np.column_stack([n0, n0 + 1, n0 + xs.size + 1, n0 + xs.size])
    return nodes, cells


def _segments(polys: list[np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
    a = np.vstack([p for p in polys])
    b = np.vstack([np.roll(p, -1, axis=0) for p in polys])
    return a, b


def _distance(pts: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance of each point (P, 2) to the nearest segment a-b (S, 2)."""
    out = np.full(pts.shape[0], np.inf)
    d = b - a
    L2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    for start in range(0, pts.shape[0], 2048):
        p = pts[start:start + 2048, None, :]
        t = np.clip(np.einsum("psj,sj->ps", p - a, d) / L2, 0.0, 1.0)
        q = a + t[..., None] * d
        out[start:start + 2048] = np.sqrt(np.min(np.sum((p - q) ** 2, axis=-1), axis=1))
    return out


def _boundary_points(poly: np.ndarray, spacing: float) -> np.ndarray:
    nxt = np.roll(poly, -1, axis=0)
    out = []
    for p, q in zip(poly, nxt):
        k = max(1, int(math.ceil(np.linalg.norm(q - p) / spacing - 1e-9)))
        s = np.arange(k) / k
        out.append(p + s[:, None] * (q - p))
    return np.vstack(out)


def split_triangles(nodes: np.ndarray, tri: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Three quadrilaterals per counter-clockwise triangle: corner, edge
    mid-point, centroid, edge mid-point (mid-points shared between
    neighbours)."""
    N = nodes.shape[0]
    edges = np.sort(np.vstack([tri[:, [0, 1]], tri[:, [1, 2]], tri[:, [2, 0]]]), axis=1)
    uniq, inv = np.unique(edges, axis=0, return_inverse=True)
    inv = inv.reshape(3, -1)
    mids = 0.5 * (nodes[uniq[:, 0]] + nodes[uniq[:, 1]])
    cent = nodes[tri].mean(axis=1)
    m_ab, m_bc, m_ca = (N + inv[k] for k in range(3))
    g = N + uniq.shape[0] + np.arange(tri.shape[0])
    a, b, c = tri.T
    quads = np.vstack([np.column_stack([a, m_ab, g, m_ca]), np.column_stack([b, m_bc, g, m_ab]),
                       np.column_stack([c, m_ca, g, m_bc])])
    return np.vstack([nodes, mids, cent]), quads


def _general(outline, holes, zone_polys, h, label):
    spacing = 2.0 * h                       # triangles of side 2h → quads of side h
    constraint = [outline] + holes + zone_polys
    bpts = np.vstack([_boundary_points(p, spacing) for p in constraint])
    lo, hi = outline.min(axis=0), outline.max(axis=0)
    dy = spacing * math.sqrt(3) / 2
    rows = []
    for k, y in enumerate(np.arange(lo[1] + dy / 2, hi[1], dy)):
        x = np.arange(lo[0] + (spacing / 2 if k % 2 else 0.0), hi[0], spacing)
        rows.append(np.column_stack([x, np.full(x.size, y)]))
    lattice = np.vstack(rows) if rows else np.zeros((0, 2))
    a, b = _segments(constraint)
    keep = inside(outline, lattice) & (_distance(lattice, a, b) > 0.5 * spacing)
    for hole in holes:
        keep &= ~inside(hole, lattice)
    pts = np.vstack([bpts, lattice[keep]])
    # drop constraint points off the domain (zone edges beyond the outline)
    on = _distance(pts, *_segments([outline] + holes)) <= 1e-9 * spacing
    domain = inside(outline, pts)
    for hole in holes:
        domain &= ~inside(hole, pts)
    pts = np.unique(np.round(pts[on | domain], 12), axis=0)
    from scipy.spatial import Delaunay
    try:
        tri = Delaunay(pts).simplices
    except (RuntimeError, ValueError) as exc:          # Qhull: too few or flat points
        raise GeometryError("element_size", f"{label}: the outline cannot be triangulated "
                                            f"({str(exc).strip().splitlines()[0]}); give a "
                                            f"smaller element_size") from None
    cent = pts[tri].mean(axis=1)
    keep = inside(outline, cent)
    for hole in holes:
        keep &= ~inside(hole, cent)
    tri = tri[keep]
    area = 0.5 * _cross(pts[tri[:, 1]] - pts[tri[:, 0]], pts[tri[:, 2]] - pts[tri[:, 0]])
    flat = np.abs(area) <= 1e-9 * spacing * spacing     # collinear boundary points
    tri, area = tri[~flat], area[~flat]
    tri[area < 0] = tri[area < 0][:, [0, 2, 1]]
    target = signed_area(outline) - sum(signed_area(hh) for hh in holes)
    if abs(np.abs(area).sum() - target) > 1e-9 * target:
        raise GeometryError("element_size", f"{label}: the mesh does not follow the outline and "
                                            f"cut-outs (area {np.abs(area).sum():.6g} against "
                                            f"{target:.6g} m^2); give a smaller element_size "
                                            f"(now {h:g} m)")
    return split_triangles(pts, tri)


def _line_count(coords: np.ndarray, h: float) -> float:
    """How many lines :func:`_lines` makes of these coordinates (as a float,
    so that a tiny h cannot overflow)."""
    c = np.unique(np.round(coords, 12))
    gaps = np.diff(c) / h - 1e-9
    return 1.0 + float(np.sum(np.maximum(1.0, np.ceil(gaps))))


def estimated_nodes(outline: np.ndarray, holes: list, constraints: list, h: float,
                    rectilinear: bool) -> float:
    """The nodes the mesher would make, estimated before meshing.

    Rectilinear: the tensor grid's lines counted exactly, times the share
    of its bounding box the bed covers. General: boundary points every 2h
    and a hexagonal lattice of spacing 2h on the bed's area less a band h
    wide along each boundary, P points in all, B on boundaries; Delaunay
    gives about 2P - B triangles and 3P - B edges, and each triangle split
    into three quads adds its centroid and its edges' mid-points: about
    6P - 2B nodes. Within about 20 % of the mesh made once elements are
    small against the bed (tested).

    Parameters
    ----------
    outline : ndarray (k, 2)
    holes, constraints : list of ndarray (m, 2)
        Cut-outs, and every polygon or segment the mesh must follow [m].
    h : float
        Element size [m].
    rectilinear : bool
        Which route the mesher takes.
    """
    area = abs(signed_area(outline)) - sum(abs(signed_area(p)) for p in holes)
    if rectilinear:
        allpts = np.vstack([outline] + holes + constraints)
        box = np.ptp(allpts, axis=0)
        grid = _line_count(allpts[:, 0], h) * _line_count(allpts[:, 1], h)
        return grid * min(1.0, area / max(box[0] * box[1], 1e-300))
    spacing = 2.0 * h
    boundary, band = 0.0, 0.0
    for k, p in enumerate([outline] + holes + constraints):
        lengths = np.linalg.norm(np.roll(p, -1, axis=0) - p, axis=1)
        boundary += float(np.sum(np.maximum(1.0, np.ceil(lengths / spacing))))
        band += (1.0 if k <= len(holes) else 2.0) * float(np.sum(lengths))
    lattice = max(0.0, area - 0.5 * spacing * band) / (spacing * spacing * math.sqrt(3) / 2)
    return 6.0 * (boundary + lattice) - 2.0 * boundary


def _check_convex(label: str, nodes: np.ndarray, cells: np.ndarray) -> None:
    """Every quadrilateral convex and counter-clockwise (positive Jacobian at
    its corners), every triangle counter-clockwise, and no corner sharper
    than ``MIN_CORNER_ANGLE``, else a GeometryError naming the first bad
    cell (the sharpest)."""
    tri = is_triangle(cells)
    xy = nodes[np.where(tri[:, None], cells[:, [0, 1, 2, 0]], cells)]
    nxt, prv = np.roll(xy, -1, axis=1), np.roll(xy, 1, axis=1)
    turn = _cross(nxt - xy, prv - xy)                      # (ne, 4) corner Jacobians
    flat = turn <= 1e-12 * np.max(np.abs(turn))
    # a triangle (a, b, c, a): corners b and c count (a's equals them, 2 × area)
    bad = np.flatnonzero(np.where(tri, flat[:, 1] | flat[:, 2], np.any(flat, axis=1)))
    if bad.size:
        c = int(bad[0])
        name = f"triangle {c - int(np.sum(~tri))}" if tri[c] else f"quad {c}"
        raise GeometryError(label, f"{label}: {name} (corners "
                                   f"{xy[c, :3 if tri[c] else 4].round(6).tolist()} m) is not "
                                   f"convex (self-intersecting, or a corner of 180 degrees "
                                   f"or more); {bad.size} such cell" + "s" * (bad.size > 1))
    a, b = nxt - xy, prv - xy
    with np.errstate(invalid="ignore", divide="ignore"):
        sine = turn / (np.linalg.norm(a, axis=-1) * np.linalg.norm(b, axis=-1))
    sine = np.where(tri[:, None], np.where(np.arange(4) == 3, 1.0, sine), sine)
    worst = np.min(np.nan_to_num(sine, nan=1.0), axis=1)
    sharp = np.flatnonzero(worst < math.sin(math.radians(MIN_CORNER_ANGLE)))
    if sharp.size:
        c = int(sharp[np.argmin(worst[sharp])])
        name = f"triangle {c - int(np.sum(~tri))}" if tri[c] else f"quad {c}"
        hint = ("remesh it" if label.startswith("mesh_file") else
                "give a smaller element_size (a cut-out or zone much smaller than the "
                "elements leaves slivers)")
        raise GeometryError(label, f"{label}: {name} (corners "
                                   f"{xy[c, :3 if tri[c] else 4].round(6).tolist()} m) has a "
                                   f"corner of {math.degrees(math.asin(worst[c])):.2g} degrees, "
                                   f"below {MIN_CORNER_ANGLE:g} ({sharp.size} such cell"
                                   + "s" * (sharp.size > 1) + f"): too distorted; {hint}")


def _label(geometry: BedGeometry, h: float, path: Path | None) -> str:
    """How messages about the mesh start: the mesh file, or the element
    size (given, or from nx and ny)."""
    if path is not None:
        return f"mesh_file = {str(path)!r}"
    if geometry.element_size is not None:
        return f"element_size = {geometry.element_size:g} m"
    return f"the mesh (element size {h:.6g} m from nx, ny)"


def mesh_bed(geometry: BedGeometry, length_x: float, length_y: float, thickness: float,
             nx: int, ny: int, folder: Path | None = None, lines=()
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Mesh a bed in its drawing frame.

    Parameters
    ----------
    geometry : BedGeometry
    length_x, length_y, thickness : float
        The rectangle used when there is no outline, and the thickness
        outside zones [m].
    nx, ny : int
        Grid of the rectangle; with no ``element_size`` the element side is
        min(bounding box x / nx, bounding box y / ny).
    folder : Path, optional
        Where a relative ``mesh_file`` is.
    lines : sequence of ((x0, y0), (x1, y1))
        Segments the mesh must have edges along (stiffeners).

    Returns
    -------
    nodes : ndarray (N, 2) [m]
    cells : ndarray (ne, 4), counter-clockwise (triangles as (a, b, c, c))
    cell_thickness : ndarray (ne,) [m]
    """
    if geometry.mesh_file is not None:
        path = Path(geometry.mesh_file)
        if folder is not None and not path.is_absolute():
            path = folder / path
        nodes, cells = read_mesh_file(path, per_node=DOFS_PER_NODE, limit=MAX_DOFS)
        ext = np.ptp(nodes, axis=0)
        h = geometry.element_size or min(ext[0] / nx, ext[1] / ny)
        label = _label(geometry, h, path)
        zones = [(z.region.polygon(h), z.thickness) for z in geometry.zones]
    else:
        if geometry.outline is None:
            outline = np.array([[-length_x / 2, -length_y / 2], [length_x / 2, -length_y / 2],
                                [length_x / 2, length_y / 2], [-length_x / 2, length_y / 2]])
        else:
            outline = np.array(geometry.outline)
            if signed_area(outline) < 0:
                outline = outline[::-1].copy()
        ext = np.ptp(outline, axis=0)
        h = geometry.element_size or min(ext[0] / nx, ext[1] / ny)
        label = _label(geometry, h, None)
        holes = [c.polygon(h) for c in geometry.cutouts]
        check_cutouts(outline, [(f"cutout {i + 1}", c.describe(), hole)
                                for i, (c, hole) in enumerate(zip(geometry.cutouts, holes))])
        zones = [(z.region.polygon(h), z.thickness) for z in geometry.zones]
        polys = [outline] + holes + [p for p, _ in zones]
        segs = [np.array(seg, dtype=float) for seg in lines]
        rectilinear = all(_rectilinear(p) for p in polys + segs)
        estimate = estimated_nodes(outline, holes, [p for p, _ in zones] + segs, h, rectilinear)
        check_size("element_size", f"{label} gives about", estimate, DOFS_PER_NODE, MAX_DOFS)
        if rectilinear:
            nodes, cells = _grid(outline, holes, [p for p, _ in zones] + segs, h)
            cent = nodes[cells].mean(axis=1)
            keep = inside(outline, cent)
            for hole in holes:
                keep &= ~inside(hole, cent)
            nodes, cells = _compact(nodes, cells[keep])
        else:
            nodes, cells = _general(outline, holes, [p for p, _ in zones] + segs, h, label)
            nodes, cells = _compact(nodes, cells)
        if cells.shape[0] == 0:
            raise GeometryError("element_size", f"{label}: no cell is left on the bed")
        check_size("element_size", f"{label} gives", nodes.shape[0], DOFS_PER_NODE, MAX_DOFS)
        cells = check_cells(label, nodes, cells, cells.shape[0])
    _check_convex(label, nodes, cells)
    t = np.full(cells.shape[0], float(thickness))
    cent = centres(nodes, cells)
    for i, (poly, tz) in enumerate(zones):
        hit = inside(poly, cent)
        if not hit.any():
            z = geometry.zones[i]
            raise GeometryError(f"zone {i + 1}", f"zone {i + 1}: {z.region.describe()} holds "
                                                 f"no cell of the bed (outside it, in a "
                                                 f"cut-out, or smaller than a cell); give it "
                                                 f"where the bed is, or a smaller element_size")
        t[hit] = tz
    return nodes, cells, t

"""Checks of a bed's geometry and mesh as geometry and as a mesh: polygons
simple, regions where they belong, meshes one conforming piece of sound
cells, and their size within the solver's limit — each failure a
:class:`~flexbed.fem.geometry.GeometryError` whose message starts with the
entry it names (``outline``, ``cutout 2``, ``mesh_file = '…'``).

What is refused and what is repaired:

* polygons (outline, polygon regions): non-finite or absurd coordinates
  (beyond ``MAX_COORDINATE``), fewer than 3 points, a repeated point, edges
  that cross or touch, no area — refused;
* cut-outs: not strictly inside the outline (outside it, across its edge or
  covering it), touching or overlapping another cut-out — refused;
* mesh cells: a corner index out of range, a quadrilateral with a repeated
  corner, a cell of no area, two cells with the same corners, an edge of
  more than two cells or two cells folded over each other, two nodes at one
  point, a mesh in several pieces (cells joined only at a node count as
  separate), a cell not convex or with a corner sharper than
  ``MIN_CORNER_ANGLE`` (checked by the mesher) — refused; clockwise cells
  are turned counter-clockwise and
  nodes no cell uses are dropped, silently.

Tolerances are relative to the extent L of what is checked: points closer
than 1e-9 L are the same point; an area below 1e-12 L² is none. Pure NumPy
and SciPy (``scipy.spatial.cKDTree``, ``scipy.sparse.csgraph``).
"""

from __future__ import annotations

import numpy as np

from .geometry import MAX_COORDINATE, MIN_EXTENT, GeometryError, inside

#: the sharpest corner a cell may have [degrees]: the shell's elements give
#: nonsense below it (a cut-out of 1e-4 m in 0.2 m elements, corners of
#: 0.003 degrees, lowers the first frequency from 23 to 6 Hz)
MIN_CORNER_ANGLE = 0.5
#: the most points a polygon of the scene may have (its edges are checked
#: pairwise for crossings)
MAX_POLYGON_POINTS = 10_000
#: points closer than this fraction of the extent are one point
SAME_POINT = 1e-9


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]


def _count(n: int, what: str) -> str:
    return f"{int(n)} {what}" + ("" if n == 1 else "s")


def _xy(p) -> str:
    return "[" + ", ".join(f"{float(v):.6g}" for v in p) + "]"


def check_coordinates(label: str, xy: np.ndarray, name: str = "point",
                      numbers: np.ndarray | None = None) -> None:
    """Refuse non-finite coordinates or coordinates beyond ``MAX_COORDINATE``.

    Parameters
    ----------
    label : str
        What the points are, as the message starts (``"outline"``).
    xy : ndarray (P, 2)
        Points [m].
    name : str
        What a point is called in the message ("point", "node").
    numbers : ndarray (P,) of int, optional
        Each point's number in the message (default 1, 2, …).
    """
    xy = np.asarray(xy, dtype=float)
    finite = np.all(np.isfinite(xy), axis=1)
    bad = ~finite | (np.max(np.abs(np.where(finite[:, None], xy, 0.0)), axis=1, initial=0.0)
                     > MAX_COORDINATE)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        n = int(numbers[i]) if numbers is not None else i + 1
        why = "is not finite" if not finite[i] else (f"m is beyond {MAX_COORDINATE:g} m "
                                                     f"(coordinates in metres)")
        raise GeometryError(label, f"{label}: {name} {n} = {_xy(xy[i])} {why}")


def segments_meet(p0, p1, q0, q1, tol: float) -> np.ndarray:
    """Whether segments p0-p1 and q0-q1 (…, 2) cross or touch (an end within
    ``tol`` [m] of the other segment): bool (…)."""
    d = p1 - p0
    e = q1 - q0
    d1, d2 = _cross(e, p0 - q0), _cross(e, p1 - q0)
    d3, d4 = _cross(d, q0 - p0), _cross(d, q1 - p0)
    proper = (((d1 > 0) & (d2 < 0)) | ((d1 < 0) & (d2 > 0))) & (
        ((d3 > 0) & (d4 < 0)) | ((d3 < 0) & (d4 > 0)))

    def near(a, b, c):                              # point c within tol of segment a-b
        ab = b - a
        L2 = np.maximum(np.sum(ab * ab, axis=-1), 1e-300)
        t = np.clip(np.sum((c - a) * ab, axis=-1) / L2, 0.0, 1.0)
        q = a + t[..., None] * ab
        return np.sum((c - q) ** 2, axis=-1) <= tol * tol

    return proper | near(q0, q1, p0) | near(q0, q1, p1) | near(p0, p1, q0) | near(p0, p1, q1)


def _meeting_pairs(a0, a1, b0, b1, tol: float, keep=None):
    """Index pairs (i, j) of segments a0-a1 (n, 2) and b0-b1 (m, 2) that
    cross or touch, first found first: bounding boxes compared in blocks of
    256 rows, :func:`segments_meet` on the pairs whose boxes overlap.
    ``keep(i, j)`` (index arrays, broadcast) masks pairs out."""
    alo, ahi = np.minimum(a0, a1) - tol, np.maximum(a0, a1) + tol
    blo, bhi = np.minimum(b0, b1), np.maximum(b0, b1)
    for start in range(0, a0.shape[0], 256):
        i = np.arange(start, min(a0.shape[0], start + 256))[:, None]
        j = np.arange(b0.shape[0])[None, :]
        box = ((alo[i, 0] <= bhi[j, 0]) & (ahi[i, 0] >= blo[j, 0])
               & (alo[i, 1] <= bhi[j, 1]) & (ahi[i, 1] >= blo[j, 1]))
        if keep is not None:
            box &= keep(i, j)
        ii, jj = np.nonzero(box)
        if ii.size:
            ii = ii + start
            hit = np.flatnonzero(segments_meet(a0[ii], a1[ii], b0[jj], b1[jj], tol))
            if hit.size:
                return int(ii[hit[0]]), int(jj[hit[0]])
    return None


def check_polygon(label: str, poly: np.ndarray) -> None:
    """Refuse a polygon (k, 2) [m] that is not simple: fewer than 3 points,
    coordinates not finite or absurd, a repeated point, an extent below
    ``MIN_EXTENT``, no area, or edges that cross or touch (other than
    neighbours at their common corner)."""
    poly = np.asarray(poly, dtype=float)
    check_coordinates(label, poly)
    k = poly.shape[0]
    if k < 3:
        raise GeometryError(label, f"{label}: {k} points; a polygon needs at least 3")
    if k > MAX_POLYGON_POINTS:
        raise GeometryError(label, f"{label}: {k:,} points; the most a polygon may have is "
                                   f"{MAX_POLYGON_POINTS:,}")
    L = float(np.ptp(poly, axis=0).max())
    if L < MIN_EXTENT:
        raise GeometryError(label, f"{label}: spans {L:g} m, less than {MIN_EXTENT:g} m "
                                   f"(coordinates in metres)")
    tol = SAME_POINT * L
    from scipy.spatial import cKDTree
    pairs = cKDTree(poly).query_pairs(tol, output_type="ndarray")
    if pairs.size:
        i, j = sorted(int(v) for v in pairs[0])
        raise GeometryError(label, f"{label}: points {i + 1} and {j + 1} are the same point "
                                   f"{_xy(poly[i])}; give each corner once (the polygon "
                                   f"closes itself)")
    x, y = poly[:, 0], poly[:, 1]
    area = 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    if not abs(area) > 1e-12 * L * L:
        shown = ", ".join(_xy(p) for p in poly[:8]) + (", ..." if k > 8 else "")
        raise GeometryError(label, f"{label} = [{shown}] encloses no area")
    a, b = poly, np.roll(poly, -1, axis=0)
    # neighbours: folded back along each other
    d, e = b - a, np.roll(b - a, -1, axis=0)
    back = (np.abs(_cross(d, e)) <= 1e-12 * L * L) & (np.sum(d * e, axis=1) < 0)
    if back.any():
        i = int(np.flatnonzero(back)[0])
        raise GeometryError(label, f"{label}: turns back on itself at point {(i + 1) % k + 1} "
                                   f"= {_xy(b[i])}")
    hit = _meeting_pairs(a, b, a, b, tol,
                         lambda i, j: (j > i + 1) & ~((i == 0) & (j == k - 1)))
    if hit is not None:
        ei, ej = hit
        raise GeometryError(label, f"{label}: edges {_xy(a[ei])}-{_xy(b[ei])} and "
                                   f"{_xy(a[ej])}-{_xy(b[ej])} m cross or touch; the "
                                   f"polygon must not intersect itself")


def polygons_meet(p: np.ndarray, q: np.ndarray, tol: float) -> bool:
    """True when polygons p (k, 2) and q (m, 2) [m] share any point: an
    edge of one crosses or touches an edge of the other, or one lies
    inside the other."""
    p1, q1 = np.roll(p, -1, axis=0), np.roll(q, -1, axis=0)
    if _meeting_pairs(p, p1, q, q1, tol) is not None:
        return True
    return bool(inside(q, p[:1]).any() or inside(p, q[:1]).any())


def check_cutouts(outline: np.ndarray, holes: list[tuple[str, str, np.ndarray]]) -> None:
    """Refuse a cut-out that is not strictly inside the outline, or that
    touches or overlaps another cut-out.

    Parameters
    ----------
    outline : ndarray (k, 2)
        The bed's outline [m] (a simple polygon).
    holes : list of (label, description, polygon (m, 2))
        Each cut-out as messages name it (``"cutout 2"``), what it is, and
        its polygon as meshed [m].
    """
    L = float(np.ptp(outline, axis=0).max())
    tol = SAME_POINT * L
    o1 = np.roll(outline, -1, axis=0)
    for label, what, hole in holes:
        check_coordinates(label, hole)
        h1 = np.roll(hole, -1, axis=0)
        crosses = _meeting_pairs(hole, h1, outline, o1, tol) is not None
        if crosses:
            raise GeometryError(label, f"{label}: {what} meets the outline's edge; a cut-out "
                                       f"must lie inside the bed (shape the outline for a "
                                       f"notch)")
        if not inside(outline, hole[:1])[0]:
            covers = inside(hole, outline[:1])[0]
            raise GeometryError(label, f"{label}: {what} "
                                       + ("covers the whole bed" if covers else
                                          "lies outside the bed's outline"))
    for n, (label, what, hole) in enumerate(holes):
        for other, _, poly in holes[:n]:
            if polygons_meet(hole, poly, tol):
                raise GeometryError(label, f"{label}: {what} touches or overlaps {other}; "
                                           f"give overlapping holes as one polygon")


def check_size(entry: str, what: str, nodes: float, per_node: int, limit: int) -> None:
    """Refuse a mesh of more than ``limit`` degrees of freedom.

    Parameters
    ----------
    entry : str
        The entry the message names (``"element_size"``, ``"mesh_file"``).
    what : str
        The message's start, naming the entry and its value.
    nodes : float
        Nodes of the mesh (exact or estimated).
    per_node, limit : int
        Degrees of freedom per node and the most allowed.
    """
    dofs = per_node * nodes
    if dofs > limit:
        shown = f"{int(dofs):,}" if dofs < 1e12 else f"{dofs:.3g}"
        raise GeometryError(entry, f"{what} {shown} degrees of freedom ({per_node} per node); "
                                   f"the limit is {limit:,}")


def _cell(c: int, n_quads: int) -> str:
    return f"quad {c}" if c < n_quads else f"triangle {c - n_quads}"


def check_cells(label: str, nodes: np.ndarray, cells: np.ndarray, n_quads: int) -> np.ndarray:
    """The cells of a mesh checked as a mesh and turned counter-clockwise.

    Parameters
    ----------
    label : str
        How messages start (``"mesh_file = 'bed.vtu'"``).
    nodes : ndarray (N, 2)
        Node coordinates [m], finite; every node used by a cell.
    cells : ndarray (ne, 4)
        Corner indices, in range: the quadrilaterals, then the triangles
        as (a, b, c, c) (:func:`flexbed.fem.cells.as_cells`); messages call
        them "quad i" and "triangle j", numbered from 0 in that order.
    n_quads : int
        How many of the cells are quadrilaterals.

    Returns
    -------
    ndarray (ne, 4)
        The cells, counter-clockwise.
    """
    from .cells import areas
    cells = np.array(cells, dtype=np.int64)
    tri = np.arange(cells.shape[0]) >= n_quads
    c3 = cells[:, :3]
    repeated = np.where(tri, (c3[:, 0] == c3[:, 1]) | (c3[:, 1] == c3[:, 2])
                        | (c3[:, 0] == c3[:, 2]),
                        np.any(np.diff(np.sort(cells, axis=1), axis=1) == 0, axis=1))
    if repeated.any():
        c = int(np.flatnonzero(repeated)[0])
        raise GeometryError(label, f"{label}: {_cell(c, n_quads)} has a repeated corner (nodes "
                                   f"{cells[c, :3 if tri[c] else 4].tolist()}); "
                                   f"{_count(repeated.sum(), 'such cell')}")
    L = float(np.ptp(nodes, axis=0).max())
    area = areas(nodes, cells)
    flat = np.abs(area) <= 1e-12 * L * L
    if flat.any():
        c = int(np.flatnonzero(flat)[0])
        corners = nodes[cells[c, :3 if tri[c] else 4]].round(9).tolist()
        raise GeometryError(label, f"{label}: {_cell(c, n_quads)} (corners {corners} m) has "
                                   f"no area; {_count(flat.sum(), 'such cell')}")
    flip = area < 0
    cells[flip] = np.where(tri[flip, None], cells[flip][:, [0, 2, 1, 1]], cells[flip][:, ::-1])
    key = np.sort(cells, axis=1)
    _, first = np.unique(key, axis=0, return_index=True)
    if first.size < cells.shape[0]:
        dup = np.setdiff1d(np.arange(cells.shape[0]), first)
        c = int(dup[0])
        same = int(np.flatnonzero(np.all(key == key[c], axis=1))[0])
        raise GeometryError(label, f"{label}: {_cell(same, n_quads)} and {_cell(c, n_quads)} "
                                   f"have the same corners; {_count(dup.size, 'cell')} "
                                   f"repeat another")
    _check_edges(label, nodes, cells, n_quads)
    _check_angles(label, nodes, cells, n_quads)
    _check_nodes(label, nodes)
    _check_pieces(label, cells)
    return cells


def _directed_edges(cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each cell's edges as (from, to) (m, 2) and the cell of each (m,)."""
    pairs = np.stack([cells, np.roll(cells, -1, axis=1)], axis=-1)     # (ne, 4, 2)
    owner = np.repeat(np.arange(cells.shape[0]), 4)
    pairs = pairs.reshape(-1, 2)
    keep = pairs[:, 0] != pairs[:, 1]
    return pairs[keep], owner[keep]


def _check_edges(label: str, nodes: np.ndarray, cells: np.ndarray, n_quads: int) -> None:
    """An edge belongs to one or two cells, and two counter-clockwise cells
    sharing an edge run along it in opposite directions (else they lie on
    the same side of it: folded over each other)."""
    pairs, owner = _directed_edges(cells)
    key = np.sort(pairs, axis=1)
    uniq, inverse, count = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.ravel()
    if np.any(count > 2):
        e = int(np.flatnonzero(count > 2)[0])
        on = np.unique(owner[inverse == e])
        names = ", ".join(_cell(int(c), n_quads) for c in on[:4])
        raise GeometryError(label, f"{label}: the edge {_xy(nodes[uniq[e, 0]])}-"
                                   f"{_xy(nodes[uniq[e, 1]])} m belongs to {on.size} cells "
                                   f"({names}); an edge joins at most two cells (do cells "
                                   f"overlap?)")
    same = np.unique(pairs, axis=0, return_counts=True)[1]
    if np.any(same > 1):
        d, n = np.unique(pairs, axis=0, return_counts=True)
        e = d[np.flatnonzero(n > 1)[0]]
        on = owner[np.all(pairs == e, axis=1)]
        raise GeometryError(label, f"{label}: {_cell(int(on[0]), n_quads)} and "
                                   f"{_cell(int(on[1]), n_quads)} lie on the "
                                   f"same side of their common edge {_xy(nodes[e[0]])}-"
                                   f"{_xy(nodes[e[1]])} m: they overlap")


def _check_angles(label: str, nodes: np.ndarray, cells: np.ndarray, n_quads: int) -> None:
    """The cells around a node fill 360 degrees about it when it is inside
    the mesh, at most 360 on its boundary; more means cells overlap there
    (folded over each other without sharing an edge)."""
    angle = np.zeros(nodes.shape[0])
    for block in (cells[:n_quads], cells[n_quads:, :3]):
        if not block.size:
            continue
        v = nodes[block]
        a = np.roll(v, -1, axis=1) - v
        b = np.roll(v, 1, axis=1) - v
        theta = np.arctan2(_cross(a, b), np.sum(a * b, axis=-1))       # (0, π) convex
        angle += np.bincount(block.ravel(), weights=np.mod(theta, 2 * np.pi).ravel(),
                             minlength=nodes.shape[0])
    pairs, _ = _directed_edges(cells)
    key = np.sort(pairs, axis=1)
    uniq, count = np.unique(key, axis=0, return_counts=True)
    inner = np.ones(nodes.shape[0], bool)
    inner[uniq[count == 1].ravel()] = False
    bad = np.where(inner, np.abs(angle - 2 * np.pi) > 1e-6, angle > 2 * np.pi + 1e-6)
    if bad.any():
        i = int(np.flatnonzero(bad)[0])
        raise GeometryError(label, f"{label}: the cells around node {i} at {_xy(nodes[i])} m "
                                   f"fill {np.degrees(angle[i]):.6g} degrees about it, not "
                                   f"{'360' if inner[i] else 'at most 360'}: cells overlap "
                                   f"there")


def _check_nodes(label: str, nodes: np.ndarray) -> None:
    """No two nodes at one point (they would leave the mesh unjoined there)."""
    from scipy.spatial import cKDTree
    L = float(np.ptp(nodes, axis=0).max())
    pairs = cKDTree(nodes).query_pairs(SAME_POINT * L, output_type="ndarray")
    if pairs.size:
        i, j = sorted(int(v) for v in pairs[0])
        pairs_text = _count(len(pairs), "such pair")
        raise GeometryError(label, f"{label}: nodes {i} and {j} are at the same point "
                                   f"{_xy(nodes[i])} m ({pairs_text}); merge "
                                   f"duplicate nodes in the mesher, or the mesh is not "
                                   f"joined there")


def _check_pieces(label: str, cells: np.ndarray) -> None:
    """One piece: every cell reached from every other across shared edges."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    ne = cells.shape[0]
    pairs, owner = _directed_edges(cells)
    key = np.sort(pairs, axis=1)
    _, inverse = np.unique(key, axis=0, return_inverse=True)
    inverse = inverse.ravel()
    graph = coo_matrix((np.ones(owner.size), (owner, inverse)),
                       shape=(ne, int(inverse.max()) + 1)).tocsr()
    n, which = connected_components(graph @ graph.T, directed=False)
    if n > 1:
        sizes = np.bincount(which)
        shown = ", ".join(str(int(s)) for s in np.sort(sizes)[::-1][:6])
        raise GeometryError(label, f"{label}: the mesh is in {n} pieces ({shown}"
                                   f"{', …' if n > 6 else ''} cells) not joined along cell "
                                   f"edges; a bed is one piece (pieces would move apart "
                                   f"freely)")


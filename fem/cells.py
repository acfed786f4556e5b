"""Cells of a shell mesh: bilinear quadrilaterals and linear triangles in
one (ne, 4) array of node indices.

A triangle is stored as the four-corner cell (a, b, c, c): its last two
corners are the same node. Natural coordinates are (ξ, η) ∈ [-1, 1]² in a
quadrilateral and (r, s), r, s ≥ 0, r + s ≤ 1 in a triangle
(x = x_a + r (x_b − x_a) + s (x_c − x_a)); the shape functions of a
triangle are (1 − r − s, r, s, 0), so the repeated corner takes nothing and
every (4,)-vector of shape functions works on the cell's four indices. Pure
NumPy.
"""

from __future__ import annotations

import numpy as np

_CORNERS = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
_TRI_DN = np.array([[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0], [0.0, 0.0]])


def is_triangle(cells: np.ndarray) -> np.ndarray:
    """Which cells (ne, 4) are triangles (last two corners equal): bool (ne,)."""
    cells = np.asarray(cells)
    return cells[:, 3] == cells[:, 2]


def as_cells(quads: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """One (nq + nt, 4) array: the quads (nq, 4), then the triangles (nt, 3)
    as (a, b, c, c)."""
    quads = np.asarray(quads, np.int64).reshape(-1, 4)
    tri = np.asarray(triangles, np.int64).reshape(-1, 3)
    return np.vstack([quads, tri[:, [0, 1, 2, 2]]])


def edges(cells: np.ndarray) -> np.ndarray:
    """The mesh's edges (m, 2), each once as (lower, higher) node index:
    four per quadrilateral, three per triangle (its repeated corner makes
    no edge), an edge shared by two cells listed once."""
    cells = np.asarray(cells, np.int64).reshape(-1, 4)
    pairs = np.stack([cells, np.roll(cells, -1, axis=1)], axis=-1).reshape(-1, 2)
    pairs = np.sort(pairs[pairs[:, 0] != pairs[:, 1]], axis=1)
    return np.unique(pairs, axis=0)


def centres(nodes: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Mean of each cell's distinct corners (ne, 2) [m] (a triangle's
    centroid)."""
    xy = np.asarray(nodes)[cells]
    out = xy.mean(axis=1)
    tri = is_triangle(cells)
    out[tri] = xy[tri, :3].mean(axis=1)
    return out


def areas(nodes: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Signed area of each cell (ne,) [m²], positive when counter-clockwise
    (a triangle's repeated corner adds nothing)."""
    xy = np.asarray(nodes)[cells][:, :, :2]
    return 0.5 * np.sum(xy[:, :, 0] * np.roll(xy[:, :, 1], -1, axis=1)
                        - np.roll(xy[:, :, 0], -1, axis=1) * xy[:, :, 1], axis=1)


def point_shape(triangle: bool, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Shape functions (4,) and natural derivatives (4, 2) of a cell at
    natural coordinates s (2,)."""
    if triangle:
        return np.array([1.0 - s[0] - s[1], s[0], s[1], 0.0]), _TRI_DN.copy()
    a, b = _CORNERS[:, 0], _CORNERS[:, 1]
    N = 0.25 * (1 + a * s[0]) * (1 + b * s[1])
    dN = np.column_stack([0.25 * a * (1 + b * s[1]), 0.25 * b * (1 + a * s[0])])
    return N, dN


def locate(nodes: np.ndarray, cells: np.ndarray, x: float, y: float
           ) -> tuple[int, np.ndarray] | None:
    """(cell, natural coordinates (2,)) of the point (x, y), or None when no
    cell holds it (tolerance 1e-9 of the largest cell)."""
    xy = np.asarray(nodes)[cells][:, :, :2]                        # (ne, 4, 2)
    lo, hi = xy.min(axis=1), xy.max(axis=1)
    size = float(np.max(hi - lo))
    tol = 1e-9 * size
    near = np.flatnonzero((x >= lo[:, 0] - tol) & (x <= hi[:, 0] + tol)
                          & (y >= lo[:, 1] - tol) & (y <= hi[:, 1] + tol))
    tri = is_triangle(cells)
    p = np.array([x, y])
    for c in near:
        if tri[c]:
            E = np.column_stack([xy[c, 1] - xy[c, 0], xy[c, 2] - xy[c, 0]])
            s = np.linalg.solve(E, p - xy[c, 0])
            if s.min() >= -1e-8 and s.sum() <= 1.0 + 1e-8:
                s = np.clip(s, 0.0, 1.0)
                return int(c), s / max(1.0, s.sum())
            continue
        s = np.zeros(2)
        for _ in range(20):                                       # Newton on the map
            N, dN = point_shape(False, s)
            r = N @ xy[c] - p
            J = dN.T @ xy[c]                                      # ∂x_j/∂ξ_i, transposed
            step = np.linalg.solve(J.T, r)
            s = s - step
            if np.max(np.abs(step)) < 1e-13:
                break
        if np.all(np.abs(s) <= 1.0 + 1e-8):
            return int(c), np.clip(s, -1.0, 1.0)
    return None

"""Edge-based strain smoothing (ES-FEM, Liu, Nguyen-Thoi & Lam 2009) of
constant-strain triangles.

Each triangle is cut into three sub-triangles by its centroid, one on each
edge; the smoothing domain of an edge is the union of the sub-triangles on
it (two inside the mesh, one on the boundary or where a triangle meets a
quadrilateral). The smoothed strain of the domain is the area-weighted mean
of the triangles' constant strains,

    B̄_k = Σ_j (A_j / 3) B_j / Σ_j (A_j / 3),

and the stiffness is Σ_k B̄_kᵀ (Σ_j (A_j / 3) D_j) B̄_k (the material
matrix integrated over the domain, so zones of another thickness count
exactly). A constant strain stays exact (the patch test), while in-plane and
plate bending come out far softer than with the triangles' own strains, which
are too stiff. Each edge couples the (up to) four nodes of its two
triangles.
"""

from __future__ import annotations

import numpy as np


def edge_stencils(tris: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The edges of a triangle mesh and where each triangle's corners sit in
    its edges' four-node stencils.

    Parameters
    ----------
    tris : ndarray (nt, 3)
        Counter-clockwise triangles (node indices).

    Returns
    -------
    stencil : ndarray (ne, 4)
        Per edge: its two nodes (lower index first) and the opposite corners
        of the triangle on its left and on its right (an edge with one
        triangle repeats its first node in the empty slot; nothing is put
        there).
    half_edge : ndarray (nt, 3)
        The edge of each triangle's side k (corner k to corner k + 1).
    slots : ndarray (nt, 3, 3)
        slots[t, k, i]: the stencil position of corner (k + i) % 3 of
        triangle t in the stencil of its side k.
    """
    nt = tris.shape[0]
    p = tris
    q = np.roll(tris, -1, axis=1)
    r = np.roll(tris, -2, axis=1)
    lo, hi = np.minimum(p, q), np.maximum(p, q)
    key = lo.astype(np.int64) * (int(tris.max()) + 1) + hi
    edges, half_edge = np.unique(key.ravel(), return_inverse=True)
    half_edge = half_edge.reshape(nt, 3)
    forward = p < q                                                  # p = lo: left triangle
    stencil = np.empty((edges.size, 4), np.int64)
    stencil[half_edge, 0] = lo
    stencil[half_edge, 1] = hi
    stencil[:, 2] = stencil[:, 0]
    stencil[:, 3] = stencil[:, 0]
    stencil[half_edge[forward], 2] = r[forward]
    stencil[half_edge[~forward], 3] = r[~forward]
    slots = np.where(forward[:, :, None], np.array([0, 1, 2]), np.array([1, 0, 3]))
    return stencil, half_edge, slots


def smoothed_operators(tris: np.ndarray, area: np.ndarray, operators: list[np.ndarray],
                       weights: list[np.ndarray]
                       ) -> tuple[np.ndarray, list[np.ndarray], list[np.ndarray]]:
    """Edge-smoothed strain operators.

    Parameters
    ----------
    tris : ndarray (nt, 3)
        Counter-clockwise triangles.
    area : ndarray (nt,) [m²]
    operators : list of ndarray (nt, 3, 15)
        Constant strain operators of the triangles on their corners' five
        DOFs (u, v, w, θx, θy).
    weights : list of ndarray (nt,)
        The material factor of each operator per triangle (E t / (1 − ν²)
        for the membrane, E t³ / 12 (1 − ν²) for bending).

    Returns
    -------
    stencil : ndarray (ne, 4)
        The four nodes of each edge domain (:func:`edge_stencils`).
    smoothed : list of ndarray (ne, 3, 20)
        B̄ of each operator on the stencil's DOFs [1/m].
    factors : list of ndarray (ne,)
        Σ_j (A_j / 3) × weight_j over the domain: the integrated material
        factor.
    """
    stencil, half_edge, slots = edge_stencils(tris)
    ne, nt = stencil.shape[0], tris.shape[0]
    share = area / 3.0
    dom = np.bincount(half_edge.ravel(), weights=np.repeat(share, 3), minlength=ne)
    # DOF column of corner (k + i) % 3 in edge k's stencil, for each triangle
    corner = (np.arange(3)[:, None] + np.arange(3)[None, :]) % 3       # [k, i]
    src = (5 * corner[None, :, :, None] + np.arange(5)).reshape(1, 3, 15)
    dst = (5 * slots[:, :, :, None] + np.arange(5)).reshape(nt, 3, 15)
    rows = np.broadcast_to(half_edge[:, :, None], (nt, 3, 15))
    smoothed, factors = [], []
    for B, wgt in zip(operators, weights):
        out = np.zeros((ne, 3, 20))
        vals = share[:, None, None, None] * B[:, :, src[0]]             # (nt, 3 strains, 3, 15)
        vals = np.moveaxis(vals, 1, -1)                                  # (nt, 3 sides, 15, 3)
        _scatter(out, rows, dst, vals)
        smoothed.append(out / dom[:, None, None])
        factors.append(np.bincount(half_edge.ravel(), weights=np.repeat(share * wgt, 3),
                                   minlength=ne))
    return stencil, smoothed, factors


def _scatter(out: np.ndarray, rows: np.ndarray, dst: np.ndarray, vals: np.ndarray) -> None:
    """out[rows, :, dst] += vals, with vals (nt, 3, 15, 3 strains)."""
    size = out.shape[0] * 20
    idx = (rows * 20 + dst).ravel()
    acc = np.zeros((size, 3))
    for s in range(3):
        acc[:, s] = np.bincount(idx, weights=vals[..., s].ravel(), minlength=size)
    out += acc.reshape(out.shape[0], 20, 3).transpose(0, 2, 1)

"""Mode shapes of the Mindlin shell anywhere on the bed: the bilinear
element field of the cell that holds the point.

A point at height z above the mid-surface point (x, y) moves by
U = (u + z θy, v − z θx, w), the shell's own kinematics
(:mod:`flexbed.fem.mitc4`), with u, v, w, θx, θy and the in-plane rotation
interpolated bilinearly from the cell's corners. Pure NumPy: usable from
the modes file alone. :func:`mode_shapes` picks this or the Kirchhoff
:class:`~flexbed.fem.shapes.GridShapes` by the file's theory.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .shapes import GridShapes, OutsidePlateError

_CORNERS = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])


def _bilinear(s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Shape functions (4,) and natural derivatives (4, 2) at s = (ξ, η)."""
    a, b = _CORNERS[:, 0], _CORNERS[:, 1]
    N = 0.25 * (1 + a * s[0]) * (1 + b * s[1])
    dN = np.column_stack([0.25 * a * (1 + b * s[1]), 0.25 * b * (1 + a * s[0])])
    return N, dN


@dataclass(frozen=True)
class QuadShapes:
    """Mode shapes on a mesh of bilinear quadrilaterals, evaluable anywhere.

    Attributes
    ----------
    nodes : ndarray (N, 2)
        Node coordinates [m].
    cells : ndarray (ne, 4)
        Counter-clockwise quadrilaterals.
    translation, rotation : ndarray (n, N, 3)
        Nodal translations and rotations per mode.
    mid_z : float
        z of the mid-surface in the bed frame [m] (non-zero when fixed
        masses lift the centre of mass off it).
    """

    nodes: np.ndarray
    cells: np.ndarray
    translation: np.ndarray
    rotation: np.ndarray
    mid_z: float = 0.0

    def locate(self, x: float, y: float) -> tuple[int, np.ndarray] | None:
        """(cell, natural coordinates (2,)) of the point (x, y), or None when
        no cell holds it."""
        xy = self.nodes[self.cells]                                   # (ne, 4, 2)
        lo, hi = xy.min(axis=1), xy.max(axis=1)
        size = float(np.max(hi - lo))
        tol = 1e-9 * size
        near = np.flatnonzero((x >= lo[:, 0] - tol) & (x <= hi[:, 0] + tol)
                              & (y >= lo[:, 1] - tol) & (y <= hi[:, 1] + tol))
        p = np.array([x, y])
        for c in near:
            s = np.zeros(2)
            for _ in range(20):                                       # Newton on the map
                N, dN = _bilinear(s)
                r = N @ xy[c] - p
                J = dN.T @ xy[c]                                      # ∂x_j/∂ξ_i, transposed
                step = np.linalg.solve(J.T, r)
                s = s - step
                if np.max(np.abs(step)) < 1e-13:
                    break
            if np.all(np.abs(s) <= 1.0 + 1e-8):
                return int(c), np.clip(s, -1.0, 1.0)
        return None

    def at(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Translation and rotation of each mode at points of the bed.

        Parameters
        ----------
        points : ndarray (P, 3)
            (x, y) on the bed, z the height above the mid-surface [m].

        Returns
        -------
        translation, rotation : ndarray (n, P, 3)

        Raises
        ------
        OutsidePlateError
            A point whose (x, y) is on no element (off the bed or in a hole).
        """
        pts = np.atleast_2d(np.asarray(points, dtype=float))
        n = self.translation.shape[0]
        trans = np.zeros((n, pts.shape[0], 3))
        rot = np.zeros((n, pts.shape[0], 3))
        for i, (x, y, z) in enumerate(pts):
            where = self.locate(x, y)
            if where is None:
                lo, hi = self.nodes.min(axis=0), self.nodes.max(axis=0)
                raise OutsidePlateError(
                    f"point ({x:g}, {y:g}, {z:g}) m lies off the bed (outside its outline "
                    f"or in a cut-out; the bed spans [{lo[0]:g}, {hi[0]:g}] x "
                    f"[{lo[1]:g}, {hi[1]:g}] m)")
            c, s = where
            N, _ = _bilinear(s)
            corner = self.cells[c]
            t = np.einsum("a,kaj->kj", N, self.translation[:, corner])
            r = np.einsum("a,kaj->kj", N, self.rotation[:, corner])
            h = z - self.mid_z                                        # above the mid-surface
            t[:, 0] += h * r[:, 1]
            t[:, 1] -= h * r[:, 0]
            trans[:, i] = t
            rot[:, i] = r
        return trans, rot


def mode_shapes(theory: str, nodes: np.ndarray, cells: np.ndarray, translation: np.ndarray,
                rotation: np.ndarray, twist: np.ndarray) -> GridShapes | QuadShapes:
    """The point evaluator of a modes file's shapes: Hermite on the grid
    (Kirchhoff) or bilinear on the cells (Mindlin)."""
    if theory == "mindlin":
        nodes = np.asarray(nodes, float)
        mid_z = float(nodes[0, 2]) if nodes.shape[1] == 3 and len(nodes) else 0.0
        return QuadShapes(nodes[:, :2], np.asarray(cells, np.int64), translation, rotation,
                          mid_z)
    return GridShapes.from_nodes(nodes, translation, rotation, twist)

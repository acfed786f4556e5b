"""Mode shapes of the Mindlin shell anywhere on the bed: the element field
(bilinear in a quadrilateral, linear in a triangle) of the cell that holds
the point.

A point at height z above the mid-surface point (x, y) moves by
U = (u + z θy, v − z θx, w), the shell's own kinematics
(:mod:`flexbed.fem.mitc4`), with u, v, w, θx, θy and the in-plane rotation
interpolated from the cell's corners (:mod:`flexbed.fem.cells`). Pure NumPy: usable from
the modes file alone. :func:`mode_shapes` picks this or the Kirchhoff
:class:`~flexbed.fem.grid_shapes.GridShapes` by the file's theory.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .cells import is_triangle, locate, point_shape
from .grid_shapes import GridShapes, OutsidePlateError



@dataclass(frozen=True)
class QuadShapes:
    """Mode shapes on a mesh of bilinear quadrilaterals and linear triangles
    (:mod:`flexbed.fem.cells`), evaluable anywhere.

    Attributes
    ----------
    nodes : ndarray (N, 2)
        Node coordinates [m].
    cells : ndarray (ne, 4)
        Counter-clockwise quadrilaterals; triangles as (a, b, c, c).
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
        no cell holds it (:func:`flexbed.fem.cells.locate`)."""
        return locate(self.nodes, self.cells, x, y)

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
            N, _ = point_shape(bool(is_triangle(self.cells[c:c + 1])[0]), s)
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

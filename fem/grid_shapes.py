"""Mode shapes of the Kirchhoff plate's grid as point motions: nodal
translations and rotations, and the motion of any point of the plate, on or
off the mid-surface (the Mindlin shell's: :mod:`flexbed.fem.quad_shapes`).

Small rotations of the plate's normal, by Kirchhoff kinematics:
θ = (∂w/∂y, -∂w/∂x, 0); a point at height z above the mid-surface moves by
the mid-surface translation (0, 0, w) plus θ × (0, 0, z) = (-z ∂w/∂x,
-z ∂w/∂y, 0). Between nodes the deflection is the element's own bicubic
Hermite interpolant, so :meth:`GridShapes.at` reproduces the finite-element
field exactly. Pure NumPy: usable from the modes file alone.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .hermite import hermite_1d


def nodal_motions(w: np.ndarray, w_x: np.ndarray, w_y: np.ndarray
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Translations and rotations at nodes from deflection and slopes.

    Parameters
    ----------
    w, w_x, w_y : ndarray (..., N)
        Deflection and its x and y derivatives at the nodes.

    Returns
    -------
    translation : ndarray (..., N, 3)
        (0, 0, w).
    rotation : ndarray (..., N, 3)
        (∂w/∂y, -∂w/∂x, 0).
    """
    zero = np.zeros_like(w)
    return np.stack([zero, zero, w], axis=-1), np.stack([w_y, -w_x, zero], axis=-1)


class OutsidePlateError(ValueError):
    """A point that does not lie on the plate."""


@dataclass(frozen=True)
class GridShapes:
    """Mode shapes on a tensor grid of nodes, evaluable anywhere.

    Attributes
    ----------
    x : ndarray (nx+1,)
        Grid lines along x, ascending [m].
    y : ndarray (ny+1,)
        Grid lines along y, ascending [m].
    w, w_x, w_y, w_xy : ndarray (n, ny+1, nx+1)
        Nodal deflection and derivatives per mode (row = y index).
    """

    x: np.ndarray
    y: np.ndarray
    w: np.ndarray
    w_x: np.ndarray
    w_y: np.ndarray
    w_xy: np.ndarray

    @classmethod
    def from_nodes(cls, nodes: np.ndarray, translation: np.ndarray, rotation: np.ndarray,
                   twist: np.ndarray) -> "GridShapes":
        """Build from per-node arrays as stored in the modes file.

        Parameters
        ----------
        nodes : ndarray (N, 2) or (N, 3)
            Node coordinates [m] on a tensor grid.
        translation, rotation : ndarray (n, N, 3)
            Nodal translations and rotations per mode.
        twist : ndarray (n, N)
            ∂²w/∂x∂y per mode.
        """
        xs = np.unique(np.round(nodes[:, 0], 12))
        ys = np.unique(np.round(nodes[:, 1], 12))
        ix = np.searchsorted(xs, np.round(nodes[:, 0], 12))
        iy = np.searchsorted(ys, np.round(nodes[:, 1], 12))
        if xs.size * ys.size != nodes.shape[0]:
            raise ValueError("nodes do not form a tensor grid")
        n = translation.shape[0]

        def grid(values: np.ndarray) -> np.ndarray:
            out = np.empty((n, ys.size, xs.size))
            out[:, iy, ix] = values
            return out

        return cls(x=xs, y=ys, w=grid(translation[..., 2]), w_x=grid(-rotation[..., 1]),
                   w_y=grid(rotation[..., 0]), w_xy=grid(twist))

    def at(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Translation and rotation of each mode at points of the plate.

        Parameters
        ----------
        points : ndarray (P, 3)
            Points in the bed frame [m]: (x, y) on the plate, z the height
            above the mid-surface.

        Returns
        -------
        translation : ndarray (n, P, 3)
        rotation : ndarray (n, P, 3)

        Raises
        ------
        OutsidePlateError
            A point whose (x, y) is off the plate.
        """
        pts = np.atleast_2d(np.asarray(points, dtype=float))
        size = max(self.x[-1] - self.x[0], self.y[-1] - self.y[0])
        tol = 1e-9 * size
        px, py, pz = pts[:, 0], pts[:, 1], pts[:, 2]
        bad = ((px < self.x[0] - tol) | (px > self.x[-1] + tol)
               | (py < self.y[0] - tol) | (py > self.y[-1] + tol))
        if np.any(bad):
            i = int(np.flatnonzero(bad)[0])
            raise OutsidePlateError(
                f"point ({px[i]:g}, {py[i]:g}, {pz[i]:g}) m lies outside the plate "
                f"[{self.x[0]:g}, {self.x[-1]:g}] x [{self.y[0]:g}, {self.y[-1]:g}] m")
        ex = np.clip(np.searchsorted(self.x, px, side="right") - 1, 0, self.x.size - 2)
        ey = np.clip(np.searchsorted(self.y, py, side="right") - 1, 0, self.y.size - 2)
        hx = self.x[ex + 1] - self.x[ex]
        hy = self.y[ey + 1] - self.y[ey]
        s = np.clip((px - self.x[ex]) / hx, 0.0, 1.0)
        t = np.clip((py - self.y[ey]) / hy, 0.0, 1.0)
        n = self.w.shape[0]
        w = np.zeros((n, pts.shape[0]))
        wx = np.zeros_like(w)
        wy = np.zeros_like(w)
        for cx in (0, 1):
            for cy in (0, 1):
                jx, jy = ex + cx, ey + cy
                end_x = np.full(s.shape, bool(cx))
                end_y = np.full(t.shape, bool(cy))
                vx, dvx, _ = hermite_1d(s, end_x, slope=False)
                sx, dsx, _ = hermite_1d(s, end_x, slope=True)
                vy, dvy, _ = hermite_1d(t, end_y, slope=False)
                sy, dsy, _ = hermite_1d(t, end_y, slope=True)
                sx, dsx = sx * hx, dsx * hx
                sy, dsy = sy * hy, dsy * hy
                dvx, dsx = dvx / hx, dsx / hx
                dvy, dsy = dvy / hy, dsy / hy
                coef = (self.w[:, jy, jx], self.w_x[:, jy, jx],
                        self.w_y[:, jy, jx], self.w_xy[:, jy, jx])
                fx = (vx, sx, vx, sx)
                fy = (vy, vy, sy, sy)
                gx = (dvx, dsx, dvx, dsx)
                gy = (dvy, dvy, dsy, dsy)
                for c, ax, ay, bx, by in zip(coef, fx, fy, gx, gy):
                    w += c * (ax * ay)
                    wx += c * (bx * ay)
                    wy += c * (ax * by)
        trans, rot = nodal_motions(w, wx, wy)
        trans[..., 0] = -pz * wx
        trans[..., 1] = -pz * wy
        return trans, rot

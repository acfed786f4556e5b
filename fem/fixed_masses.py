"""Masses fixed to the bed without mounts: point masses and rigid
equipment (mass, inertia tensor about its own centre of mass, position).

An item whose centre of mass sits at height z above the mid-surface point
(x, y) moves rigidly with the shell there: its centre by the shell's own
kinematics U = (u + z θy, v − z θx, w) and its attitude by the rotation
(θx, θy, ½(∂v/∂x − ∂u/∂y)), all from the bilinear field of the element
holding (x, y). Its kinetic energy ½ m |U̇|² + ½ θ̇ᵀ J θ̇ gives the mass
matrix m TᵀT + Rᵀ J R (T, R: the point's translation and rotation per
element DOF), and the same T, R give its share of every modal invariant
exactly (:func:`moments`). Pure NumPy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .cells import is_triangle, point_shape
from .geometry import MAX_COORDINATE, GeometryError

_EPS = np.zeros((3, 3, 3))
_EPS[0, 1, 2] = _EPS[1, 2, 0] = _EPS[2, 0, 1] = 1.0
_EPS[0, 2, 1] = _EPS[2, 1, 0] = _EPS[1, 0, 2] = -1.0


@dataclass(frozen=True, slots=True)
class FixedMass:
    """A rigid item fixed to the bed.

    Parameters
    ----------
    name : str
    position : (x, y, z)
        Its centre of mass in the drawing frame, z above the mid-surface [m].
    mass : float
        [kg].
    inertia : 3 × 3 nested tuple
        Inertia tensor about its centre of mass, bed axes [kg m²] (zero: a
        point mass).
    """

    name: str
    position: tuple[float, float, float]
    mass: float
    inertia: tuple = ((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))

    def __post_init__(self) -> None:
        p = np.array(self.position, dtype=float)
        if p.shape != (3,) or not np.all(np.isfinite(p)):
            raise GeometryError("position", f"position = {self.position!r} must be [x, y, z] "
                                            f"[m]")
        if np.abs(p).max() > MAX_COORDINATE:
            raise GeometryError("position", f"position = {self.position!r} m is beyond "
                                            f"{MAX_COORDINATE:g} m (coordinates in metres)")
        object.__setattr__(self, "position", tuple(float(v) for v in p))
        m = self.mass
        if isinstance(m, bool) or not isinstance(m, (int, float)) or not (
                math.isfinite(m) and m > 0):
            raise GeometryError("mass", f"mass = {m!r} must be a number > 0 [kg]")
        object.__setattr__(self, "mass", float(m))
        J = np.array(self.inertia, dtype=float)
        if J.shape == (3,):
            J = np.diag(J)
        if J.shape != (3, 3) or not np.all(np.isfinite(J)) or not np.allclose(J, J.T):
            raise GeometryError("inertia", f"inertia = {self.inertia!r} must be 3 numbers or "
                                           f"a symmetric 3 x 3 [kg m^2]")
        if np.linalg.eigvalsh(J).min() < -1e-12 * max(1.0, np.abs(J).max()):
            raise GeometryError("inertia", f"inertia = {self.inertia!r} is not positive "
                                           f"semi-definite")
        object.__setattr__(self, "inertia", tuple(tuple(float(v) for v in r) for r in J))


def attachment(nodes: np.ndarray, cells: np.ndarray, cell: int, s: np.ndarray,
               height: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """DOFs (20,), translation operator T (3, 20) and rotation operator
    R (3, 20) of a point at natural coordinates s of ``cell``, ``height``
    above the mid-surface (DOF order u, v, w, θx, θy per corner; a
    triangle's repeated corner gets zero columns)."""
    N, dN = point_shape(bool(is_triangle(cells[cell:cell + 1])[0]), s)
    xy = nodes[cells[cell], :2]
    J = dN.T @ xy                                    # J[i, j] = ∂x_j/∂ξ_i
    dNx = np.linalg.solve(J, dN.T).T                 # (4, 2) ∂N/∂x, ∂N/∂y
    T = np.zeros((3, 20))
    R = np.zeros((3, 20))
    c = np.arange(4) * 5
    T[0, c] = N
    T[0, c + 4] = height * N
    T[1, c + 1] = N
    T[1, c + 3] = -height * N
    T[2, c + 2] = N
    R[0, c + 3] = N
    R[1, c + 4] = N
    R[2, c + 1] = 0.5 * dNx[:, 0]
    R[2, c] = -0.5 * dNx[:, 1]
    dofs = (5 * cells[cell][:, None] + np.arange(5)).ravel()
    return dofs, T, R


def moments(item: FixedMass, position: np.ndarray, T: np.ndarray, R: np.ndarray
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The item's share of the primitive integrals of
    :func:`flexbed.fem.invariants.shell_second_moments`.

    Parameters
    ----------
    item : FixedMass
    position : ndarray (3,)
        Its centre of mass in the frame of the invariants [m].
    T, R : ndarray (3, n)
        Its translation and rotation per mode.

    Returns
    -------
    S (3, n), Q (n, 3, 3), P (n, n, 3, 3)
        ∫ρΦ, ∫ρ ū0 Φ_kᵀ, ∫ρ Φ_k Φ_lᵀ over the item, with Φ = T + R × r.
    """
    m = item.mass
    J = np.array(item.inertia)
    E = 0.5 * np.trace(J) * np.eye(3) - J            # ∫ρ r rᵀ about its centre
    S = m * T
    # ∫ρ r (R × r)ᵀ: [i, j] = Σ E_ib ε_jab R_a
    Q = m * position[None, :, None] * T.T[:, None, :] + np.einsum("ib,jab,an->nij", E, _EPS, R)
    P = m * np.einsum("ik,jl->klij", T, T)
    P += np.einsum("iab,jcd,ak,cl,bd->klij", _EPS, _EPS, R, R, E)
    return S, Q, P

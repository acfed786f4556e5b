"""Mass, centre of mass and inertia of a meshed bed, integrated exactly
over its bilinear quadrilaterals (2 × 2 Gauss points: the integrands are
at most cubic in each natural coordinate) — the same numbers as the shell's
consistent mass matrix (:func:`flexbed.fem.invariants.shell_mass_properties`),
without assembling it. Pure NumPy."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

_G = 1.0 / np.sqrt(3.0)
_GAUSS = np.array([[-_G, -_G], [_G, -_G], [_G, _G], [-_G, _G]])
_CORNERS = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])


@dataclass(frozen=True)
class MassProperties:
    """Rigid-body mass properties.

    Attributes
    ----------
    mass : float
        [kg].
    centre : ndarray (3,)
        Centre of mass in the frame the geometry was given in [m].
    inertia : ndarray (3, 3)
        Inertia tensor about the centre of mass [kg m²].
    """

    mass: float
    centre: np.ndarray
    inertia: np.ndarray


def shift_inertia(mass: float, inertia_at_origin: np.ndarray, centre: np.ndarray) -> np.ndarray:
    """Inertia about the centre of mass from the one about the origin
    (parallel axes): J_c = J_o − m (|c|² I − c cᵀ)."""
    c = np.asarray(centre, dtype=float)
    return inertia_at_origin - mass * (c @ c * np.eye(3) - np.outer(c, c))


def plate_mass_properties(nodes: np.ndarray, cells: np.ndarray, thickness: np.ndarray,
                          density: float) -> MassProperties:
    """Mass properties of a mid-surface-symmetric plate on a quad mesh.

    Parameters
    ----------
    nodes : ndarray (N, 2) [m]
    cells : ndarray (ne, 4), counter-clockwise
    thickness : ndarray (ne,) [m]
    density : float [kg/m³]
    """
    xy = np.asarray(nodes, dtype=float)[cells]                     # (ne, 4, 2)
    t = np.asarray(thickness, dtype=float)
    a, b = _CORNERS[:, 0], _CORNERS[:, 1]
    m = 0.0
    sx = sy = sxx = syy = sxy = szz = 0.0
    for xi, eta in _GAUSS:
        N = 0.25 * (1 + a * xi) * (1 + b * eta)
        dN = np.column_stack([0.25 * a * (1 + b * eta), 0.25 * b * (1 + a * xi)])
        J = np.einsum("ai,eaj->eij", dN, xy)
        det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
        x, y = np.einsum("a,eaj->je", N, xy)
        w = density * t * det
        m += w.sum()
        sx += (w * x).sum()
        sy += (w * y).sum()
        sxx += (w * x * x).sum()
        syy += (w * y * y).sum()
        sxy += (w * x * y).sum()
        szz += (w * t * t / 12.0).sum()
    J0 = np.array([[syy + szz, -sxy, 0.0], [-sxy, sxx + szz, 0.0], [0.0, 0.0, sxx + syy]])
    c = np.array([sx / m, sy / m, 0.0])
    return MassProperties(mass=float(m), centre=c, inertia=shift_inertia(m, J0, c))

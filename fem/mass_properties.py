"""Mass, centre of mass and inertia of a meshed bed, integrated exactly
over its bilinear quadrilaterals (2 × 2 Gauss points: the integrands are
at most cubic in each natural coordinate) and linear triangles (three
points, exact for the quadratic integrands) — the same numbers as the shell's
consistent mass matrix (:func:`flexbed.fem.invariants.shell_mass_properties`),
without assembling it. Pure NumPy."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .cells import is_triangle, point_shape

_G = 1.0 / np.sqrt(3.0)
_GAUSS = np.array([[-_G, -_G], [_G, -_G], [_G, _G], [-_G, _G]])
#: three-point rule of a triangle (weights 1/6 in (r, s)), exact to degree 2
_TRI_POINTS = np.array([[1 / 6, 1 / 6], [2 / 3, 1 / 6], [1 / 6, 2 / 3]])


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
    """Mass properties of a mid-surface-symmetric plate on a mesh of
    quadrilaterals and triangles (:mod:`flexbed.fem.cells`).

    Parameters
    ----------
    nodes : ndarray (N, 2) [m]
    cells : ndarray (ne, 4), counter-clockwise (triangles as (a, b, c, c))
    thickness : ndarray (ne,) [m]
    density : float [kg/m³]
    """
    cells = np.asarray(cells)
    tri = is_triangle(cells)
    t = np.asarray(thickness, dtype=float)
    sums = np.zeros(7)                              # m, sx, sy, sxx, syy, sxy, szz
    for pick, rule, weight in ((~tri, _GAUSS, 1.0), (tri, _TRI_POINTS, 1.0 / 6.0)):
        xy = np.asarray(nodes, dtype=float)[cells[pick]]          # (ne, 4, 2)
        for s in rule:
            N, dN = point_shape(rule is _TRI_POINTS, s)
            J = np.einsum("ai,eaj->eij", dN, xy)
            det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
            x, y = np.einsum("a,eaj->je", N, xy)
            w = weight * density * t[pick] * det
            sums += [w.sum(), (w * x).sum(), (w * y).sum(), (w * x * x).sum(),
                     (w * y * y).sum(), (w * x * y).sum(), (w * t[pick] ** 2 / 12.0).sum()]
    m, sx, sy, sxx, syy, sxy, szz = sums
    J0 = np.array([[syy + szz, -sxy, 0.0], [-sxy, sxx + szz, 0.0], [0.0, 0.0, sxx + syy]])
    c = np.array([sx / m, sy / m, 0.0])
    return MassProperties(mass=float(m), centre=c, inertia=shift_inertia(m, J0, c))

"""Stresses of the 3D-solid reference bed (:mod:`flexbed.fem.solid`), to
check the shell's (:mod:`flexbed.fem.stresses`): a uniform pressure on a
pad of the top face (a mount's footprint), and the stress at the centre of
each element's top face, from the triquadratic displacement's gradient
there (Hooke's law in 3D: σ = λ tr(ε) I + 2 μ ε).
"""

from __future__ import annotations

import numpy as np
from skfem import Basis, ElementHex2, FacetBasis, LinearForm, MeshHex, asm

__all__ = ["pad_load", "top_face_stresses"]

_TOL = 1e-9


@LinearForm
def _unit(v, w):
    return v


def pad_load(mesh: MeshHex, n_dofs: int, pad: tuple, force: float, top: float) -> np.ndarray:
    """Consistent load vector (n_dofs,) of a total ``force`` [N] along −z
    spread uniformly over the rectangle ``pad`` = (x0, x1, y0, y1) [m] of
    the face z = ``top`` (its edges on mesh lines); DOF 3 i + c."""
    x0, x1, y0, y1 = pad
    facets = mesh.facets_satisfying(
        lambda x: (np.abs(x[2] - top) < _TOL) & (x[0] > x0 - _TOL) & (x[0] < x1 + _TOL)
        & (x[1] > y0 - _TOL) & (x[1] < y1 + _TOL))
    scalar = asm(_unit, FacetBasis(mesh, ElementHex2(), facets=facets))
    f = np.zeros(n_dofs)
    f[2::3] = -force / ((x1 - x0) * (y1 - y0)) * scalar
    return f


def top_face_stresses(mesh: MeshHex, u: np.ndarray, young: float, poisson: float
                      ) -> tuple[np.ndarray, np.ndarray]:
    """Stress at the centre of each element's upper face.

    Parameters
    ----------
    mesh : MeshHex
    u : ndarray (3 N,)
        Displacements of the ElementHex2 basis, DOF 3 i + c [m].
    young, poisson : float
        E [Pa], ν [-].

    Returns
    -------
    points : ndarray (ne, 3)
        Where [m].
    sigma : ndarray (ne, 3, 3)
        Stress tensors [Pa].
    """
    ne = mesh.t.shape[1]
    grad = np.zeros((ne, 3, 3))                     # ∂u_c/∂x_a: [e, c, a]
    where = np.zeros((ne, 3))
    height = np.full(ne, -np.inf)
    for axis in range(3):                           # the face whose centre lies highest
        for side in (0.0, 1.0):
            X = np.full((3, 1), 0.5)
            X[axis] = side
            basis = Basis(mesh, ElementHex2(), quadrature=(X, np.array([1.0])))
            p = basis.mapping.F(X)[:, :, 0]                            # (3, ne)
            up = p[2] > height + _TOL
            height[up] = p[2, up]
            where[up] = p[:, up].T
            for c in range(3):
                grad[up, c] = basis.interpolate(u[c::3]).grad[:, up, 0].T
    eps = 0.5 * (grad + np.transpose(grad, (0, 2, 1)))
    lam = young * poisson / ((1 + poisson) * (1 - 2 * poisson))
    mu = young / (2 * (1 + poisson))
    sigma = 2 * mu * eps + lam * np.trace(eps, axis1=1, axis2=2)[:, None, None] * np.eye(3)
    return where, sigma

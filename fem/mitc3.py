"""Element quantities of the flat three-node shell triangle, vectorised
over the triangles: MITC3 transverse shear, constant-strain membrane and
bending operators (smoothed over edges by :mod:`flexbed.fem.edge_smoothing`),
consistent mass.

Same five DOFs per node as the four-node shell (:mod:`flexbed.fem.mitc4`):
u, v, w, θx, θy; a point at height z moves by U = (u + z θy, v − z θx, w),
so the normal's slopes are β = (θy, −θx) and the transverse shear strain is
γ = ∇w + β. Every field is linear on the triangle.

* **Transverse shear: MITC3** (Lee & Bathe 2004). The tangential shear
  strain of the displacement field along each edge, taken at the edge's
  mid-point, is the tying value; the assumed strain is the field
  γ = a + b (−(y − y_c), x − x_c) (the lowest Raviart–Thomas–Nédélec space,
  three parameters) with exactly these three edge values. It is isotropic
  (independent of the node numbering) and removes shear locking: a
  Kirchhoff motion (w quadratic, β = −∇w… linear) has zero tied shear.
  Shear correction factor 5/6; the integrand is quadratic and integrated
  exactly. MITC3 alone still locks mildly on thin plates (t/L = 1/1000:
  13 % error on 2 × 16 × 16 triangles for FV12's twisting modes, where
  MITC4 has 0.6 %); the shear modulus is therefore scaled by
  t² / (t² + α h²), h the longest side, α = 0.05 (the stabilisation of
  Lyly, Stenberg & Vihinen 1993), which removes it (1.2 % there) and
  tends to 1 as the mesh is refined (0.99 for the reference bed,
  t = 0.1 m, on 2 × 24 × 144 triangles).
* **Membrane and bending operators**: the constant strain ε = (u,x, v,y,
  u,y + v,x) and curvature κ = (βx,x, βy,y, βx,y + βy,x) of the linear
  fields (``Bm``, ``Bb``). On its own the constant-strain triangle is much
  too stiff in in-plane bending; the shell smooths both over edge domains
  (ES-FEM, Liu, Nguyen-Thoi & Lam 2009), which is exact for constant
  strain and curvature (the patch tests) and much softer in bending.
* **Mass**: consistent, ρt ∫N_i N_j dA = ρtA (1 + δ_ij) / 12 on the
  translations and ρt³/12 times the same on the rotations (rotary
  inertia), exact.
"""

from __future__ import annotations

import numpy as np

from .mitc4 import SHEAR_FACTOR

#: the scalar mass pattern ∫N_i N_j dA / A of a linear triangle
#: α of the shear stabilisation t² / (t² + α h²) (Lyly, Stenberg & Vihinen 1993)
STABILISATION = 0.05
_MASS = (np.ones((3, 3)) + np.eye(3)) / 12.0


def gradients(xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Area and shape-function gradients of linear triangles.

    Parameters
    ----------
    xy : ndarray (nt, 3, 2)
        Corner coordinates, counter-clockwise [m].

    Returns
    -------
    area : ndarray (nt,) [m²]
    dNx : ndarray (nt, 3, 2)
        ∂N_i/∂x, ∂N_i/∂y [1/m].
    """
    x, y = xy[:, :, 0], xy[:, :, 1]
    xj, yj = np.roll(x, -1, axis=1), np.roll(y, -1, axis=1)          # next corner
    xk, yk = np.roll(x, -2, axis=1), np.roll(y, -2, axis=1)          # the one after
    area = 0.5 * ((x[:, 1] - x[:, 0]) * (y[:, 2] - y[:, 0])
                  - (x[:, 2] - x[:, 0]) * (y[:, 1] - y[:, 0]))
    dNx = np.stack([yj - yk, xk - xj], axis=-1) / (2.0 * area)[:, None, None]
    return area, dNx


def strain_operators(dNx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Membrane strain and bending curvature operators, (nt, 3, 15) each,
    on the DOFs (u, v, w, θx, θy) of the three corners [1/m]."""
    nt = dNx.shape[0]
    U, V, TX, TY = (np.arange(3) * 5 + k for k in (0, 1, 3, 4))
    Bm = np.zeros((nt, 3, 15))
    Bm[:, 0, U] = dNx[:, :, 0]
    Bm[:, 1, V] = dNx[:, :, 1]
    Bm[:, 2, U] = dNx[:, :, 1]
    Bm[:, 2, V] = dNx[:, :, 0]
    Bb = np.zeros((nt, 3, 15))                       # β = (θy, −θx)
    Bb[:, 0, TY] = dNx[:, :, 0]
    Bb[:, 1, TX] = -dNx[:, :, 1]
    Bb[:, 2, TY] = dNx[:, :, 1]
    Bb[:, 2, TX] = -dNx[:, :, 0]
    return Bm, Bb


def shear_stiffness(xy: np.ndarray, area: np.ndarray, thickness: np.ndarray, young: float,
                    poisson: float) -> np.ndarray:
    """MITC3 transverse-shear stiffness (nt, 15, 15) [N/m per unit DOF²].

    Parameters
    ----------
    xy : ndarray (nt, 3, 2)
        Counter-clockwise corners [m].
    area : ndarray (nt,) [m²]
    thickness : ndarray (nt,) [m]
    young, poisson : float
        E [Pa], ν [-].
    """
    nt = xy.shape[0]
    W, TX, TY = 2, 3, 4
    centre = xy.mean(axis=1)                                          # (nt, 2)
    # tying: e_k · γ at the mid-point of edge k (from corner k to k + 1),
    # = (w_j − w_i) + e_k · (β_i + β_j) / 2 for the linear fields
    tau = np.zeros((nt, 3, 15))
    A = np.zeros((nt, 3, 3))
    for k in range(3):
        i, j = k, (k + 1) % 3
        e = xy[:, j] - xy[:, i]                                       # (nt, 2)
        m = 0.5 * (xy[:, i] + xy[:, j]) - centre
        tau[:, k, 5 * j + W] += 1.0
        tau[:, k, 5 * i + W] -= 1.0
        for n in (i, j):
            tau[:, k, 5 * n + TY] += 0.5 * e[:, 0]                   # βx = θy
            tau[:, k, 5 * n + TX] -= 0.5 * e[:, 1]                   # βy = −θx
        A[:, k] = np.column_stack([e[:, 0], e[:, 1], -e[:, 0] * m[:, 1] + e[:, 1] * m[:, 0]])
    coef = np.linalg.solve(A, tau)                                    # (nt, 3, 15): a_x, a_y, b
    # ∫ PᵀP dA with P = [[1, 0, −(y − y_c)], [0, 1, x − x_c]]: diag(A, A, polar moment)
    r = xy - centre[:, None, :]
    polar = area / 12.0 * np.sum(r * r, axis=(1, 2))
    weight = np.stack([area, area, polar], axis=1)                    # (nt, 3)
    t = np.asarray(thickness, float)
    h2 = np.max(np.sum((xy - np.roll(xy, 1, axis=1)) ** 2, axis=2), axis=1)   # longest side²
    G = SHEAR_FACTOR * young / (2.0 * (1.0 + poisson))
    Gs = G * t * t * t / (t * t + STABILISATION * h2)                # stabilised
    return Gs[:, None, None] * np.einsum("eki,ek,ekj->eij", coef, weight, coef)


def mass_blocks(area: np.ndarray, thickness: np.ndarray, density: float
                ) -> tuple[np.ndarray, np.ndarray]:
    """Scalar consistent mass blocks (nt, 3, 3): ρt ∫N_i N_j dA [kg] and
    ρt³/12 ∫N_i N_j dA [kg m²]."""
    t = np.asarray(thickness, float)
    base = area[:, None, None] * _MASS
    return (density * t)[:, None, None] * base, (density * t ** 3 / 12.0)[:, None, None] * base


def drilling_operator(dNx: np.ndarray) -> np.ndarray:
    """Operator (nt, 6) giving the in-plane rotation ½(∂v/∂x − ∂u/∂y) of each
    triangle from its corners' (u1, v1, u2, v2, u3, v3) [1/m]."""
    out = np.zeros((dNx.shape[0], 6))
    out[:, 0::2] = -0.5 * dNx[:, :, 1]
    out[:, 1::2] = 0.5 * dNx[:, :, 0]
    return out

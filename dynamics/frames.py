"""Points carried by body frames: a frame's rotation applied to vectors at
many samples, in one fixed order of operations.

``apply(A, u)`` gives A u and ``apply_t(A, w)`` Aᵀ w for rotation matrices
A (k, 3, 3), each component summed as ``(A_i0 u_0 + A_i1 u_1) + A_i2 u_2``
(NumPy's ``einsum`` may sum in another order, which depends on the
machine's vector instructions). :func:`point_path` gives the same numbers
as ``r + apply(rotation.A(p̂), u)`` with p̂ the unit Euler parameters
(``p / |p|``, as :func:`flexbed.dynamics.history.body_poses` normalises
them) in compiled code, one sample at a time, without the (k, 3, 3)
matrices: a study's peak of a point's displacement
(:mod:`flexbed.study.outputs`) reads the numbers a results file's point
(:meth:`flexbed.analyses.points.Run.absolute`) gives, bit for bit, at a
twentieth of the cost.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["apply", "apply_t", "point_path"]


def apply(A: np.ndarray, u: np.ndarray) -> np.ndarray:
    """A u (..., 3) for A (..., 3, 3) and u (..., 3) [any unit]."""
    return (A[..., :, 0] * u[..., None, 0] + A[..., :, 1] * u[..., None, 1]
            + A[..., :, 2] * u[..., None, 2])


def apply_t(A: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Aᵀ w (..., 3) for A (..., 3, 3) and w (..., 3) [any unit]."""
    return (A[..., 0, :] * w[..., None, 0] + A[..., 1, :] * w[..., None, 1]
            + A[..., 2, :] * w[..., None, 2])


@njit(cache=True, inline="always")
def _unit(e0, e1, e2, e3):
    n = math.sqrt(((e0 * e0 + e1 * e1) + e2 * e2) + e3 * e3)
    return e0 / n, e1 / n, e2 / n, e3 / n


@njit(cache=True, inline="always")
def _matrix(p, k, A):
    """A (3, 3) = rotation.A of the unit Euler parameters of p[k] (p[k]
    normalised twice: a body's stored parameters, then rotation.A's own)."""
    e0, e1, e2, e3 = _unit(p[k, 0], p[k, 1], p[k, 2], p[k, 3])
    e0, e1, e2, e3 = _unit(e0, e1, e2, e3)
    d = 2.0 * e0 * e0 - 1.0
    t = 2.0 * e0
    a1, a2, a3 = 2.0 * e1, 2.0 * e2, 2.0 * e3
    A[0, 0] = d + a1 * e1
    A[1, 1] = d + a2 * e2
    A[2, 2] = d + a3 * e3
    A[0, 1] = a1 * e2 + t * -e3
    A[0, 2] = a1 * e3 + t * e2
    A[1, 0] = a2 * e1 + t * e3
    A[1, 2] = a2 * e3 + t * -e1
    A[2, 0] = a3 * e1 + t * -e2
    A[2, 1] = a3 * e2 + t * e1


@njit(cache=True)
def point_path(r, p, u, r_ref, p_ref, relative):
    """Positions (k, 3) [m] of a point fixed in a body.

    Parameters
    ----------
    r : (k, 3) float64 [m]
        The body's origin.
    p : (k, 4) float64
        Its Euler parameters (any length: normalised as
        :func:`flexbed.dynamics.history.body_poses` and then
        :func:`flexbed.dynamics.rotation.A` do).
    u : (3,) float64 [m]
        The point in the body's frame.
    r_ref, p_ref : (k, 3), (k, 4) float64
        Another body's origin and Euler parameters (read when
        ``relative``).
    relative : bool
        Give the position relative to the other body, in its frame:
        A_refᵀ (R − r_ref); else the inertial position R = r + A u.
    """
    k = r.shape[0]
    out = np.empty((k, 3))
    A = np.empty((3, 3))
    B = np.empty((3, 3))
    for s in range(k):
        _matrix(p, s, A)
        R0 = r[s, 0] + ((A[0, 0] * u[0] + A[0, 1] * u[1]) + A[0, 2] * u[2])
        R1 = r[s, 1] + ((A[1, 0] * u[0] + A[1, 1] * u[1]) + A[1, 2] * u[2])
        R2 = r[s, 2] + ((A[2, 0] * u[0] + A[2, 1] * u[1]) + A[2, 2] * u[2])
        if relative:
            _matrix(p_ref, s, B)
            w0, w1, w2 = R0 - r_ref[s, 0], R1 - r_ref[s, 1], R2 - r_ref[s, 2]
            R0 = (B[0, 0] * w0 + B[1, 0] * w1) + B[2, 0] * w2
            R1 = (B[0, 1] * w0 + B[1, 1] * w1) + B[2, 1] * w2
            R2 = (B[0, 2] * w0 + B[1, 2] * w1) + B[2, 2] * w2
        out[s, 0], out[s, 1], out[s, 2] = R0, R1, R2
    return out

"""Compiled passes over a run's output samples for a study's metrics: a
point's positions from the states (:func:`point_path`) and the peaks of
norms (:func:`peak_norms`), one sample at a time, without the (k, 3, 3)
frames or the temporaries the same NumPy expressions make (a twentieth of
their cost on 3,001 samples).

Each gives the numbers of the NumPy code it stands for bit for bit: the
same operations in the same order (no fused multiply-adds: numba does not
contract without ``fastmath``), as tests check.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .jitcache import refresh as _refresh

__all__ = ["point_path", "peak_norms"]

_refresh()   # before any compiled function is loaded (flexbed.dynamics.jitcache)


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
    """Positions (k, 3) [m] of a point fixed in a body: ``r +
    frames.apply(rotation.A(p / |p|), u)``, or with ``relative``
    ``frames.apply_t(A_ref, R − r_ref)``, the numbers of
    :meth:`flexbed.analyses.points.Run.absolute` (``relative``) bit for bit.

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


@njit(cache=True)
def peak_norms(v):
    """max over k of |v[k, j]| (m,) for v (k, m, 3): the squares summed as
    ``(v0² + v1²) + v2²``, the largest rooted (NumPy's
    ``np.linalg.norm(v, axis=-1).max(axis=0)`` bit for bit: the root is
    monotone and correctly rounded; a NaN anywhere gives NaN)."""
    k, m = v.shape[0], v.shape[1]
    out = np.full(m, -np.inf)
    for i in range(k):
        for j in range(m):
            s = (v[i, j, 0] * v[i, j, 0] + v[i, j, 1] * v[i, j, 1]) + v[i, j, 2] * v[i, j, 2]
            if s > out[j] or s != s:
                out[j] = s
    for j in range(m):
        out[j] = math.sqrt(out[j]) if out[j] == out[j] else out[j]
    return out

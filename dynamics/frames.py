"""Points carried by body frames: a frame's rotation applied to vectors at
many samples, in one fixed order of operations.

``apply(A, u)`` gives A u and ``apply_t(A, w)`` Aᵀ w for rotation matrices
A (k, 3, 3), each component summed as ``(A_i0 u_0 + A_i1 u_1) + A_i2 u_2``
(NumPy's ``einsum`` may sum in another order, which depends on the
machine's vector instructions). :func:`flexbed.dynamics.sample_passes.point_path`
computes the same sums in the same order in compiled code: a results
file's points (:meth:`flexbed.analyses.points.Run.absolute`) and a study's
peaks of displacement agree bit for bit.
"""

from __future__ import annotations

import numpy as np

__all__ = ["apply", "apply_t"]


def apply(A: np.ndarray, u: np.ndarray) -> np.ndarray:
    """A u (..., 3) for A (..., 3, 3) and u (..., 3) [any unit]."""
    return (A[..., :, 0] * u[..., None, 0] + A[..., :, 1] * u[..., None, 1]
            + A[..., :, 2] * u[..., None, 2])


def apply_t(A: np.ndarray, w: np.ndarray) -> np.ndarray:
    """Aᵀ w (..., 3) for A (..., 3, 3) and w (..., 3) [any unit]."""
    return (A[..., 0, :] * w[..., None, 0] + A[..., 1, :] * w[..., None, 1]
            + A[..., 2, :] * w[..., None, 2])

"""Static correction of the truncated bed modes at the mount points.

A bed that keeps its n lowest modes loses the quasi-static deflection that
the mount forces cause in the modes left out. ``[bed] static_correction =
true`` adds it back as residual vectors (modal truncation augmentation):

1. the mount forces act on the bed at its mount points P (D = 3 per point);
   a unit force along direction d at P deflects the left-out modes
   R = n … N−1 of the modes file statically by
   ``c_d = K_R⁻¹ Φ_R(P)ᵀ e_d`` (Φ_R(P) : (D, |R|) their translations there);
2. an orthonormal basis Q of span{c_d} (SVD, dependent directions dropped:
   a mid-surface point has no in-plane modal translation);
3. Rayleigh–Ritz in that span: ``(Qᵀ K_R Q) v = ω² (Qᵀ M_R Q) v``, so that the
   residual vectors B = Q V are mass-orthonormal, stiffness-orthogonal, and
   orthogonal to the kept modes (they are combinations of the others).

The bed's coordinates are then a' with ``a = T a'``, T = [[I_n, 0], [0, B]]
(N × (n + m)), and every modal invariant follows by the change of
coordinates (:func:`change_of_modes`). The correction is exact for the
static response of modes n … N−1 to forces at the mount points, and it
is what a first-order dynamic correction needs when those modes are far
above the excitation; modes above the file's N are still left out.
"""

from __future__ import annotations

import numpy as np
from scipy.linalg import eigh

__all__ = ["residual_basis", "change_of_modes", "SVD_RTOL"]

#: singular values below SVD_RTOL × the largest mark dependent load directions
SVD_RTOL = 1e-8


def residual_basis(modal_mass: np.ndarray, modal_stiffness: np.ndarray,
                   mount_shapes: np.ndarray, n_kept: int) -> tuple[np.ndarray, np.ndarray]:
    """The change of coordinates a = T a' with residual vectors.

    Parameters
    ----------
    modal_mass, modal_stiffness : (N, N)
        I6 [–] and K_aa [s⁻²] of the modes file's N modes.
    mount_shapes : (N, D)
        Translation of each mode at the bed's mount points, D = 3 × points
        [kg^-1/2].
    n_kept : int
        Modes kept as they are (the lowest), n_kept < N.

    Returns
    -------
    T : (N, n_kept + m)
        Columns: the kept modes, then the m residual vectors as combinations
        of modes n_kept … N−1.
    omega : (m,)
        The residual vectors' Ritz frequencies [rad/s].
    """
    N = modal_mass.shape[0]
    R = slice(n_kept, N)
    C = np.linalg.solve(modal_stiffness[R, R], mount_shapes[R])          # (|R|, D)
    U, s, _ = np.linalg.svd(C, full_matrices=False)
    if s.size == 0 or s[0] == 0.0:
        Q = np.zeros((N - n_kept, 0))
    else:
        Q = U[:, s > SVD_RTOL * s[0]]
    Kr = Q.T @ modal_stiffness[R, R] @ Q
    Mr = Q.T @ modal_mass[R, R] @ Q
    w2, V = eigh(0.5 * (Kr + Kr.T), 0.5 * (Mr + Mr.T))
    T = np.zeros((N, n_kept + Q.shape[1]))
    T[:n_kept, :n_kept] = np.eye(n_kept)
    T[R, n_kept:] = Q @ V
    return T, np.sqrt(np.maximum(w2, 0.0))


def change_of_modes(T: np.ndarray, *, I3, I4, I5, I6, I8, I9, K, shapes) -> dict:
    """The invariants of the coordinates a' (a = T a') from those of a.

    Linear in the mode shapes: I3, I4 (3, N) → (3, n'); I8 (N, 3, 3) →
    (n', 3, 3); shapes (N, P, 3) → (n', P, 3). Bilinear: I5 (N, 3, N),
    I6 (N, N), I9 (N, N, 3, 3), K (N, N).
    """
    return {
        "I3": I3 @ T, "I4": I4 @ T,
        "I5": np.einsum("ka,kcl,lb->acb", T, I5, T),
        "I6": T.T @ I6 @ T,
        "I8": np.einsum("ka,kij->aij", T, I8),
        "I9": np.einsum("ka,klij,lb->abij", T, I9, T),
        "K": T.T @ K @ T,
        "shapes": np.einsum("ka,kpc->apc", T, shapes),
    }

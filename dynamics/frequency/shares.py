"""Energy tables of mode shapes: the kinetic energy share of each coordinate
and the strain energy share of each mount axis and of the flexible bodies'
own deformation (see :mod:`flexbed.dynamics.frequency.modal`).

Each table is a *raw* energy per mode (:func:`kinetic`, :func:`strain`:
time-averaged, up to the mode's common factor) divided by its sum over the
mode (:func:`shares`), so the raw energies may come from elsewhere — the
hub-and-leaves solution writes those of its modes with the hub at rest
from their structure (:mod:`flexbed.dynamics.frequency.star_modes`) —
and be divided alike.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from .mounted import DENSE_LIMIT, MountedSystem

__all__ = ["sparse_of", "times", "bilinear", "kinetic", "strain", "shares"]

#: modes per block of a large system's strain table (its temporaries stay small)
_BLOCK = 128


def sparse_of(ms: MountedSystem, name: str):
    """``ms``'s matrix ``name`` as CSR (M from ``ms.sparse``, D from
    ``ms.mount_rows``)."""
    if name == "M" and ms.sparse is not None:
        return ms.sparse[0]
    if name == "D" and ms.mount_rows is not None:
        return ms.mount_rows[0]
    return sp.csr_matrix(getattr(ms, name))


def times(B, c: np.ndarray) -> np.ndarray:
    """Rows of ``c @ Bᵀ`` (m, r) for B (r, n) sparse and real, c (m, n) real
    or complex (a complex c as its real and imaginary parts side by side:
    one real product, half the work of a complex one)."""
    ct = np.ascontiguousarray(c.T)
    if np.iscomplexobj(c):
        return (B @ ct.view(float)).view(complex).T
    return (B @ ct).T


def bilinear(a: np.ndarray, B, c: np.ndarray, large: bool) -> np.ndarray:
    """aₖᴴ B cₖ for each row k of a and c (m, n), B (n, n) dense or sparse.
    A large system's by a sparse product (B block-sparse by the mount graph);
    a small one's by the einsum, whose sums its results were made with."""
    if large:
        return np.sum(a.conj() * times(B, c), axis=1)
    return np.einsum("ki,ij,kj->k", a.conj(), B, c)


def kinetic(ms: MountedSystem, phi: np.ndarray) -> np.ndarray:
    """``Re(φ̄_j (M φ)_j)`` (m, n) for shapes φ (m, n)."""
    Mphi = times(sparse_of(ms, "M"), phi) if ms.n > DENSE_LIMIT else phi @ ms.M.T
    return (phi.conj() * Mphi).real


def strain(ms: MountedSystem, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``½ k_t |D φ|²`` of each mount axis (m, 3M) and ``½ Re(φᴴ K_el φ)``
    (m,) for shapes φ (m, n)."""
    large = ms.n > DENSE_LIMIT
    if large:                                # by blocks of modes, into one array
        D = sparse_of(ms, "D")
        half_k = 0.5 * ms.k_tangent
        mounts = np.empty((phi.shape[0], D.shape[0]))
        for a in range(0, phi.shape[0], _BLOCK):
            dx = times(D, phi[a:a + _BLOCK])                               # (b, 3M)
            mounts[a:a + _BLOCK] = (dx.real ** 2 + dx.imag ** 2) * half_k
    else:
        dx = phi @ ms.D.T                                                  # (m, 3M)
        mounts = 0.5 * ms.k_tangent[None, :] * np.abs(dx) ** 2
    if large and not ms.K_elastic.any():                          # a rigid bed
        elastic = np.zeros(phi.shape[0])
    else:
        elastic = 0.5 * bilinear(phi, sparse_of(ms, "K_elastic") if large else ms.K_elastic,
                                 phi, large).real
    return mounts, elastic


def shares(energy: np.ndarray, mounts: np.ndarray, elastic: np.ndarray):
    """The tables from the raw energies (m, n), (m, 3M), (m,) (``energy`` and
    ``mounts`` divided in place): kinetic shares (m, n), mount axes' (m, M, 3),
    the deformation's (m,)."""
    total = mounts.sum(axis=1) + elastic
    total = np.where(total != 0.0, total, 1.0)
    mounts /= total[:, None]
    energy /= energy.sum(axis=1, keepdims=True)
    return energy, mounts.reshape(mounts.shape[0], -1, 3), elastic / total

"""The dynamic stiffness ``G(ω) = K − ω² M + iω C`` of a large mounted system
solved by blocks, many frequencies at once.

The coordinates belong to bodies (``MountedSystem.body``) and bodies are
coupled only through mounts, so G is block-sparse by the mount graph. A
set L of bodies no two of which share a mount (the *leaves*: on a raft,
the pieces of equipment) makes ``G_LL`` block-diagonal; the others (the
*hubs*: the bed) are few. Then, per frequency, exactly (Gaussian
elimination in that order, no approximation):

    S = G_HH − G_HL G_LL⁻¹ G_LH,   S x_H = r_H − G_HL G_LL⁻¹ r_L,
    x_L = G_LL⁻¹ (r_L − G_LH x_H)

with the leaves' small blocks (6 × 6, or 6 + modes) factorised in one
batched call over leaves and frequencies, and S (hubs × hubs) dense. The
cost per frequency is O(leaves) + O(hubs³). :func:`block_plan` chooses the
leaves (a maximal independent set of the body graph, bodies of fewest
neighbours first) and says whether the hubs are few enough
(:data:`MAX_HUBS` coordinates); otherwise the caller factorises the
sparse G per frequency.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

__all__ = ["BlockPlan", "block_plan", "solve_blocks", "MAX_HUBS"]

#: most hub coordinates for which the block elimination is used
MAX_HUBS = 200
#: frequencies per batched block solve
_CHUNK = 64


@dataclass(frozen=True)
class BlockPlan:
    """How to eliminate: ``leaf_index`` (nL, w) the coordinates of each leaf
    body (all leaves have w coordinates: one plan per block size is not
    needed on the scenes this serves, so leaves of another size count as
    hubs); ``hub`` (nH,) the hubs' coordinates; the dense pieces of K, M, C:
    ``LL`` (3, nL, w, w), ``LH`` (3, nL, w, nH), ``HL`` (3, nL, nH, w),
    ``HH`` (3, nH, nH)."""

    leaf_index: np.ndarray
    hub: np.ndarray
    LL: np.ndarray
    LH: np.ndarray
    HL: np.ndarray
    HH: np.ndarray


def block_plan(K: sp.spmatrix, M: sp.spmatrix, C: sp.spmatrix, body: np.ndarray
               ) -> BlockPlan | None:
    """The elimination plan, or None when it would not pay (no leaves, no
    hubs, or more than :data:`MAX_HUBS` hub coordinates).

    K, M, C : (n, n) sparse; body : (n,) the body each coordinate belongs to.
    """
    body = np.asarray(body)
    owners, coord_body = np.unique(body, return_inverse=True)
    nb = owners.size
    pattern = (abs(K) + abs(M) + abs(C)).tocoo()
    a, b = coord_body[pattern.row], coord_body[pattern.col]
    off = a != b
    adj = sp.coo_matrix((np.ones(int(off.sum())), (a[off], b[off])), shape=(nb, nb)).tocsr()
    adj = ((adj + adj.T) > 0).tocsr()
    degree = np.diff(adj.indptr)
    sizes = np.bincount(coord_body, minlength=nb)
    w = int(np.bincount(sizes).argmax()) if nb else 0
    leaf = np.zeros(nb, dtype=bool)
    blocked = np.zeros(nb, dtype=bool)
    for k in np.argsort(degree, kind="stable"):
        if blocked[k] or sizes[k] != w:
            continue
        leaf[k] = True
        blocked[adj.indices[adj.indptr[k]:adj.indptr[k + 1]]] = True
    hub = np.flatnonzero(~leaf[coord_body])
    if not leaf.any() or hub.size == 0 or hub.size > MAX_HUBS:
        return None
    leaf_index = np.stack([np.flatnonzero(coord_body == k) for k in np.flatnonzero(leaf)])

    nL = leaf_index.shape[0]
    leaf_of = np.full(body.size, -1)
    local = np.zeros(body.size, dtype=np.intp)
    leaf_of[leaf_index] = np.arange(nL)[:, None]
    local[leaf_index] = np.arange(w)[None, :]
    hub_pos = np.full(body.size, -1)
    hub_pos[hub] = np.arange(hub.size)

    def pieces(A):
        A = A.tocoo()
        r, c, v = A.row, A.col, A.data
        lr, lc = leaf_of[r], leaf_of[c]
        LL = np.zeros((nL, w, w))
        LH = np.zeros((nL, w, hub.size))
        HL = np.zeros((nL, hub.size, w))
        HH = np.zeros((hub.size, hub.size))
        k = (lr >= 0) & (lc >= 0)
        assert np.all(lr[k] == lc[k]), "leaves coupled to each other"
        np.add.at(LL, (lr[k], local[r[k]], local[c[k]]), v[k])
        k = (lr >= 0) & (lc < 0)
        np.add.at(LH, (lr[k], local[r[k]], hub_pos[c[k]]), v[k])
        k = (lr < 0) & (lc >= 0)
        np.add.at(HL, (lc[k], hub_pos[r[k]], local[c[k]]), v[k])
        k = (lr < 0) & (lc < 0)
        np.add.at(HH, (hub_pos[r[k]], hub_pos[c[k]]), v[k])
        return LL, LH, HL, HH

    parts = [pieces(A) for A in (K, M, C)]
    return BlockPlan(leaf_index, hub, *(np.stack([p[i] for p in parts]) for i in range(4)))


def solve_blocks(plan: BlockPlan, omega: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """x (k, n) with ``G(ω_k) x = rhs`` for every ω (k,) [rad/s]; rhs (n,)."""
    omega = np.asarray(omega, dtype=float)
    nL, w = plan.leaf_index.shape
    nH = plan.hub.size
    n = nL * w + nH
    X = np.empty((omega.size, n), dtype=complex)
    rL = rhs[plan.leaf_index].astype(complex)                # (nL, w)
    rH = rhs[plan.hub].astype(complex)                       # (nH,)
    for s in range(0, omega.size, _CHUNK):
        om = omega[s:s + _CHUNK]
        f = om.size
        w2 = om * om

        def at(parts, w2=w2, om=om):
            """K − ω² M + iω C of the pieces, (f, ...), built in place."""
            shape = (-1,) + (1,) * (parts.ndim - 1)
            G = np.empty((om.size,) + parts.shape[1:], dtype=complex)
            G.real = parts[0][None] - w2.reshape(shape) * parts[1][None] \
                if parts[1].any() else np.broadcast_to(parts[0], G.shape)
            G.imag = om.reshape(shape) * parts[2][None]
            return G

        GLL, GHL, GHH = at(plan.LL), at(plan.HL), at(plan.HH)
        rhs_L = np.empty((f, nL, w, nH + 1), dtype=complex)
        rhs_L[..., :nH] = at(plan.LH)
        rhs_L[..., nH] = rL[None]
        Y = np.linalg.solve(GLL, rhs_L)                      # G_LL⁻¹ [G_LH, r_L]
        T = np.matmul(GHL, Y).sum(axis=1)                    # (f, nH, nH + 1)
        S = GHH - T[:, :, :nH]
        xH = np.linalg.solve(S, (rH[None, :] - T[:, :, nH])[..., None])[..., 0]
        xL = Y[..., nH] - np.matmul(Y[..., :nH], xH[:, None, :, None])[..., 0]
        X[s:s + f, plan.leaf_index.reshape(-1)] = xL.reshape(f, nL * w)
        X[s:s + f, plan.hub] = xH
    return X

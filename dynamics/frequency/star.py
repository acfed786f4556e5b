"""Eigen-solution of a hub-and-leaves matrix, exact but for a stated
perturbation, in O(n²) rather than a dense O(n³) solve.

A matrix of *star* form couples every leaf block only to the hub (the
states of one bed carrying many pieces of equipment, each mounted to the
bed and the base only):

    A = [[A_LL,  A_LH],     A_LL = diag(A_ℓℓ) (nL blocks s × s),
         [A_HL,  A_HH]]     A_HH (H × H), A_ℓH (s × H), A_Hℓ (H × s).

Each leaf block is diagonalised, ``A_ℓℓ = V_ℓ diag(μ_ℓ) V_ℓ⁻¹``; in the
leaves' modal coordinates A is an arrowhead matrix, diag(μ) bordered by
the rows ``R_m = (V_ℓ⁻¹ A_ℓH)_k`` (hub → leaf mode m = (ℓ, k)) and the
columns ``C_m = (A_Hℓ V_ℓ)_k`` (leaf mode → hub). Leaf modes whose μ agree
to :data:`GROUP_TOL` (identical pieces of equipment) form a group G of g.
With μ_G their mean and the singular value decomposition of the group's
columns' conjugates beside its rows, ``[C̄_m, R_m]_{m∈G} = Q Σ Wᴴ``
(g × 2H, each half scaled to unit norm), split Q = [Q₁, Q₂] at the rank r
(singular values above :data:`RANK_TOL` times the largest; r ≤ 2H however
many leaves, 1 to 12 on the tiled rafts): the g − r combinations Q₂
neither drive the hub (``C Q₂ = 0``) nor feel it (``Q₂ᴴ R = 0``), so

    A [Q₂ in leaf modes; hub 0] = μ_G [Q₂; 0],   [Q₂ᴴ; 0] A = μ_G [Q₂ᴴ; 0]

exactly: they are eigenvectors, right and left, with the hub at rest. What
is left, the hub and the r combinations Q₁ of every group, is a dense
matrix of ``H + Σ r_G`` states (60 for 128 pieces of equipment of two
kinds on a rigid bed, against 1548), decoupled from the Q₂ states: its
eigenpairs are the others, mapped back through Q₁ and V_ℓ, and its
inverse eigenvector matrix gives their left vectors.

Error: the result is the exact eigen-solution of ``A + E`` with ``‖E‖₂``
at most the largest spread |μ_m − μ_G| within a group plus the largest
singular value dropped (:attr:`StarEig.bound`, measured); eigenvalues move
by at most κ‖E‖₂ (Bauer–Fike, κ the condition number of the eigenvector
matrix). :func:`star_eig` measures the residual ``‖A x − λ x‖ / (‖A‖_F ‖x‖)``
of every pair from the dense solution (an eliminated pair's is at most
``bound / ‖A‖_F``, from the construction) and returns None when either
exceeds :data:`RESIDUAL_TOL` (the caller then solves densely); the left vectors are
the rows of the inverse of the same (block-diagonal) vector matrix, so
``left @ right = I`` by construction. Groups too small to leave a null
space (g ≤ r) are kept as they are, without the mean.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components
from scipy.spatial import KDTree

__all__ = ["Star", "StarEig", "star_eig", "GROUP_TOL", "RANK_TOL", "RESIDUAL_TOL"]

#: leaf eigenvalues within this many times max|μ| of each other form a group
GROUP_TOL = 1e-11
#: singular values of a group's [C̄, R] below this times the largest count as
#: zero (identical pieces' couplings differ by the linearisation's round-off,
#: ~1e-11 relative with a differenced stiffness: keeping those directions only
#: makes the dense part larger)
RANK_TOL = 1e-10
#: largest relative residual ‖A x − λ x‖ / (‖A‖_F ‖x‖) accepted
RESIDUAL_TOL = 1e-10


@dataclass(frozen=True)
class Star:
    """The pieces of a star-form matrix: ``leaf`` (nL, s, s) A_ℓℓ,
    ``leaf_hub`` (nL, s, H) A_ℓH, ``hub_leaf`` (nL, H, s) A_Hℓ, ``hub``
    (H, H) A_HH. Its states are ordered leaf 0 (s), …, leaf nL − 1, hub."""

    leaf: np.ndarray
    leaf_hub: np.ndarray
    hub_leaf: np.ndarray
    hub: np.ndarray

    @property
    def size(self) -> int:
        return self.leaf.shape[0] * self.leaf.shape[1] + self.hub.shape[0]

    def apply(self, X: np.ndarray) -> np.ndarray:
        """A X for X (size, k), by the pieces (O(nL s² k))."""
        nL, s, _ = self.leaf.shape
        XL = X[:nL * s].reshape(nL, s, -1)
        XH = X[nL * s:]
        YL = self.leaf @ XL + (self.leaf_hub.reshape(nL * s, -1) @ XH).reshape(nL, s, -1)
        YH = self.hub @ XH + self.hub_leaf.transpose(1, 0, 2).reshape(-1, nL * s) @ X[:nL * s]
        return np.vstack([YL.reshape(nL * s, -1), YH])

    def norm(self) -> float:
        """‖A‖_F."""
        return float(np.sqrt(sum(np.sum(np.abs(p) ** 2) for p in
                                 (self.leaf, self.leaf_hub, self.hub_leaf, self.hub))))


@dataclass(frozen=True)
class StarEig:
    """``values`` (n,) λ; ``right`` (n, n) right vectors (columns), rows in
    the star's order; ``left`` (n, n) or None, rows l with l A = λ l and
    ``left @ right = I``; ``reduced``: size of the dense eigen-solution;
    ``eliminated``: pairs found with the hub at rest; ``bound``: ‖E‖₂
    bound of the perturbation solved exactly; ``residual``: largest
    relative residual of the pairs; ``groups``: those pairs' right vectors
    by group, each ``(first, leaves (g,), vectors (g, s), coefficients (g, k))``:
    pair ``first + j`` is ``vectors[i] · coefficients[i, j]`` on leaf
    ``leaves[i]`` and zero elsewhere (None when a group holds two modes of
    one leaf, whose vectors add)."""

    values: np.ndarray
    right: np.ndarray
    left: np.ndarray | None
    reduced: int
    eliminated: int
    bound: float
    residual: float
    groups: tuple | None = None


def _groups(mu: np.ndarray, radius: float) -> list[np.ndarray]:
    """Indices of μ (m,) linked by distances ≤ radius (connected components)."""
    pts = np.column_stack([mu.real, mu.imag])
    pairs = KDTree(pts).query_pairs(radius, output_type="ndarray")
    g = sp.coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])) if len(pairs) else
                      (np.zeros(0), (np.zeros(0, int), np.zeros(0, int))),
                      shape=(mu.size, mu.size))
    _, label = connected_components(g, directed=False)
    order = np.argsort(label, kind="stable")
    cuts = np.flatnonzero(np.diff(label[order])) + 1
    return np.split(order, cuts)


def star_eig(a: Star, left: bool = False, select=None, group_tol: float = GROUP_TOL
             ) -> StarEig | None:
    """The eigenpairs of the star-form matrix ``a`` (see the module
    docstring), or None when a residual exceeds :data:`RESIDUAL_TOL`.

    left : bool
        Also the left vectors.
    select : callable, optional
        λ (k,) → bool (k,), called once with every distinct eigenvalue:
        only the pairs it keeps are built (default every one).
    """
    nL, s, _ = a.leaf.shape
    H = a.hub.shape[0]
    nm = nL * s
    mu, V = np.linalg.eig(a.leaf)                                   # (nL, s), (nL, s, s)
    Vinv = np.linalg.inv(V)
    R = (Vinv @ a.leaf_hub).reshape(nm, H)                          # rows R_m
    C = (a.hub_leaf @ V).transpose(0, 2, 1).reshape(nm, H)          # C_m as rows
    mu = mu.reshape(nm)
    scale = float(np.abs(mu).max()) if nm else 1.0
    kept_cols, kept_rows, kept_vals, kept_mu = [], [], [], []      # P: leaf modes → kept states
    elim = []                                   # (idx, Q₂, μ_G) of groups with a null space
    bound = 0.0
    n_kept = 0
    for idx in _groups(mu, group_tol * scale):
        g = idx.size
        if g > 1:
            Cg, Rg = C[idx].conj(), R[idx]                          # (g, H) each
            cn, rn = np.linalg.norm(Cg), np.linalg.norm(Rg)
            Z = np.hstack([Cg / (cn if cn > 0.0 else 1.0), Rg / (rn if rn > 0.0 else 1.0)])
            U, sv, _ = np.linalg.svd(Z, full_matrices=True)
            r = int(np.sum(sv > RANK_TOL * sv[0])) if sv[0] > 0.0 else 0
            if r < g:
                Q1, Q2 = U[:, :r], U[:, r:]
                mean = mu[idx].mean()
                dropped = float(sv[r]) * max(cn, rn) if r < sv.size else 0.0
                bound = max(bound, float(np.abs(mu[idx] - mean).max()) + dropped)
                elim.append((idx, Q2, mean))
                kept_rows.append(np.repeat(idx, r))
                kept_cols.append(n_kept + np.tile(np.arange(r), g))
                kept_vals.append(Q1.reshape(-1))
                kept_mu.append(np.full(r, mean))
                n_kept += r
                continue
        kept_rows.append(idx)
        kept_cols.append(n_kept + np.arange(g))
        kept_vals.append(np.ones(g))
        kept_mu.append(mu[idx])
        n_kept += g
    P = sp.csr_matrix((np.concatenate(kept_vals), (np.concatenate(kept_rows),
                                                   np.concatenate(kept_cols))),
                      shape=(nm, n_kept), dtype=complex)
    PH = P.conj().T.tocsr()
    nr = n_kept + H
    A_red = np.empty((nr, nr), dtype=complex)
    A_red[:n_kept, :n_kept] = np.diag(np.concatenate(kept_mu))
    A_red[:n_kept, n_kept:] = PH @ R
    A_red[n_kept:, :n_kept] = (PH @ C).T
    A_red[n_kept:, n_kept:] = a.hub
    lam_r, Y = np.linalg.eig(A_red)

    # vectors in leaf-mode coordinates (nm) and the hub's (H): the reduced
    # pairs, then the eliminated ones (Q₂ on their group, the hub at rest)
    keep = np.ones(nr, dtype=bool)
    if select is not None:                      # one call: every distinct value
        chosen = np.asarray(select(np.concatenate([lam_r, [e[2] for e in elim]])))
        keep = chosen[:nr]
        elim = [e for e, c in zip(elim, chosen[nr:]) if c]
    n_red = int(keep.sum())
    n_el = sum(e[1].shape[1] for e in elim)
    n = n_red + n_el
    Ys = Y[:, keep]
    lam = np.empty(n, dtype=complex)
    lam[:n_red] = lam_r[keep]
    # written as rows (one per pair), returned as their transpose: the columns
    # the callers gather by mode come out contiguous
    rows_r = np.zeros((n, nm + H), dtype=complex)
    rows_r[:n_red, :nm] = (V @ (P @ Ys[:n_kept]).reshape(nL, s, n_red)).reshape(nm, n_red).T
    rows_r[:n_red, nm:] = Ys[n_kept:].T
    st = rows_r.strides                  # the leaf columns as (pair, leaf, state), a view
    by_leaf = np.lib.stride_tricks.as_strided(rows_r, (n, nL, s), (st[0], s * st[1], st[1]))
    col = n_red
    groups = []
    for idx, Q2, mean in elim:           # leaf ℓ's states: V_ℓ[:, k] Q₂[(ℓ, k), :]
        k = Q2.shape[1]
        leaf, mode = np.divmod(idx, s)
        vectors = V[leaf, :, mode]                                              # (g, s)
        vals = vectors[..., None] * Q2[:, None, :]                              # (g, s, k)
        if groups is not None and np.unique(leaf).size == leaf.size:
            groups.append((col, leaf, vectors, Q2))
        else:
            groups = None
        step = leaf[1] - leaf[0] if leaf.size > 1 else 1
        if step > 0 and np.all(np.diff(leaf) == step):       # evenly spaced: a slice
            by_leaf[col:col + k, leaf[0]:leaf[-1] + 1:step, :] = vals.transpose(2, 0, 1)
        elif np.unique(leaf).size == leaf.size:
            by_leaf[col:col + k, leaf, :] = vals.transpose(2, 0, 1)
        else:                            # two of one leaf's modes in the group
            at = (leaf[:, None] * s + np.arange(s)[None, :])[None]              # (1, g, s)
            np.add.at(rows_r, (np.arange(col, col + k)[:, None, None], at),
                      vals.transpose(2, 0, 1))
        lam[col:col + k] = mean
        col += k
    right = rows_r.T

    L = None
    if left:
        Yinv = np.linalg.inv(Y)[keep]                               # rows over [kept, hub]
        lm = np.zeros((n, nm), dtype=complex)                       # left rows, leaf modes
        lh = np.zeros((n, H), dtype=complex)
        lm[:n_red] = (PH.T @ Yinv[:, :n_kept].T).T                  # Yinv_kept Pᴴ
        lh[:n_red] = Yinv[:, n_kept:]
        row = n_red
        for idx, Q2, _ in elim:
            k = Q2.shape[1]
            lm[row:row + k, idx] = Q2.conj().T
            row += k
        L = np.empty((n, nm + H), dtype=complex)
        L[:, :nm] = (lm.reshape(n, nL, s).transpose(1, 0, 2) @ Vinv).transpose(
            1, 0, 2).reshape(n, nm)
        L[:, nm:] = lh

    norm = a.norm()
    x = right[:, :n_red]                     # the eliminated pairs' residual is ≤ bound
    res = np.linalg.norm(a.apply(x) - x * lam[None, :n_red], axis=0) / (
        norm * np.linalg.norm(x, axis=0))
    worst = max(float(res.max()) if res.size else 0.0, bound / norm)
    if not worst <= RESIDUAL_TOL:
        return None
    return StarEig(lam, right, L, nr, n_el, bound, worst,
                   None if groups is None else tuple(groups))

"""The mounted system's two eigenproblems in hub-and-leaves form, solved by
:func:`~flexbed.dynamics.frequency.star.star_eig`.

The block plan of :mod:`flexbed.dynamics.frequency.blocks` splits the
coordinates into leaves (bodies no two of which share a mount: the pieces
of equipment) and the hub (the bed). With M block-diagonal by body (no
mass coupling between a leaf and the hub, checked here),

- undamped, the standard matrix ``M⁻¹K``: leaf blocks ``M_ℓ⁻¹K_ℓℓ``
  (w × w), couplings ``M_ℓ⁻¹K_ℓH`` and ``M_H⁻¹K_Hℓ``;
- damped, the first-order matrix ``[[0, I], [−M⁻¹K, −M⁻¹C]]`` with each
  body's states [q; q̇] together: leaf blocks
  ``[[0, I], [−M_ℓ⁻¹K_ℓℓ, −M_ℓ⁻¹C_ℓℓ]]`` (2w × 2w), the hub's alike, and
  couplings only in the rate rows (so a group of identical leaves keeps at
  most as many states as the hub has coordinates).

Both return what :mod:`flexbed.dynamics.frequency.modal` takes from its
dense solutions, in the coordinates' own order; None when the plan does
not apply or the structured solution's residual is too large. Both also
return a :class:`Structured`, whose :meth:`Structured.energies` writes the
modes' raw energy tables (:mod:`flexbed.dynamics.frequency.shares`): a
mode with the hub at rest is one vector per leaf of its group times a
coefficient (:attr:`flexbed.dynamics.frequency.star.StarEig.groups`), so
its kinetic energy on a leaf, its strain energy in a leaf's mounts and its
leaf's deformation are that leaf's own, once per group, times the squared
coefficient: outer products the size of the tables, where the general
products cost a pass over every mount row's coordinates for every mode.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import shares
from .blocks import BlockPlan, block_plan
from .mounted import MountedSystem
from .star import Star, StarEig, star_eig

__all__ = ["plan_of", "undamped", "damped", "Structured"]


@dataclass(frozen=True)
class Structured:
    """A structured solution's modes: ``got`` the star's pairs, ``rows``
    (m, n) their shapes (position states) in the coordinates' order,
    ``plan`` the block plan."""

    got: StarEig
    rows: np.ndarray
    plan: BlockPlan

    def energies(self, ms: MountedSystem, picked: np.ndarray):
        """The raw kinetic (k, n), mount-axis (k, 3M) and deformation (k,)
        energies (:func:`flexbed.dynamics.frequency.shares.kinetic`,
        :func:`~flexbed.dynamics.frequency.shares.strain`) of the pairs
        ``picked`` (k,) in that order, or None (a group with two modes of
        one leaf, or a mount row on two leaves)."""
        got, plan = self.got, self.plan
        if got.groups is None:
            return None
        nL, w = plan.leaf_index.shape
        Dc = shares.sparse_of(ms, "D")                    # CSR
        D = Dc.tocoo()
        leaf_of = np.full(ms.n, nL)                       # coordinate → leaf (nL: none)
        leaf_of[plan.leaf_index] = np.arange(nL)[:, None]
        low = np.full(D.shape[0], nL)
        high = np.full(D.shape[0], -1)
        np.minimum.at(low, D.row, leaf_of[D.col])
        np.maximum.at(high, D.row, np.where(leaf_of[D.col] < nL, leaf_of[D.col], -1))
        if np.any((high >= 0) & (low != high)):
            return None
        row_leaf = np.where(high >= 0, high, nL)          # each mount row's leaf (nL: none)
        m = got.values.size
        dest = np.full(m, -1)
        dest[picked] = np.arange(picked.size)
        first = m - got.eliminated                        # pairs before: the dense solution's
        general = np.flatnonzero(dest[:first] >= 0)
        energy = np.zeros((picked.size, ms.n))
        mounts = np.zeros((picked.size, D.shape[0]))
        elastic = np.zeros(picked.size)
        if general.size:
            phi = self.rows[general]
            energy[dest[general]] = shares.kinetic(ms, phi)
            mounts[dest[general]], elastic[dest[general]] = shares.strain(ms, phi)
        half_k = 0.5 * ms.k_tangent
        M_leaf = plan.LL[1]
        K_el = ms.K_elastic[plan.leaf_index[:, :, None], plan.leaf_index[:, None, :]]
        flexible = bool(K_el.any())
        for start, leaves, vectors, coef in got.groups:
            cols = start + np.arange(coef.shape[1])
            to = dest[cols]
            if not np.any(to >= 0):
                continue
            coef, to = coef[:, to >= 0], to[to >= 0]
            v = vectors[:, :w]                                             # position states
            weight = (coef.real ** 2 + coef.imag ** 2).T                   # (k, g)
            kin = (v.conj() * (M_leaf[leaves] @ v[..., None])[..., 0]).real    # (g, w)
            energy[to[:, None], plan.leaf_index[leaves].reshape(1, -1)] = (
                weight[:, :, None] * kin[None]).reshape(to.size, -1)
            y = np.zeros(ms.n, dtype=complex)
            y[plan.leaf_index[leaves]] = v
            dx = Dc @ y                                                    # (3M,)
            per_leaf = np.zeros((to.size, nL + 1))
            per_leaf[:, leaves] = weight
            own = half_k * (dx.real ** 2 + dx.imag ** 2)
            if to[-1] - to[0] == to.size - 1 and np.all(np.diff(to) == 1):   # one run of rows
                block = mounts[to[0]:to[-1] + 1]
                np.take(per_leaf, row_leaf, axis=1, out=block)
                block *= own
            else:
                mounts[to] = per_leaf[:, row_leaf] * own
            if flexible:
                bent = 0.5 * (v.conj() * (K_el[leaves] @ v[..., None])[..., 0]).sum(1).real
                elastic[to] = weight @ bent
        return energy, mounts, elastic


def plan_of(ms: MountedSystem) -> BlockPlan | None:
    """The block plan of ``ms``, or None (no sparse matrices or ones that
    are not ``ms``'s dense M, K, C — a copy with K or C replaced —, no
    leaves, too many hub coordinates, or mass coupling between leaves and
    hub)."""
    if ms.sparse is None:
        return None
    Ms, Ks, Cs = ms.sparse
    if not all(_equal(S, D) for S, D in ((Ms, ms.M), (Ks, ms.K), (Cs, ms.C))):
        return None
    plan = block_plan(Ks, Ms, Cs, ms.body)
    if plan is None or np.any(plan.LH[1]) or np.any(plan.HL[1]):
        return None
    return plan


def _equal(S, D: np.ndarray) -> bool:
    """Whether the sparse S equals the dense D entry for entry: D holds S's
    values at S's positions and no other nonzero (without densifying S)."""
    S = S.tocoo()
    nz = S.data != 0.0
    return (S.shape == D.shape and np.count_nonzero(D) == np.count_nonzero(nz)
            and bool(np.all(D[S.row[nz], S.col[nz]] == S.data[nz])))


def _perm(plan: BlockPlan) -> np.ndarray:
    """Coordinate of each star position (leaves' coordinates, then the hub's)."""
    return np.concatenate([plan.leaf_index.reshape(-1), plan.hub])


def undamped(ms: MountedSystem, plan: BlockPlan):
    """(λ, vl, vr, μ, structured) of ``K φ = λ M φ``: λ (n,) and vr (n, n)
    right vectors (columns) as ``_standard_eig`` gives them, vl (n, n) with
    ``vl_kᴴ K = λ_k vl_kᴴ M`` and ``vl_kᴴ M vr_l = δ_kl`` (both transposes of
    arrays of rows: Fortran order, a column is contiguous), μ (n,) the
    products ``vl_kᴴ M vr_k`` as computed (1 but for round-off), a
    :class:`Structured` of the vr; or None."""
    K, M = plan.LL[0], plan.LL[1]
    MH = plan.HH[1]
    star = Star(np.linalg.solve(M, K), np.linalg.solve(M, plan.LH[0]),
                np.linalg.solve(MH[None], plan.HL[0]), np.linalg.solve(MH, plan.HH[0]))
    got = star_eig(star, left=True)
    if got is None:
        return None
    nL, w = plan.leaf_index.shape
    nm = nL * w
    n = got.values.size
    perm = _perm(plan)
    # ψ = conj(M⁻ᵀ wᵀ): its rows conj(w M⁻¹), body by body
    left = np.empty((n, nm + MH.shape[0]), dtype=complex)
    left[:, :nm] = (got.left[:, :nm].reshape(n, nL, 1, w) @ np.linalg.inv(M)).reshape(n, nm)
    left[:, nm:] = got.left[:, nm:] @ np.linalg.inv(MH)
    np.conjugate(left, out=left)
    mu = np.einsum("ki,ki->k", got.left, got.right.T)     # ψₖᴴ M φₖ = wₖ φₖ (1 but for round-off)
    # rows (one per pair) in the coordinates' order, returned as columns
    rows = _in_order(got.right.T, perm)
    return got.values, _in_order(left, perm).T, rows.T, mu, Structured(got, rows, plan)


def _in_order(rows: np.ndarray, perm: np.ndarray) -> np.ndarray:
    """(m, n) ``out`` with ``out[:, perm] = rows`` (rows (m, n) in the star's
    order), copied by runs of consecutive coordinates (a plan's bodies are
    runs of them: a few block copies rather than a scatter of every entry)."""
    out = np.empty(rows.shape, dtype=rows.dtype)
    cut = np.flatnonzero(np.diff(perm) != 1) + 1
    for a, b in zip(np.r_[0, cut], np.r_[cut, perm.size]):
        out[:, perm[a]:perm[a] + b - a] = rows[:, a:b]
    return out


def damped(ms: MountedSystem, plan: BlockPlan):
    """(λ (2n,), V (n, 2n), structured): the first-order eigenvalues, the
    position halves of their vectors (columns, Fortran order), coordinates
    in order, and their :class:`Structured`; or None."""
    nL, w = plan.leaf_index.shape
    h = plan.hub.size
    K, M, C = plan.LL
    MH = plan.HH[1]
    eye_l = np.broadcast_to(np.eye(w), (nL, w, w))
    leaf = np.block([[np.zeros((nL, w, w)), eye_l],
                     [-np.linalg.solve(M, K), -np.linalg.solve(M, C)]])
    leaf_hub = np.zeros((nL, 2 * w, 2 * h))
    leaf_hub[:, w:, :h] = -np.linalg.solve(M, plan.LH[0])
    leaf_hub[:, w:, h:] = -np.linalg.solve(M, plan.LH[2])
    hub_leaf = np.zeros((nL, 2 * h, 2 * w))
    hub_leaf[:, h:, :w] = -np.linalg.solve(MH[None], plan.HL[0])
    hub_leaf[:, h:, w:] = -np.linalg.solve(MH[None], plan.HL[2])
    hub = np.block([[np.zeros((h, h)), np.eye(h)],
                    [-np.linalg.solve(MH, plan.HH[0]), -np.linalg.solve(MH, plan.HH[2])]])
    def upper(lam):
        """Each conjugate pair once (Im λ > 0) and the real roots."""
        return lam.imag >= -1e-12 * np.abs(lam).max()

    got = star_eig(Star(leaf, leaf_hub, hub_leaf, hub), select=upper)
    if got is None:
        return None
    R = got.right.T                                          # rows, states in the star's order
    m = R.shape[0]
    pos = np.concatenate([R[:, :2 * w * nL].reshape(m, nL, 2 * w)[:, :, :w].reshape(m, nL * w),
                          R[:, 2 * w * nL:2 * w * nL + h]], axis=1)   # their position states
    rows = _in_order(pos, _perm(plan))
    return got.values, rows.T, Structured(got, rows, plan)

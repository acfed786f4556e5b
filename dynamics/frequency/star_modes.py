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
not apply or the structured solution's residual is too large.
"""

from __future__ import annotations

import numpy as np

from .blocks import BlockPlan, block_plan
from .mounted import MountedSystem
from .star import Star, star_eig

__all__ = ["plan_of", "undamped", "damped"]


def plan_of(ms: MountedSystem) -> BlockPlan | None:
    """The block plan of ``ms``, or None (no sparse matrices or ones that
    are not ``ms``'s dense M, K, C — a copy with K or C replaced —, no
    leaves, too many hub coordinates, or mass coupling between leaves and
    hub)."""
    if ms.sparse is None:
        return None
    Ms, Ks, Cs = ms.sparse
    if any(np.any(S.toarray() != D) for S, D in ((Ms, ms.M), (Ks, ms.K), (Cs, ms.C))):
        return None
    plan = block_plan(Ks, Ms, Cs, ms.body)
    if plan is None or np.any(plan.LH[1]) or np.any(plan.HL[1]):
        return None
    return plan


def _perm(plan: BlockPlan) -> np.ndarray:
    """Coordinate of each star position (leaves' coordinates, then the hub's)."""
    return np.concatenate([plan.leaf_index.reshape(-1), plan.hub])


def undamped(ms: MountedSystem, plan: BlockPlan):
    """(λ, vl, vr) of ``K φ = λ M φ`` as ``_standard_eig`` gives them: vr
    (n, n) right vectors (columns), vl (n, n) with ``vl_kᴴ K = λ_k vl_kᴴ M``
    and ``vl_kᴴ M vr_l = δ_kl``; or None."""
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
    psi = np.empty((ms.n, n), dtype=complex)                     # ψ = conj(M⁻ᵀ wᵀ), by body
    psi[:nm] = np.linalg.solve(M.transpose(0, 2, 1),
                               got.left[:, :nm].T.reshape(nL, w, n)).reshape(nm, n)
    psi[nm:] = np.linalg.solve(MH.T, got.left[:, nm:].T)
    perm = _perm(plan)
    vr = np.empty_like(got.right)
    vr[perm] = got.right
    vl = np.empty_like(psi)
    vl[perm] = psi.conj()
    return got.values, vl, vr


def damped(ms: MountedSystem, plan: BlockPlan):
    """(λ (2n,), V (n, 2n)): the first-order eigenvalues and the position
    halves of their vectors, coordinates in order; or None."""
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
    rows = np.concatenate([(2 * w * np.arange(nL)[:, None] + np.arange(w)).reshape(-1),
                           2 * w * nL + np.arange(h)])                # position states
    V = np.empty((ms.n, got.values.size), dtype=complex)
    V[_perm(plan)] = got.right[rows]
    return got.values, V

"""Compiled pieces of the statics' Newton–Raphson for scenes of rigid bodies.

A study point's statics take three or four Newton iterations on some twenty
unknowns; in NumPy each iteration is a hundred-odd calls on arrays of a few
dozen entries, whose calls cost more than their arithmetic. Here, for a
scene whose bodies are all rigid and carry no loads of their own (the
tangent's own terms are then nil):

- :func:`rigid_tangent` — the dense tangent stiffness ∂(M v̇)/∂q at rest,
  the formulas of :mod:`flexbed.dynamics.tangent` (its docstring derives
  them) mount by mount, from the work arrays of one right-hand side and the
  laws' slopes; its entries are summed in the order of
  :func:`flexbed.dynamics.tangent.tangent`'s scatter, and each product of
  3 × 3 matrices is summed left to right, so the two agree to round-off
  (NumPy's stacked products may use BLAS, whose order and fused
  multiply-adds differ: 1e-14 of the largest entry, tests check);
- :func:`step_state` — the state after a Newton step: translations added,
  rotations composed ``p ← p ⊗ p(δθ)`` and normalised, the numbers of
  :func:`flexbed.dynamics.jacobian.perturbed_positions` bit for bit (the
  same operations in the same order; numba does not contract to fused
  multiply-adds without ``fastmath``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .jitcache import refresh as _refresh

__all__ = ["rigid_tangent", "step_state"]

_refresh()   # before any compiled function is loaded (flexbed.dynamics.jitcache)


@njit(cache=True)
def _skew_into(v0, v1, v2, S):
    S[0, 0], S[0, 1], S[0, 2] = 0.0, -v2, v1
    S[1, 0], S[1, 1], S[1, 2] = v2, 0.0, -v0
    S[2, 0], S[2, 1], S[2, 2] = -v1, v0, 0.0


# _mul and _mul_t are called with arrays of one type (writeable, C-contiguous,
# 2-D; a mount's read-only axes copied first): each is compiled once on a
# first run, not once per flag and per literal of a transpose argument
@njit(cache=True)
def _mul(A, B, out):
    """out (3, c) = A (3, 3) @ B (3, c); each entry summed left to right."""
    for r in range(3):
        for c in range(B.shape[1]):
            acc = 0.0
            for k in range(3):
                acc += A[r, k] * B[k, c]
            out[r, c] = acc


@njit(cache=True)
def _mul_t(A, B, out):
    """out (3, c) = Aᵀ @ B for A (3, 3), B (3, c); each entry summed left
    to right."""
    for r in range(3):
        for c in range(B.shape[1]):
            acc = 0.0
            for k in range(3):
                acc += A[k, r] * B[k, c]
            out[r, c] = acc


@njit(cache=True)
def rigid_tangent(A, P, ub, f, F, U, kx, body_i, body_j, K):
    """The tangent stiffness of rigid bodies at rest, dense, into K.

    Parameters
    ----------
    A : (nb, 3, 3) array
        The bodies' rotation matrices (the right-hand side's ``w_A``; row 0
        the base).
    P, ub : (2M, 3) arrays
        The mount ends' inertial positions [m] and body-frame points [m]
        (``w_P``, ``w_ub``: the ends i, then the ends j).
    f, F : (M, 3) arrays
        The mounts' forces in their own axes and inertial [N] (``w_f``,
        ``w_F``).
    U : (M, 3, 3) array
        The mounts' axes in body i.
    kx : (3M,) array
        ∂f/∂Δx of every mount direction [N/m]
        (:func:`flexbed.dynamics.tangent.law_slopes`).
    body_i, body_j : (M,) int arrays
        The bodies of the ends (0 the base: no unknowns).
    K : (6n, 6n) array
        Zeroed on entry; on return ∂(M v̇)/∂q in the unknowns δr, δθ of the
        bodies 1… [N/m, N/rad, N m/m, N m/rad].
    """
    M = U.shape[0]
    E = np.zeros((2, 3, 6))          # E of the ends i, j: [I, −A_b ū~]
    dl = np.zeros((3, 12))
    Thi = np.zeros((3, 12))
    S = np.empty((3, 3))
    T = np.empty((3, 3))
    t12 = np.empty((3, 12))
    u12 = np.empty((3, 12))
    dDx = np.empty((3, 12))
    dg = np.empty((3, 12))
    Q = np.empty((6, 12))
    dF = np.empty((M, 3, 12))
    Um = np.empty((3, 3))            # a mount's axes (U is read-only in a System)
    lam = np.empty(3)
    Fb = np.empty(3)
    for m in range(M):
        ends = (body_i[m], body_j[m])
        for s in range(2):
            e = m + s * M
            b = ends[s]
            for r in range(3):
                for c in range(6):
                    E[s, r, c] = 0.0
            if b > 0:
                for r in range(3):
                    E[s, r, r] = 1.0
                _skew_into(ub[e, 0], ub[e, 1], ub[e, 2], S)
                _mul(A[b], S, T)
                for r in range(3):
                    for c in range(3):
                        E[s, r, 3 + c] = -T[r, c]
        for r in range(3):
            for c in range(6):
                dl[r, c] = -E[0, r, c]
                dl[r, 6 + c] = E[1, r, c]
        for r in range(3):
            for c in range(12):
                Thi[r, c] = 0.0
        if ends[0] > 0:
            for r in range(3):
                Thi[r, 3 + r] = 1.0
        Ai = A[ends[0]]
        for r in range(3):
            for c in range(3):
                Um[r, c] = U[m, r, c]
        # λ = A_iᵀ (P_j − P_i); F̄ = Uᵀ f
        l0 = P[M + m, 0] - P[m, 0]
        l1 = P[M + m, 1] - P[m, 1]
        l2 = P[M + m, 2] - P[m, 2]
        for r in range(3):
            lam[r] = (Ai[0, r] * l0 + Ai[1, r] * l1) + Ai[2, r] * l2
            Fb[r] = (U[m, 0, r] * f[m, 0] + U[m, 1, r] * f[m, 1]) + U[m, 2, r] * f[m, 2]
        # δΔx = U (A_iᵀ dl + λ~ Θ_i);  δf = kx δΔx
        _mul_t(Ai, dl, t12)
        _skew_into(lam[0], lam[1], lam[2], S)
        _mul(S, Thi, u12)
        for r in range(3):
            for c in range(12):
                t12[r, c] += u12[r, c]
        _mul(Um, t12, dDx)
        for r in range(3):
            for c in range(12):
                dDx[r, c] *= kx[3 * m + r]
        # δF = A_i (Uᵀ δf − F̄~ Θ_i)
        _mul_t(Um, dDx, t12)
        _skew_into(Fb[0], Fb[1], Fb[2], S)
        _mul(S, Thi, u12)
        for r in range(3):
            for c in range(12):
                t12[r, c] -= u12[r, c]
        _mul(Ai, t12, dF[m])
    for s in range(2):          # the ends i, then j: the scatter's order
        for m in range(M):
            ends = (body_i[m], body_j[m])
            b = ends[s]
            if b == 0:
                continue
            e = m + s * M
            Ab = A[b]
            # ḡ = A_bᵀ F; δḡ = A_bᵀ δF + ḡ~ Θ_b (Θ_b in the columns of the end's body)
            g0 = (Ab[0, 0] * F[m, 0] + Ab[1, 0] * F[m, 1]) + Ab[2, 0] * F[m, 2]
            g1 = (Ab[0, 1] * F[m, 0] + Ab[1, 1] * F[m, 1]) + Ab[2, 1] * F[m, 2]
            g2 = (Ab[0, 2] * F[m, 0] + Ab[1, 2] * F[m, 1]) + Ab[2, 2] * F[m, 2]
            _mul_t(Ab, dF[m], dg)
            _skew_into(g0, g1, g2, S)
            for r in range(3):
                for c in range(3):
                    dg[r, 6 * s + 3 + c] += S[r, c]
            # Q = ± [δF; ū~ δḡ]
            _skew_into(ub[e, 0], ub[e, 1], ub[e, 2], T)
            _mul(T, dg, u12)
            sg = 1.0 if s == 0 else -1.0
            for c in range(12):
                for r in range(3):
                    Q[r, c] = sg * dF[m, r, c]
                    Q[3 + r, c] = sg * u12[r, c]
            row0 = 6 * (b - 1)
            for w in range(6):
                for c in range(12):
                    other = ends[c // 6]
                    if other > 0:
                        K[row0 + w, 6 * (other - 1) + c % 6] += Q[w, c]


@njit(cache=True)
def step_state(y, q0, n, dx, out):
    """out (ny,) = y (ny,) with the rigid bodies' positions stepped by dx
    (6n,): the numbers of ``perturbed_positions(system, y, dx[None])[0]``
    (q0 : the index of the first body's position in y, 7 per body)."""
    for i in range(y.size):             # (a slice assignment costs seconds to compile)
        out[i] = y[i]
    for b in range(n):
        q = q0 + 7 * b
        for k in range(3):
            out[q + k] = y[q + k] + dx[6 * b + k]
        t0, t1, t2 = dx[6 * b + 3], dx[6 * b + 4], dx[6 * b + 5]
        angle = math.sqrt((t0 * t0 + t1 * t1) + t2 * t2)
        half = 0.5 * angle
        if angle < 1e-300:
            b0, b1, b2, b3 = 1.0, 0.0, 0.0, 0.0
        else:
            sc = math.sin(half) / angle
            b0, b1, b2, b3 = math.cos(half), sc * t0, sc * t1, sc * t2
        a0, a1, a2, a3 = y[q + 3], y[q + 4], y[q + 5], y[q + 6]
        p0 = a0 * b0 - ((a1 * b1 + a2 * b2) + a3 * b3)
        p1 = (a0 * b1 + b0 * a1) + (a2 * b3 - a3 * b2)
        p2 = (a0 * b2 + b0 * a2) + (a3 * b1 - a1 * b3)
        p3 = (a0 * b3 + b0 * a3) + (a1 * b2 - a2 * b1)
        norm = math.sqrt(((p0 * p0 + p1 * p1) + p2 * p2) + p3 * p3)
        out[q + 3] = p0 / norm
        out[q + 4] = p1 / norm
        out[q + 5] = p2 / norm
        out[q + 6] = p3 / norm

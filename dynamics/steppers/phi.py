"""The φ-functions of the error estimate's propagators in compiled loops
(see :func:`flexbed.dynamics.linear_estimate.defect_propagators`): their
Taylor series on a short interval and the exact doubling of the interval.

``φ_0(X) = e^X`` and ``φ_j(X) = Σ_k X^k / (k + j)!``; over an interval of
length L, ``Φ = φ_0(L A)`` and ``P_p = L φ_{p+1}(L A)`` carry
ė = A e + d, d a polynomial in σ = t/L with σ-derivatives w_p at 0, as
``e(L) = Φ e(0) + Σ_p P_p w_p``.
"""

from __future__ import annotations

import numpy as np

from .propagate import jit

__all__ = ["phi_series", "phi_double"]


@jit
def phi_series(X, coef, h, cols, Phi, P):
    """Φ = Σ_k coef[0, k] X^k and P_p = h Σ_k coef[p + 1, k] X^k[:, cols]
    (k = 0 … K), the matrix products compiled (BLAS).

    Parameters
    ----------
    X : (n, n) float64
        h A (balanced), its norm small enough for K + 1 terms.
    coef : (q + 1, K + 1) float64
        1/(k + j)!, j = 0 … q.
    h : float [s]
    cols : (c,) int64
        The columns of P kept.
    Phi : (n, n) float64
        Written.
    P : (q, n, c) float64
        Written.

    Returns
    -------
    float
        The larger of ‖X^K‖₁/K! and ‖X^(K−1)‖₁/(K−1)! (the series' tail).
    """
    n = X.shape[0]
    q = P.shape[0]
    K = coef.shape[1] - 1
    c = cols.size
    Xk = np.eye(n)
    for i in range(n):
        for j in range(n):
            Phi[i, j] = 0.0
        for p in range(q):
            for j in range(c):
                P[p, i, j] = 0.0
    tail = 0.0
    for k in range(K + 1):
        if k:
            Xk = np.dot(Xk, X)
        a = coef[0, k]
        for i in range(n):
            for j in range(n):
                Phi[i, j] += a * Xk[i, j]
        for p in range(q):
            b = h * coef[p + 1, k]
            for i in range(n):
                for j in range(c):
                    P[p, i, j] += b * Xk[i, cols[j]]
        if k >= K - 1:
            norm = 0.0
            for j in range(n):
                s = 0.0
                for i in range(n):
                    s += abs(Xk[i, j])
                norm = max(norm, s)
            tail = max(tail, norm * coef[0, k])
    return tail


@jit
def phi_double(Phi, P, mix, halves):
    """The interval doubled, in place: Φ ← Φ², P_p ← 2^−p (Φ P_p +
    Σ_{i ≤ p} P_i mix[i, p]) (mix[i, p] = 1/(p − i)!, halves[p] = 2^−p);
    one product Φ [P_0 … P_{q−1} Φ].

    Parameters
    ----------
    Phi : (n, n) float64
    P : (q, n, c) float64
    mix : (q, q) float64
    halves : (q,) float64
    """
    q, n, c = P.shape
    B = np.empty((n, q * c + n))
    for p in range(q):
        for i in range(n):
            for j in range(c):
                B[i, p * c + j] = P[p, i, j]
    for i in range(n):
        for j in range(n):
            B[i, q * c + j] = Phi[i, j]
    prod = np.dot(Phi, B)
    for p in range(q - 1, -1, -1):           # P_i, i ≤ p, still the old ones
        for i in range(n):
            for j in range(c):
                s = prod[i, p * c + j]
                for r in range(p + 1):
                    s += P[r, i, j] * mix[r, p]
                P[p, i, j] = s * halves[p]
    for i in range(n):
        for j in range(n):
            Phi[i, j] = prod[i, q * c + j]

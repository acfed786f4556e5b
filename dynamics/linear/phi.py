"""The φ-functions of the linear fast path in compiled loops: those of the
error estimate's propagators (see
:func:`flexbed.dynamics.linear.estimate.defect_propagators`) and the
exponential of the propagation's augmented matrix (see
:class:`flexbed.dynamics.linear.propagation._Exponential`): their Taylor
series on a short interval and the exact doubling of the interval. Both
work on A balanced by powers of 2
(:attr:`flexbed.dynamics.linear.model.Linearisation.balanced`).

``φ_0(X) = e^X`` and ``φ_j(X) = Σ_k X^k / (k + j)!``; over an interval of
length L, ``Φ = φ_0(L A)`` and ``P_p = L φ_{p+1}(L A)`` carry
ė = A e + d, d a polynomial in σ = t/L with σ-derivatives w_p at 0, as
``e(L) = Φ e(0) + Σ_p P_p w_p``.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from .sweep import jit

__all__ = ["phi_functions", "phi_double", "exp_and_phi_columns", "series_terms", "norm1",
           "halvings", "doubling_tables", "SERIES_NORM"]


#: the series are summed for ‖X‖₁ at most this ...
SERIES_NORM = 2.0
#: ... to the first power X^K whose next term's bound ‖X‖₁^(K+1)/(K+1+q)!
#: in the series of φ_q is below this share of φ_q(0) = 1/q! (at
#: ‖X‖₁ = 2: K = 20 for φ_4, whose X^21/25! is below 1.4e-19 in norm,
#: 5e-18 of φ_4(−2) = 0.029; K = 24 for e^X; at 0.2: K = 11 for e^X,
#: 10 for φ_4) ...
SERIES_TOL = 1e-17
#: ... and at most to this power
SERIES_TERMS = 30
#: the powers X … X^_BLOCK of Paterson and Stockmeyer's evaluation
_BLOCK = 5


@jit
def norm1(A):
    """‖A‖₁ (n, n): the largest column sum of |A|."""
    n = A.shape[0]
    best = 0.0
    for j in range(A.shape[1]):
        col = 0.0
        for i in range(n):
            col += abs(A[i, j])
        best = max(best, col)
    return best


def halvings(x: float) -> int:
    """The least s ≥ 0 with x / 2^s ≤ :data:`SERIES_NORM`: the halvings of an
    interval whose ‖hA‖₁ is x before its series (and the doublings after)."""
    return max(0, math.ceil(math.log2(x / SERIES_NORM))) if x > SERIES_NORM else 0


@functools.lru_cache(maxsize=8)
def doubling_tables(degree: int) -> tuple:
    """The doublings' mixing 1/(p − i)! (i ≤ p) and 2^−p of
    :func:`phi_double` (q = degree + 1 of them)."""
    q = degree + 1
    mix = np.array([[1.0 / math.factorial(p - i) if i <= p else 0.0 for p in range(q)]
                    for i in range(q)])
    return mix, 2.0 ** -np.arange(q)


@jit
def series_terms(X, q):
    """The last power K of X in the Taylor series of φ_q(X): the least K
    whose next term's bound ‖X‖₁^(K+1)/(K+1+q)! is at most
    :data:`SERIES_TOL`/q!, and at most :data:`SERIES_TERMS`."""
    n = X.shape[0]
    x = 0.0
    for j in range(n):
        col = 0.0
        for i in range(n):
            col += abs(X[i, j])
        x = max(x, col)
    bound = 1.0                          # ‖X‖^k q!/(k + q)! at k = 0
    for k in range(1, SERIES_TERMS + 1):
        bound *= x / (k + q)
        if bound <= SERIES_TOL:
            return k - 1
    return SERIES_TERMS


@jit
def phi_functions(X, out):
    """φ_0(X) … φ_q(X) into out (q + 1, n, n), ‖X‖₁ ≤ :data:`SERIES_NORM`.

    φ_q by its Taylor series to the power :func:`series_terms` gives
    (20 at ‖X‖₁ = 2 for φ_4), summed by Paterson and Stockmeyer's scheme
    (X² … X⁵, then Horner in X⁵: 7 products at 20 terms); then
    φ_j = X φ_{j+1} + I/j!, j = q − 1 … 0 (q products).

    Parameters
    ----------
    X : (n, n) float64
    out : (q + 1, n, n) float64
        Written.
    """
    n = X.shape[0]
    q = out.shape[0] - 1
    m = _BLOCK
    powers = np.empty((m + 1, n, n))
    for i in range(n):
        for j in range(n):
            powers[0, i, j] = 1.0 if i == j else 0.0
            powers[1, i, j] = X[i, j]
    for k in range(2, m + 1):
        np.dot(powers[k - 1], X, powers[k])
    # coefficients 1/(k + q)!, k = 0 … K
    K = series_terms(X, q)
    c = np.empty(K + 1)
    f = 1.0
    for i in range(2, q + 1):
        f *= i
    for k in range(K + 1):
        if k:
            f *= k + q
        c[k] = 1.0 / f
    blocks = (K + 1 + m - 1) // m
    R = np.zeros((n, n))
    for b in range(blocks - 1, -1, -1):
        if b < blocks - 1:
            R = np.dot(R, powers[m])
        for i in range(m):
            k = b * m + i
            if k > K:
                break
            ck = c[k]
            for r in range(n):
                for s in range(n):
                    R[r, s] += ck * powers[i, r, s]
    for r in range(n):
        for s in range(n):
            out[q, r, s] = R[r, s]
    inv = 1.0
    for j in range(1, q):
        inv /= j
    for j in range(q - 1, -1, -1):                    # inv = 1/j!
        np.dot(X, out[j + 1], out[j])
        for r in range(n):
            out[j, r, r] += inv
        if j:
            inv *= j


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


@jit
def exp_and_phi_columns(X, V, h, Phi, P):
    """Φ = e^X into Phi (n, n) and P_p = h φ_{p+1}(X) V into P (q, n, c),
    p = 0 … q − 1, ‖X‖₁ ≤ :data:`SERIES_NORM`: e^X by
    :func:`phi_functions`, the columns by their Taylor series on the
    Krylov vectors X^k V (matrix–vector products only) to the power e^X's
    series takes (:func:`series_terms`; the first term left out is
    smaller than e^X's, relative to ‖V‖).

    Parameters
    ----------
    X : (n, n) float64
    V : (n, c) float64
    h : float
    Phi : (n, n) float64
        Written.
    P : (q, n, c) float64
        Written.
    """
    n, c = V.shape
    q = P.shape[0]
    phi_functions(X, Phi.reshape((1, n, n)))
    K = series_terms(X, np.int64(0))                 # int64 as in phi_functions
    inv = np.empty(K + q + 1)                          # inv[i] = 1/i!
    inv[0] = 1.0
    for i in range(1, K + q + 1):
        inv[i] = inv[i - 1] / i
    P[:] = 0.0
    Xk = V.copy()
    for k in range(K + 1):
        for p in range(q):
            ck = h * inv[k + p + 1]
            for i in range(n):
                for j in range(c):
                    P[p, i, j] += ck * Xk[i, j]
        if k < K:
            Xk = np.dot(X, Xk)

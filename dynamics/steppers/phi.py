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

__all__ = ["phi_functions", "phi_double", "SERIES_NORM"]


#: the series are summed for ‖X‖₁ at most this ...
SERIES_NORM = 2.0
#: ... to X^SERIES_TERMS: the first term left out of φ_4, X^21/25!, is
#: below 2^21/25! = 1.4e-19 in norm, 5e-18 of φ_4(−2) = 0.029
SERIES_TERMS = 20
#: the powers X … X^_BLOCK of Paterson and Stockmeyer's evaluation
_BLOCK = 5


@jit
def phi_functions(X, out):
    """φ_0(X) … φ_q(X) into out (q + 1, n, n), ‖X‖₁ ≤ :data:`SERIES_NORM`.

    φ_q by its Taylor series to X^:data:`SERIES_TERMS`, summed by
    Paterson and Stockmeyer's scheme (X² … X⁵, then Horner in X⁵: 7
    products); then φ_j = X φ_{j+1} + I/j!, j = q − 1 … 0 (q products).

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
        powers[k] = np.dot(powers[k - 1], X)
    # coefficients 1/(k + q)!, k = 0 … SERIES_TERMS
    K = SERIES_TERMS
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
    out[q] = R
    inv = 1.0
    for j in range(1, q):
        inv /= j
    for j in range(q - 1, -1, -1):                    # inv = 1/j!
        out[j] = np.dot(X, out[j + 1])
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

"""The linear fast path's recursion, compiled: x_{i+1} = Φ_{j(i)} x_i + p_i
over every piece, with precomputed propagators (see
:mod:`flexbed.dynamics.linear`)."""

from __future__ import annotations

from .common import jit

__all__ = ["linear_sweep"]


@jit
def linear_sweep(Phis, which, P, x0, X):
    """X[0] = x0; X[i + 1] = Phis[which[i]] @ X[i] + P[i], i = 0 … k − 1.

    Parameters
    ----------
    Phis : (m, n, n) float64
        The propagators, one per distinct piece length.
    which : (k,) int64
        The propagator of each piece.
    P : (k, n) float64
        The inputs' part of each piece's step.
    x0 : (n,) float64
    X : (k + 1, n) float64
        Written.
    """
    n = x0.size
    for j in range(n):
        X[0, j] = x0[j]
    for i in range(which.size):
        Phi = Phis[which[i]]
        for r in range(n):
            s = P[i, r]
            for c in range(n):
                s += Phi[r, c] * X[i, c]
            X[i + 1, r] = s

"""The linear fast path's compiled loops: the recursion
x_{i+1} = Φ_{j(i)} x_i + p_i over every piece with precomputed propagators
(the propagation, and the error estimate's over its nodes: see
:mod:`flexbed.dynamics.linear`), the states of the linear model's
deviations and the deviations' rates of state derivatives
(:meth:`flexbed.dynamics.linear.model.Coordinates.to_y` and ``rate``).
The error estimate's own loops are in
:mod:`flexbed.dynamics.linear.defect`."""

from __future__ import annotations

import math

import numba
import numpy as np

#: as :data:`flexbed.dynamics.steppers.common.jit`, with the sums' terms
#: free to be reordered and fused (vectorised dot products: 3–4 times
#: faster; the results change by round-off only); NaNs and infinities keep
#: their meaning
jit = numba.njit(cache=True, error_model="numpy", fastmath={"reassoc", "contract"})
#: the same, for the helpers that only compiled code calls: no wrapper for
#: calls from Python is compiled (nor linked into their callers)
inner = numba.njit(cache=True, error_model="numpy", fastmath={"reassoc", "contract"},
                   no_cpython_wrapper=True)

__all__ = ["linear_sweep", "poly_derivatives", "deviations_to_states", "states_to_deviations",
           "rates_of_states",
           "few_distinct"]


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
        The inputs' part of each piece's step. It may be ``X[1:]`` itself
        (the sweep then adds Φ x_i in place): row i + 1 of X is written
        only after P[i] is read.
    x0 : (n,) float64
    X : (k + 1, n) float64
        Written.
    """
    n = x0.size
    for j in range(n):
        X[0, j] = x0[j]
    for i in range(which.size):
        Phi = Phis[which[i]]
        x = X[i]
        # eight rows at a time: eight independent sums over x (1.09–1.17
        # times faster than four at a time at n = 54 … 42, which were
        # 1.3–1.4 times faster than one), then two, then one
        r = 0
        while r + 8 <= n:
            f0, f1, f2, f3 = Phi[r], Phi[r + 1], Phi[r + 2], Phi[r + 3]
            f4, f5, f6, f7 = Phi[r + 4], Phi[r + 5], Phi[r + 6], Phi[r + 7]
            s0, s1, s2, s3 = P[i, r], P[i, r + 1], P[i, r + 2], P[i, r + 3]
            s4, s5, s6, s7 = P[i, r + 4], P[i, r + 5], P[i, r + 6], P[i, r + 7]
            for c in range(n):
                xc = x[c]
                s0 += f0[c] * xc
                s1 += f1[c] * xc
                s2 += f2[c] * xc
                s3 += f3[c] * xc
                s4 += f4[c] * xc
                s5 += f5[c] * xc
                s6 += f6[c] * xc
                s7 += f7[c] * xc
            X[i + 1, r], X[i + 1, r + 1], X[i + 1, r + 2], X[i + 1, r + 3] = s0, s1, s2, s3
            X[i + 1, r + 4], X[i + 1, r + 5], X[i + 1, r + 6], X[i + 1, r + 7] = s4, s5, s6, s7
            r += 8
        while r + 2 <= n:
            f0, f1 = Phi[r], Phi[r + 1]
            s0, s1 = P[i, r], P[i, r + 1]
            for c in range(n):
                s0 += f0[c] * x[c]
                s1 += f1[c] * x[c]
            X[i + 1, r], X[i + 1, r + 1] = s0, s1
            r += 2
        while r < n:
            f0 = Phi[r]
            s0 = P[i, r]
            for c in range(n):
                s0 += f0[c] * x[c]
            X[i + 1, r] = s0
            r += 1


@jit
def poly_derivatives(coeffs, origins, idx, t0, h, out):
    """Adds to out (k, q) the σ-derivatives h^m f^(m)(t0) (m < q) of the
    piecewise polynomial f on the pieces [t0, t0 + h] (k,), each inside
    f's piece ``idx`` (k,) of ascending coefficients ``coeffs[idx]`` in
    u = t − ``origins[idx]`` (:class:`flexbed.dynamics.piecewise.PiecewisePolynomial`):
    Horner in u of the m-th derivative's coefficients p!/(p − m)! c_p."""
    d = coeffs.shape[1] - 1
    q = out.shape[1]
    for i in range(t0.size):
        j = idx[i]
        u = t0[i] - origins[j]
        hm = 1.0
        for m in range(min(d, q - 1) + 1):
            acc = 0.0
            for p in range(d, m - 1, -1):
                ratio = 1.0
                for r in range(p - m + 1, p + 1):
                    ratio *= r
                acc = acc * u + coeffs[j, p] * ratio
            out[i, m] += acc * hm
            hm *= h[i]


@jit
def deviations_to_states(Z, y_eq, add, put, th_index, p_index, p_eq, Y):
    """States Y (k, ny) of deviations Z (k, nz) (see
    :meth:`flexbed.dynamics.linear.model.Coordinates.to_y`): y_eq, plus
    ``Z[:, add[:, 0]]`` at ``add[:, 1]``, ``Z[:, put[:, 0]]`` put at
    ``put[:, 1]``, and each body's Euler parameters p_eq ⊗ (√(1 − |θ/2|²), θ/2),
    θ at ``th_index`` (n, 3), written at ``p_index`` (n, 4)."""
    k = Z.shape[0]
    for i in range(k):
        for j in range(y_eq.size):
            Y[i, j] = y_eq[j]
        for j in range(add.shape[0]):
            Y[i, add[j, 1]] += Z[i, add[j, 0]]
        for j in range(put.shape[0]):
            Y[i, put[j, 1]] = Z[i, put[j, 0]]
        for b in range(th_index.shape[0]):
            s1 = 0.5 * Z[i, th_index[b, 0]]
            s2 = 0.5 * Z[i, th_index[b, 1]]
            s3 = 0.5 * Z[i, th_index[b, 2]]
            s0 = math.sqrt(max(1.0 - (s1 * s1 + s2 * s2 + s3 * s3), 0.0))
            a0, a1, a2, a3 = p_eq[b, 0], p_eq[b, 1], p_eq[b, 2], p_eq[b, 3]
            Y[i, p_index[b, 0]] = a0 * s0 - a1 * s1 - a2 * s2 - a3 * s3
            Y[i, p_index[b, 1]] = a0 * s1 + s0 * a1 + a2 * s3 - a3 * s2
            Y[i, p_index[b, 2]] = a0 * s2 + s0 * a2 + a3 * s1 - a1 * s3
            Y[i, p_index[b, 3]] = a0 * s3 + s0 * a3 + a1 * s2 - a2 * s1


@jit
def states_to_deviations(Y, y_eq, add, put, th_index, p_index, p_conj, Z):
    """Deviations Z (k, nz) of states Y (k, ny), the inverse of
    :func:`deviations_to_states` (see
    :meth:`flexbed.dynamics.linear.model.Coordinates.to_z`):
    ``Y[:, add[:, 1]] − y_eq[add[:, 1]]`` at ``add[:, 0]``,
    ``Y[:, put[:, 1]]`` at ``put[:, 0]``, and each body's
    θ = 2 vec(p_eq* ⊗ p/|p|) (the sign of the scalar part made positive),
    p at ``p_index`` (n, 4), p_eq* = ``p_conj`` (n, 4), θ written at
    ``th_index`` (n, 3)."""
    k = Y.shape[0]
    for i in range(k):
        for j in range(add.shape[0]):
            Z[i, add[j, 0]] = Y[i, add[j, 1]] - y_eq[add[j, 1]]
        for j in range(put.shape[0]):
            Z[i, put[j, 0]] = Y[i, put[j, 1]]
        for b in range(th_index.shape[0]):
            b0 = Y[i, p_index[b, 0]]
            b1 = Y[i, p_index[b, 1]]
            b2 = Y[i, p_index[b, 2]]
            b3 = Y[i, p_index[b, 3]]
            norm = math.sqrt(b0 * b0 + b1 * b1 + b2 * b2 + b3 * b3)
            a0, a1, a2, a3 = p_conj[b, 0], p_conj[b, 1], p_conj[b, 2], p_conj[b, 3]
            r0 = a0 * b0 - a1 * b1 - a2 * b2 - a3 * b3
            f = (-2.0 if r0 < 0.0 else 2.0) / norm
            Z[i, th_index[b, 0]] = f * (a0 * b1 + b0 * a1 + a2 * b3 - a3 * b2)
            Z[i, th_index[b, 1]] = f * (a0 * b2 + b0 * a2 + a3 * b1 - a1 * b3)
            Z[i, th_index[b, 2]] = f * (a0 * b3 + b0 * a3 + a1 * b2 - a2 * b1)


@jit
def rates_of_states(dY, take, th_index, p_index, p_conj, Zd):
    """Rates Zd (k, nz) of state derivatives dY (k, ny) (see
    :meth:`flexbed.dynamics.linear.model.Coordinates.rate`):
    ``dY[:, take[:, 1]]`` at ``take[:, 0]``, and each body's
    θ̇ = 2 vec(p_eq* ⊗ ṗ), ṗ at ``p_index`` (n, 4), p_eq* = ``p_conj``
    (n, 4), θ̇ written at ``th_index`` (n, 3)."""
    k = dY.shape[0]
    for i in range(k):
        for j in range(take.shape[0]):
            Zd[i, take[j, 0]] = dY[i, take[j, 1]]
        for b in range(th_index.shape[0]):
            a0, a1, a2, a3 = p_conj[b, 0], p_conj[b, 1], p_conj[b, 2], p_conj[b, 3]
            b0 = dY[i, p_index[b, 0]]
            b1 = dY[i, p_index[b, 1]]
            b2 = dY[i, p_index[b, 2]]
            b3 = dY[i, p_index[b, 3]]
            Zd[i, th_index[b, 0]] = 2.0 * (a0 * b1 + b0 * a1 + a2 * b3 - a3 * b2)
            Zd[i, th_index[b, 1]] = 2.0 * (a0 * b2 + b0 * a2 + a3 * b1 - a1 * b3)
            Zd[i, th_index[b, 2]] = 2.0 * (a0 * b3 + b0 * a3 + a1 * b2 - a2 * b1)


@jit
def few_distinct(keys, which, first, most):
    """The distinct values of keys (k,) when there are at most ``most``:
    which[i] the rank of keys[i] among them (ascending), first[r] the first
    i of rank r; returns how many, or −1 when there are more (a linear scan
    over the few seen so far: the usual case of one or two piece lengths,
    without sorting k values). keys are finite.

    Parameters
    ----------
    keys : (k,) float64
    which : (k,) int64
        Written.
    first : (most,) int64
        Written (its first m entries).
    most : int
    """
    vals = np.empty(most)
    seen = np.empty(most, dtype=np.int64)
    m = 0
    for i in range(keys.size):
        v = keys[i]
        j = 0
        while j < m and vals[j] != v:
            j += 1
        if j == m:
            if m == most:
                return -1
            vals[m] = v
            seen[m] = i
            m += 1
        which[i] = j
    # ranks by counting (m ≤ most, a few): the values are distinct, so the
    # order is argsort's, without compiling numba's sort (4 s on a first run)
    rank = np.empty(m, dtype=np.int64)
    for a in range(m):
        r = 0
        for b in range(m):
            if vals[b] < vals[a]:
                r += 1
        rank[a] = r
        first[r] = seen[a]
    for i in range(keys.size):
        which[i] = rank[which[i]]
    return m


@jit
def merge_cuts(grid, extra, tol, out):
    """The output grid (k,) and the sorted extra cuts (e,) merged into out
    (at least k + e long), ascending, a cut within ``tol`` of the time kept
    before it or of the next grid time left out (the grid's times exact);
    returns how many were written."""
    k, e = grid.size, extra.size
    i = j = n = 0
    while i < k or j < e:
        if j == e or (i < k and grid[i] <= extra[j]):
            v = grid[i]
            i += 1
            if n and v - out[n - 1] <= tol:
                out[n - 1] = v                   # a cut just before it: the grid's time
            else:
                out[n] = v
                n += 1
        else:
            v = extra[j]
            j += 1
            if (n and v - out[n - 1] <= tol) or (i < k and grid[i] - v <= tol):
                continue
            out[n] = v
            n += 1
    return n

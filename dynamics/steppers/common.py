"""What the compiled steppers share: the call of the right-hand side on the
shifted state, projection of the Euler parameters, the output rows
(:func:`rows_inside`, :func:`write_rows`), SciPy's initial-step selection."""

from __future__ import annotations

import math

import numba
import numpy as np

__all__ = ["jit", "inner", "EPS", "SQRT_EPS", "rhs", "finite", "project", "end_tol", "rows_inside",
           "write_rows", "initial_step"]

#: the decorator of the compiled steppers, called from Python
jit = numba.njit(cache=True, error_model="numpy")
#: the decorator of their helpers, called from compiled code only (no
#: wrapper for calls from Python is compiled)
inner = numba.njit(cache=True, error_model="numpy", no_cpython_wrapper=True)

EPS = float(np.finfo(float).eps)
SQRT_EPS = math.sqrt(EPS)


@inner
def rhs(t, seg_end, z, shift, ybuf, dz, kernel):
    """dz = f(t, z + shift); ybuf (ny,) scratch; kernel = (function, F, I),
    the compiled right-hand side and the scene's storage."""
    for i in range(z.size):
        ybuf[i] = z[i] + shift[i]
    fn, F, I = kernel
    fn(t, seg_end, ybuf.ctypes, dz.ctypes, F.ctypes, I.ctypes)


@inner
def finite(x):
    """Whether every entry of the 1-D array x is finite."""
    for i in range(x.size):
        if not math.isfinite(x[i]):
            return False
    return True


@inner
def project(z, shift, p_idx, f):
    """Euler parameters of z + shift onto |p| = 1 (in z), and the same rows
    of f (the derivative kept at z; ṗ is linear in p) divided by the same
    |p|. A caller that keeps no derivative passes scratch for f."""
    for b in range(p_idx.shape[0]):
        s = 0.0
        for k in range(4):
            j = p_idx[b, k]
            p = z[j] + shift[j]
            s += p * p
        nrm = math.sqrt(s)
        if not (nrm > 0.0 and math.isfinite(nrm)):
            continue
        for k in range(4):
            j = p_idx[b, k]
            z[j] = (z[j] + shift[j]) / nrm - shift[j]
            f[j] /= nrm


@inner
def normalise_row(Y, k, p_idx):
    """Euler parameters of the output row Y[k] onto |p| = 1."""
    for b in range(p_idx.shape[0]):
        s = 0.0
        for m in range(4):
            p = Y[k, p_idx[b, m]]
            s += p * p
        nrm = math.sqrt(s)
        if nrm > 0.0 and math.isfinite(nrm):
            for m in range(4):
                Y[k, p_idx[b, m]] /= nrm


@inner
def end_tol(t_new):
    """Grid times within this of t_new take the step's end state."""
    return 1e-12 * max(1.0, abs(t_new))


@inner
def rows_inside(grid, k_out, t_new):
    """The output rows strictly inside a step ending at t_new: k_out …
    k_dense − 1, their grid times before t_new − end_tol(t_new). Returns
    k_dense. The stepper writes these rows from its dense output,
    ``Y[k] = dense(grid[k]) + shift``, then calls :func:`write_rows`."""
    tol = end_tol(t_new)
    k = k_out
    while k < grid.size and grid[k] < t_new - tol:
        k += 1
    return k


@inner
def write_rows(grid, Y, k_out, k_dense, t_new, z_new, shift, p_idx):
    """The output rows of an accepted step that ends at t_new in z_new.

    Rows k_out … k_dense − 1 (:func:`rows_inside`) hold the dense output
    already; the rows from k_dense on whose grid times lie within
    end_tol(t_new) of t_new take the end state, ``Y[k] = z_new + shift``;
    then every one of these rows has its Euler parameters normalised.

    grid : (k,) ascending [s]; Y : (k, ny); z_new, shift : (ny,);
    p_idx : (n_bodies, 4) int64 (see the package docstring).
    Returns the first row not written (the new k_out).
    """
    tol = end_tol(t_new)
    k = k_dense
    while k < grid.size and grid[k] <= t_new + tol:
        for i in range(z_new.size):
            Y[k, i] = z_new[i] + shift[i]
        k += 1
    for j in range(k_out, k):
        normalise_row(Y, j, p_idx)
    return k


@inner
def initial_step(t0, t_b, z, f0, shift, kernel, rtol, atol, h_max, order, ybuf, z1, f1, counts):
    """SciPy's ``select_initial_step`` (Hairer, Nørsett & Wanner I, II.4).

    order : error-estimator order (dop853: 7; radau: 3), an int64 (a
    literal would compile one specialisation per stepper). One evaluation.
    Returns the first step [s].
    """
    ny = z.size
    interval = abs(t_b - t0)
    if ny == 0:
        return math.inf
    if interval == 0.0:
        return 0.0
    d0 = 0.0
    d1 = 0.0
    for i in range(ny):
        sc = atol[i] + abs(z[i]) * rtol
        d0 += (z[i] / sc) ** 2
        d1 += (f0[i] / sc) ** 2
    d0 = math.sqrt(d0 / ny)
    d1 = math.sqrt(d1 / ny)
    if d0 < 1e-5 or d1 < 1e-5:
        h0 = 1e-6
    else:
        h0 = 0.01 * d0 / d1
    h0 = min(h0, interval)
    for i in range(ny):
        z1[i] = z[i] + h0 * f0[i]
    rhs(t0 + h0, t_b, z1, shift, ybuf, f1, kernel)
    counts[0] += 1
    d2 = 0.0
    for i in range(ny):
        sc = atol[i] + abs(z[i]) * rtol
        d2 += ((f1[i] - f0[i]) / sc) ** 2
    d2 = math.sqrt(d2 / ny) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / (order + 1))
    return min(100.0 * h0, h1, interval, h_max)

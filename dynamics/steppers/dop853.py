"""Dormand–Prince 8(5,3) with SciPy's DOP853 step control, compiled (see
:mod:`flexbed.dynamics.steppers`)."""

from __future__ import annotations

import math

import numpy as np

from .common import inner, EPS, finite, initial_step, jit, project, rhs, rows_inside, write_rows
from .dop853_coefficients import DOP853

__all__ = ["dop853_segment"]

# --- DOP853 coefficients (.dop853_coefficients) ------------------------------
_DA = DOP853.A                    # (16, 16)
_DC = DOP853.C                    # (16,)
_DB = DOP853.B                    # (12,)
_DE3 = DOP853.E3                  # (13,)
_DE5 = DOP853.E5                  # (13,)
_DD = DOP853.D                    # (4, 16)


@inner
def _combine(out, z, h, K, coef, n_rows):
    """out = z + h · Σ_{j < n_rows} coef[j] K[j] (zero coefficients skipped)."""
    ny = z.size
    for i in range(ny):
        out[i] = 0.0
    for j in range(n_rows):
        c = coef[j]
        if c != 0.0:
            for i in range(ny):
                out[i] += c * K[j, i]
    for i in range(ny):
        out[i] = z[i] + out[i] * h


@inner
def _dop853_error_norm(K, h, z, zn, rtol, atol, e5, e3):
    """SciPy's DOP853 error norm: |h|·‖e5‖² / sqrt((‖e5‖² + 0.01‖e3‖²)·ny),
    e5, e3 the 5th- and 3rd-order estimates scaled by atol + max(|z|, |zn|)·rtol."""
    ny = z.size
    for i in range(ny):
        e5[i] = 0.0
        e3[i] = 0.0
    for j in range(13):
        c5 = _DE5[j]
        c3 = _DE3[j]
        for i in range(ny):
            e5[i] += c5 * K[j, i]
            e3[i] += c3 * K[j, i]
    s5 = 0.0
    s3 = 0.0
    for i in range(ny):
        sc = atol[i] + max(abs(z[i]), abs(zn[i])) * rtol
        s5 += (e5[i] / sc) ** 2
        s3 += (e3[i] / sc) ** 2
    if s5 == 0.0 and s3 == 0.0:
        return 0.0
    return abs(h) * s5 / math.sqrt((s5 + 0.01 * s3) * ny)


@inner
def _dense_coefficients(F, K, z, zn, h):
    """F (7, ny): the dense output's coefficients of a step z → zn of
    length h from its 16 stages K (SciPy's ``Dop853DenseOutput``)."""
    ny = z.size
    for i in range(ny):
        dz = zn[i] - z[i]
        F[0, i] = dz
        F[1, i] = h * K[0, i] - dz
        F[2, i] = 2.0 * dz - h * (K[12, i] + K[0, i])
    for r in range(4):
        for i in range(ny):
            F[3 + r, i] = 0.0
        for j in range(16):
            c = _DD[r, j]
            if c != 0.0:
                for i in range(ny):
                    F[3 + r, i] += c * K[j, i]
        for i in range(ny):
            F[3 + r, i] *= h


@jit
def dop853_segment(t_a, t_b, z, shift, kernel, rtol, atol, dt_or_h0, h_max, grid, Y, k_out,
                   max_steps, p_idx, n_motion, counts, work):
    """Dormand–Prince 8(5,3) over [t_a, t_b], SciPy's DOP853 step control.

    See the module docstring for the parameters and returns; n_motion and
    work are unused. 12 evaluations per attempt, 1 at the start (+1 for the
    automatic first step), 3 more for a step with an output time inside it.
    """
    ny = z.size
    if not (t_b > t_a):
        return 0, t_b, dt_or_h0, k_out
    K = np.empty((16, ny))
    buf = np.empty((7, ny))
    ybuf, f, zn, zt, e5, e3, ft = buf[0], buf[1], buf[2], buf[3], buf[4], buf[5], buf[6]
    F = np.empty((7, ny))
    exponent = -1.0 / 8.0

    project(z, shift, p_idx, f)                 # f: scratch until the rhs below
    rhs(t_a, t_b, z, shift, ybuf, f, kernel)
    counts[0] += 1
    if not finite(f):
        return -2, t_a, dt_or_h0, k_out
    if dt_or_h0 > 0.0:
        h_abs = dt_or_h0
    else:
        h_abs = initial_step(t_a, t_b, z, f, shift, kernel, rtol, atol, h_max, np.int64(7),
                             ybuf, zt, ft, counts)
    t = t_a
    steps = 0
    while t < t_b:
        if steps >= max_steps:
            return 1, t, h_abs, k_out
        min_step = 10.0 * EPS * abs(t)
        if h_abs > h_max:
            h_abs = h_max
        elif h_abs < min_step:
            h_abs = min_step
        rejected = False
        t_new = t
        h = h_abs
        while True:
            if h_abs < min_step:
                return -1, t, h_abs, k_out
            t_new = t + h_abs
            if t_new > t_b:
                t_new = t_b
            h = t_new - t
            h_abs = abs(h)
            for i in range(ny):
                K[0, i] = f[i]
            for s in range(1, 12):
                _combine(zt, z, h, K, _DA[s], s)
                rhs(t + _DC[s] * h, t_b, zt, shift, ybuf, K[s], kernel)
            _combine(zn, z, h, K, _DB, _DB.size)
            rhs(t_new, t_b, zn, shift, ybuf, K[12], kernel)
            counts[0] += 12
            if not (finite(zn) and finite(K[12])):
                return -2, t, h_abs, k_out
            err = _dop853_error_norm(K, h, z, zn, rtol, atol, e5, e3)
            if not math.isfinite(err):
                return -2, t, h_abs, k_out
            if err < 1.0:
                if err == 0.0:
                    factor = 10.0
                else:
                    factor = min(10.0, 0.9 * err ** exponent)
                if rejected:
                    factor = min(1.0, factor)
                h_abs *= factor
                break
            h_abs *= max(0.2, 0.9 * err ** exponent)
            rejected = True
            counts[2] += 1
        counts[1] += 1
        steps += 1

        # output: 7th-order dense output inside the step, its 3 extra
        # stages only for a step with an output time inside
        k_dense = rows_inside(grid, k_out, t_new)
        if k_dense > k_out:
            for s in range(13, 16):
                _combine(zt, z, h, K, _DA[s], s)
                rhs(t + _DC[s] * h, t_b, zt, shift, ybuf, K[s], kernel)
            counts[0] += 3
            _dense_coefficients(F, K, z, zn, h)
        for k in range(k_out, k_dense):
            x = (grid[k] - t) / h
            for i in range(ny):
                acc = 0.0
                for m in range(7):               # F[6], F[5], …, F[0]; ×x, ×(1−x) alternately
                    acc += F[6 - m, i]
                    if m % 2 == 0:
                        acc *= x
                    else:
                        acc *= 1.0 - x
                Y[k, i] = acc + z[i] + shift[i]
        k_out = write_rows(grid, Y, k_out, k_dense, t_new, zn, shift, p_idx)

        for i in range(ny):
            z[i] = zn[i]
            f[i] = K[12, i]
        project(z, shift, p_idx, f)
        t = t_new
    return 0, t_b, h_abs, k_out

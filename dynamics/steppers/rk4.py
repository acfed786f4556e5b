"""Classical Runge–Kutta 4 in fixed steps, compiled (see
:mod:`flexbed.dynamics.steppers`)."""

from __future__ import annotations

import math

import numpy as np

from .common import finite, jit, project, rhs, rows_inside, write_rows

__all__ = ["rk4_segment"]


@jit
def rk4_segment(t_a, t_b, z, shift, kernel, rtol, atol, dt_or_h0, h_max, grid, Y, k_out, max_steps,
                p_idx, n_motion, counts, work):
    """Classical RK4 over [t_a, t_b] in equal steps of at most min(dt_or_h0, h_max).

    See the module docstring for the parameters and returns; rtol, atol,
    n_motion and work are unused. 4 evaluations per step and 1 at the start.
    """
    ny = z.size
    if not (t_b > t_a):
        return 0, t_b, dt_or_h0, k_out
    dt = min(dt_or_h0, h_max)
    n = max(1, int(math.ceil((t_b - t_a) / dt - 1e-9)))
    h = (t_b - t_a) / n
    buf = np.empty((7, ny))
    ybuf, f, k2, k3, k4, zt, zn = buf[0], buf[1], buf[2], buf[3], buf[4], buf[5], buf[6]
    fn = np.empty(ny)

    project(z, shift, p_idx, f)                 # f: scratch until the rhs below
    rhs(t_a, t_b, z, shift, ybuf, f, kernel)
    counts[0] += 1
    if not finite(f):
        return -2, t_a, h, k_out
    t = t_a
    for step in range(n):
        if step >= max_steps:
            return 1, t, h, k_out
        t_new = t_b if step == n - 1 else t_a + (step + 1) * h
        hs = t_new - t
        for i in range(ny):
            zt[i] = z[i] + 0.5 * hs * f[i]
        rhs(t + 0.5 * hs, t_b, zt, shift, ybuf, k2, kernel)
        for i in range(ny):
            zt[i] = z[i] + 0.5 * hs * k2[i]
        rhs(t + 0.5 * hs, t_b, zt, shift, ybuf, k3, kernel)
        for i in range(ny):
            zt[i] = z[i] + hs * k3[i]
        rhs(t_new, t_b, zt, shift, ybuf, k4, kernel)
        for i in range(ny):
            zn[i] = z[i] + (hs / 6.0) * (f[i] + 2.0 * (k2[i] + k3[i]) + k4[i])
        counts[0] += 3
        if not finite(zn):
            return -2, t, h, k_out
        rhs(t_new, t_b, zn, shift, ybuf, fn, kernel)
        counts[0] += 1
        if not finite(fn):
            return -2, t, h, k_out
        counts[1] += 1

        # output: cubic Hermite on (z, f) -> (zn, fn) inside the step
        k_dense = rows_inside(grid, k_out, t_new)
        for k in range(k_out, k_dense):
            s = (grid[k] - t) / hs
            h00 = (1.0 + 2.0 * s) * (1.0 - s) ** 2
            h10 = s * (1.0 - s) ** 2
            h01 = s * s * (3.0 - 2.0 * s)
            h11 = s * s * (s - 1.0)
            for i in range(ny):
                Y[k, i] = (h00 * z[i] + h10 * hs * f[i] + h01 * zn[i] + h11 * hs * fn[i]
                           + shift[i])
        k_out = write_rows(grid, Y, k_out, k_dense, t_new, zn, shift, p_idx)

        for i in range(ny):
            z[i] = zn[i]
            f[i] = fn[i]
        project(z, shift, p_idx, f)
        t = t_new
    return 0, t_b, h, k_out

"""Radau IIA of order 5, compiled (see :mod:`flexbed.dynamics.steppers`),
its workspace, and its linear algebra through LAPACK (:mod:`.lapack`)."""

from __future__ import annotations

import math

import numpy as np

from .common import (inner, EPS, SQRT_EPS, finite, initial_step, jit, project, rhs, rows_inside,
                     write_rows)
from .lapack import LAPACK
from .radau_coefficients import RADAU

__all__ = ["radau_segment", "radau_workspace", "radau_reset"]

# --- Radau IIA (order 5) constants (.radau_coefficients) ---------------------
_RT = RADAU.T                     # (3, 3) eigenvectors of A⁻¹
_RTI = RADAU.TI                   # (3, 3) their inverse
_RC = RADAU.C                     # (3,) stage times
_RE = RADAU.E                     # (3,) error estimate
_RP = RADAU.P                     # (3, 3) dense output
_MU_REAL = RADAU.MU_REAL
_MU_COMPLEX = RADAU.MU_COMPLEX
_TIC0, _TIC1, _TIC2 = (complex(c) for c in RADAU.TI_COMPLEX)   # T⁻¹'s complex row
_NEWTON_MAXITER = 6
_LU_REUSE_RTOL = 1e-6   # |h − h_lu| ≤ this·h_lu: same h (round-off of t_new − t)
# radau keeps h (and its LU factors) when the proposed ratio h_new/h lies in
# [_KEEP_H_LOW, 1.2): 1.0 would be Hairer's quot1; -inf is SciPy's rule (keep
# h for every ratio below 1.2), which took 1.6-17 times fewer LUs on the
# checks of this module, for similar steps, and less time on ny = 61.
_KEEP_H_LOW = -math.inf

# radau workspace: the scalar state vector's entries
_S_RESUME, _S_T, _S_H_LU, _S_CURRENT_JAC, _S_HAS_OLD, _S_H_OLD, _S_ERR_OLD, \
    _S_HAS_SOL, _S_T_SOL, _S_H_SOL = range(10)
_N_RESET = 10                     # the entries above: a reset zeroes them
_S_KEEP_LO, _S_SCIPY_LIKE = 10, 11     # the options (see radau_workspace)
_N_STATE = 12


def radau_workspace(ny: int, *, keep_h_low: float = _KEEP_H_LOW, scipy_like: bool = False) -> tuple:
    """Workspace of :func:`radau_segment` for a state of ny components.

    Parameters
    ----------
    ny : int
    keep_h_low : float
        h is kept (and the LU factors with it) when the proposed ratio
        h_new/h lies in [keep_h_low, 1.2) and the Jacobian is not
        recomputed: 1.0 would be Hairer's quot1; SciPy's ``Radau`` in
        effect uses −inf (h kept for every ratio below 1.2), the default.
    scipy_like : bool
        For verification only: SciPy ``Radau``'s other choices where they
        differ from this module's — the LU factors reused after a step was
        cut at t_b (h changed), no extra error evaluation on a segment's
        first step, no bounds on the accepted step's ratio nor on the error
        remembered by the predictive controller (Hairer: ≥ 0.2, ≥ 1e-2).
        With keep_h_low = −inf it takes SciPy's steps.

    Returns
    -------
    tuple
        (JT (ny, ny) float64, the Jacobian transposed: JT[j, i] = ∂f_i/∂z_j;
        LUr (ny, ny) float64, pivr (ny,) int32: LU of μ_r/h I − J (Fortran
        order); LUc (ny, ny) complex128, pivc (ny,) int32: LU of μ_c/h I − J;
        Q (3, ny) float64, z_old (ny,) float64: the last step's dense output
        z(t_old + x h) = z_old + Q[0] x + Q[1] x² + Q[2] x³; state (12,)
        float64: flags and scalars (resume flag, time, h of the LU factors,
        current-Jacobian flag, controller history, dense-output interval,
        then the two options);
        (dgetrf, dgetrs, zgetrf, zgetrs) ctypes LAPACK functions).
        A new workspace (or :func:`radau_reset`) starts afresh.
    """
    ny = int(ny)
    state = np.zeros(_N_STATE)
    state[_S_KEEP_LO] = keep_h_low
    state[_S_SCIPY_LIKE] = 1.0 if scipy_like else 0.0
    return (np.zeros((ny, ny)), np.zeros((ny, ny)), np.zeros(ny, np.int32),
            np.zeros((ny, ny), np.complex128), np.zeros(ny, np.int32),
            np.zeros((3, ny)), np.zeros(ny), state, LAPACK)


def radau_reset(work: tuple) -> None:
    """Forget a paused call: the next :func:`radau_segment` starts afresh
    (new Jacobian, projection, no history)."""
    work[7][:_N_RESET] = 0.0


@inner
def _jacobian(t, t_b, z, f0, shift, kernel, JT, n_motion, zj, ybuf, fj, counts):
    """Forward differences over z[:n_motion] at (t, z), f0 = f(t, z):
    JT[j, i] = ∂f_i/∂z_j, steps sqrt(eps)·max(1, |z_j + shift_j|); rows
    n_motion… are zero. n_motion evaluations."""
    ny = z.size
    for i in range(ny):
        zj[i] = z[i]
    for j in range(n_motion):
        zj[j] = z[j] + SQRT_EPS * max(1.0, abs(z[j] + shift[j]))
        delta = zj[j] - z[j]
        rhs(t, t_b, zj, shift, ybuf, fj, kernel)
        for i in range(ny):
            JT[j, i] = (fj[i] - f0[i]) / delta
        zj[j] = z[j]
    for j in range(n_motion, ny):
        for i in range(ny):
            JT[j, i] = 0.0
    counts[0] += n_motion
    counts[3] += 1


@inner
def _factor(h, JT, LUr, pivr, LUc, pivc, lapack, nn, info, counts):
    """LU of μ_r/h I − J and μ_c/h I − J (Fortran order: JT transposed).
    Returns whether both are regular."""
    dgetrf, zgetrf = lapack[0], lapack[2]
    ny = JT.shape[0]
    mr = _MU_REAL / h
    mc = _MU_COMPLEX / h
    for j in range(ny):
        for i in range(ny):
            LUr[j, i] = -JT[j, i]
            LUc[j, i] = -JT[j, i]
        LUr[j, j] += mr
        LUc[j, j] += mc
    dgetrf(nn.ctypes, nn.ctypes, LUr.ctypes, nn.ctypes, pivr.ctypes, info.ctypes)
    ok = info[0] == 0
    zgetrf(nn.ctypes, nn.ctypes, LUc.ctypes, nn.ctypes, pivc.ctypes, info.ctypes)
    ok = ok and info[0] == 0
    counts[4] += 1
    return ok


@inner
def _rms3(dW, scale):
    """sqrt(mean((dW / scale)²)) over the (3, ny) array dW."""
    ny = scale.size
    s = 0.0
    for r in range(3):
        for i in range(ny):
            s += (dW[r, i] / scale[i]) ** 2
    return math.sqrt(s / (3 * ny))


@inner
def _solve_real(lapack, trans, nn, one, LU, piv, b, info):
    """b ← (LU)⁻¹ b with the real factors of :func:`_factor` (in place)."""
    lapack[1](trans.ctypes, nn.ctypes, one.ctypes, LU.ctypes, nn.ctypes, piv.ctypes, b.ctypes,
              nn.ctypes, info.ctypes)


@inner
def _solve_complex(lapack, trans, nn, one, LU, piv, b, info):
    """b ← (LU)⁻¹ b with the complex factors of :func:`_factor` (in place)."""
    lapack[3](trans.ctypes, nn.ctypes, one.ctypes, LU.ctypes, nn.ctypes, piv.ctypes, b.ctypes,
              nn.ctypes, info.ctypes)


@inner
def _newton(t, t_b, z, h, Z0, scale, tol, shift, kernel, LUr, pivr, LUc, pivc, lapack, Z, W, F, dW,
            ybuf, zt, br, bc, nn, one, info, trans, counts):
    """Simplified Newton iteration for the collocation system (SciPy's
    ``solve_collocation_system``), in the variables W = T⁻¹ Z.

    Z0 (3, ny): starting guess, z + Z0[i] ≈ z(t + C_i h). Writes the stages
    into Z. Returns (converged, iterations, rate; rate < 0: undefined).
    """
    ny = z.size
    mr = _MU_REAL / h
    mc = _MU_COMPLEX / h
    for r in range(3):
        for i in range(ny):
            W[r, i] = _RTI[r, 0] * Z0[0, i] + _RTI[r, 1] * Z0[1, i] + _RTI[r, 2] * Z0[2, i]
            Z[r, i] = Z0[r, i]
    dW_norm_old = 0.0
    has_old = False
    rate = -1.0
    converged = False
    n_iter = 0
    for k in range(_NEWTON_MAXITER):
        n_iter = k + 1
        for r in range(3):
            for i in range(ny):
                zt[i] = z[i] + Z[r, i]
            rhs(t + h * _RC[r], t_b, zt, shift, ybuf, F[r], kernel)
        counts[0] += 3
        if not (finite(F[0]) and finite(F[1]) and finite(F[2])):
            break
        for i in range(ny):
            br[i] = (_RTI[0, 0] * F[0, i] + _RTI[0, 1] * F[1, i] + _RTI[0, 2] * F[2, i]
                     - mr * W[0, i])
            bc[i] = (_TIC0 * F[0, i] + _TIC1 * F[1, i] + _TIC2 * F[2, i]
                     - mc * (W[1, i] + 1j * W[2, i]))
        _solve_real(lapack, trans, nn, one, LUr, pivr, br, info)
        _solve_complex(lapack, trans, nn, one, LUc, pivc, bc, info)
        for i in range(ny):
            dW[0, i] = br[i]
            dW[1, i] = bc[i].real
            dW[2, i] = bc[i].imag
        dW_norm = _rms3(dW, scale)
        if not math.isfinite(dW_norm):
            break
        if has_old:
            rate = dW_norm / dW_norm_old
            if rate >= 1.0 or rate ** (_NEWTON_MAXITER - k) / (1.0 - rate) * dW_norm > tol:
                break
        for r in range(3):
            for i in range(ny):
                W[r, i] += dW[r, i]
        for r in range(3):
            for i in range(ny):
                Z[r, i] = _RT[r, 0] * W[0, i] + _RT[r, 1] * W[1, i] + _RT[r, 2] * W[2, i]
        if dW_norm == 0.0 or (has_old and rate / (1.0 - rate) * dW_norm < tol):
            converged = True
            break
        dW_norm_old = dW_norm
        has_old = True
    return converged, n_iter, rate


@inner
def _rms(x, scale):
    """sqrt(mean((x / scale)²)) over the 1-D array x."""
    s = 0.0
    for i in range(x.size):
        s += (x[i] / scale[i]) ** 2
    return math.sqrt(s / x.size)


@inner
def _predict_factor(h_abs, h_abs_old, err, err_old, has_old):
    """Predictive step-size factor (Gustafsson; Hairer & Wanner II, IV.8)."""
    if not has_old or err == 0.0:
        mult = 1.0
    else:
        mult = h_abs / h_abs_old * (err_old / err) ** 0.25
    if err == 0.0:
        return math.inf
    return min(1.0, mult) * err ** -0.25


@jit
def radau_segment(t_a, t_b, z, shift, kernel, rtol, atol, dt_or_h0, h_max, grid, Y, k_out,
                  max_steps, p_idx, n_motion, counts, work):
    """Radau IIA of order 5 over [t_a, t_b] (see the module docstring).

    work : tuple from :func:`radau_workspace` (ny), with the options. A
    call resumes the previous one (same Jacobian, LU factors, dense output
    and controller history; no projection) when that one paused (status 1)
    at t == t_a; otherwise it starts afresh: projects z, evaluates f and the
    Jacobian at (t_a, z) (1 + n_motion evaluations).
    """
    JT, LUr, pivr, LUc, pivc, Q, z_sol, st, lapack = work
    keep_lo = st[_S_KEEP_LO]
    scipy_like = st[_S_SCIPY_LIKE] == 1.0
    ny = z.size
    if JT.shape[0] != ny or atol.size != ny or shift.size != ny:
        raise ValueError("radau_segment: workspace, atol or shift do not match the state size")
    if not (t_b > t_a):
        st[_S_RESUME] = 0.0
        return 0, t_b, dt_or_h0, k_out
    buf = np.empty((10, ny))
    ybuf, f, zn, zt, scale, err, ze, fj, zj, fn = (buf[0], buf[1], buf[2], buf[3], buf[4],
                                                     buf[5], buf[6], buf[7], buf[8], buf[9])
    st3 = np.empty((5, 3, ny))
    Z, W, F, dW, Z0 = st3[0], st3[1], st3[2], st3[3], st3[4]
    bc = np.empty(ny, np.complex128)
    nn = np.full(1, ny, np.int32)
    one = np.ones(1, np.int32)
    info = np.zeros(1, np.int32)
    trans = np.full(1, ord("N"), np.uint8)

    resume = st[_S_RESUME] == 1.0 and st[_S_T] == t_a
    st[_S_RESUME] = 0.0
    if not resume:
        project(z, shift, p_idx, f)             # f: scratch until the rhs below
        st[_S_HAS_SOL] = 0.0
        st[_S_HAS_OLD] = 0.0
        st[_S_H_LU] = 0.0
    rhs(t_a, t_b, z, shift, ybuf, f, kernel)
    counts[0] += 1
    if not finite(f):
        return -2, t_a, dt_or_h0, k_out
    if resume:
        current_jac = st[_S_CURRENT_JAC] == 1.0
    else:
        _jacobian(t_a, t_b, z, f, shift, kernel, JT, n_motion, zj, ybuf, fj, counts)
        current_jac = True
    h_lu = st[_S_H_LU]                       # 0: no valid LU factors
    if dt_or_h0 > 0.0:
        h_abs = dt_or_h0
    else:
        h_abs = initial_step(t_a, t_b, z, f, shift, kernel, rtol, atol, h_max, np.int64(3), ybuf,
                              zt, fj, counts)
    newton_tol = max(10.0 * EPS / rtol, min(0.03, math.sqrt(rtol)))
    first = not resume
    t = t_a
    steps = 0
    status = 0
    n_iter = 0
    rate = -1.0
    error_norm = 0.0
    while t < t_b:
        if steps >= max_steps:
            status = 1
            break
        min_step = 10.0 * EPS * abs(t)
        h_proposed = h_abs
        has_old = st[_S_HAS_OLD] == 1.0
        if h_abs > h_max:
            h_abs = h_max
            has_old = False
        elif h_abs < min_step:
            h_abs = min_step
            has_old = False
        h_abs_old = st[_S_H_OLD]
        err_old = st[_S_ERR_OLD]
        rejected = False
        accepted = False
        h = h_abs
        t_new = t
        safety = 0.9
        while not accepted:
            if h_abs < min_step:
                status = -1
                break
            t_new = t + h_abs
            if t_new > t_b:
                t_new = t_b
            h = t_new - t
            h_abs = abs(h)
            # starting guess: the last step's collocation polynomial
            if st[_S_HAS_SOL] == 1.0:
                for r in range(3):
                    x = (t + h * _RC[r] - st[_S_T_SOL]) / st[_S_H_SOL]
                    x2 = x * x
                    x3 = x2 * x
                    for i in range(ny):
                        Z0[r, i] = (Q[0, i] * x + Q[1, i] * x2 + Q[2, i] * x3 + z_sol[i]) - z[i]
            else:
                for r in range(3):
                    for i in range(ny):
                        Z0[r, i] = 0.0
            for i in range(ny):
                scale[i] = atol[i] + abs(z[i]) * rtol
            converged = False
            while True:
                lu_ok = h_lu != 0.0 and (scipy_like or abs(h - h_lu) <= _LU_REUSE_RTOL * h_lu)
                regular = True
                if not lu_ok:
                    regular = _factor(h, JT, LUr, pivr, LUc, pivc, lapack, nn, info, counts)
                    h_lu = h if regular else 0.0
                if regular:
                    converged, n_iter, rate = _newton(t, t_b, z, h, Z0, scale, newton_tol, shift,
                                                      kernel, LUr, pivr, LUc, pivc, lapack, Z, W, F,
                                                      dW, ybuf, zt, err, bc, nn, one, info, trans,
                                                      counts)
                if converged or current_jac:
                    break
                _jacobian(t, t_b, z, f, shift, kernel, JT, n_motion, zj, ybuf, fj, counts)
                current_jac = True
                h_lu = 0.0
            if not converged:
                h_abs *= 0.5
                h_lu = 0.0
                counts[2] += 1
                continue
            for i in range(ny):
                zn[i] = z[i] + Z[2, i]
                ze[i] = (Z[0, i] * _RE[0] + Z[1, i] * _RE[1] + Z[2, i] * _RE[2]) / h
                err[i] = f[i] + ze[i]
            _solve_real(lapack, trans, nn, one, LUr, pivr, err, info)
            for i in range(ny):
                scale[i] = atol[i] + max(abs(z[i]), abs(zn[i])) * rtol
            error_norm = _rms(err, scale)
            safety = 0.9 * (2 * _NEWTON_MAXITER + 1) / (2 * _NEWTON_MAXITER + n_iter)
            if (rejected or (first and not scipy_like)) and error_norm > 1.0:
                for i in range(ny):
                    zt[i] = z[i] + err[i]
                rhs(t, t_b, zt, shift, ybuf, fj, kernel)
                counts[0] += 1
                for i in range(ny):
                    err[i] = fj[i] + ze[i]
                _solve_real(lapack, trans, nn, one, LUr, pivr, err, info)
                error_norm = _rms(err, scale)
            if error_norm > 1.0 or not math.isfinite(error_norm):
                factor = _predict_factor(h_abs, h_abs_old, error_norm, err_old, has_old)
                h_abs *= max(0.2, safety * factor) if math.isfinite(error_norm) else 0.2
                h_lu = 0.0
                rejected = True
                counts[2] += 1
            else:
                accepted = True
        if status != 0:
            break

        recompute_jac = n_iter > 2 and rate > 1e-3
        factor = _predict_factor(h_abs, h_abs_old, error_norm, err_old, has_old)
        factor = min(10.0, safety * factor)
        if not scipy_like:
            factor = max(0.2, factor)        # Hairer's facl (SciPy: no lower bound)
        if not recompute_jac and keep_lo <= factor < 1.2:
            factor = 1.0
        else:
            h_lu = 0.0
        rhs(t_new, t_b, zn, shift, ybuf, fn, kernel)
        counts[0] += 1
        if not (finite(zn) and finite(fn)):
            status = -2
            break
        counts[1] += 1
        steps += 1

        # dense output of this step: z(t + x h) = z + Q·(x, x², x³)
        for m in range(3):
            for i in range(ny):
                Q[m, i] = Z[0, i] * _RP[0, m] + Z[1, i] * _RP[1, m] + Z[2, i] * _RP[2, m]
        for i in range(ny):
            z_sol[i] = z[i]
        st[_S_T_SOL] = t
        st[_S_H_SOL] = h
        st[_S_HAS_SOL] = 1.0
        k_dense = rows_inside(grid, k_out, t_new)
        for k in range(k_out, k_dense):
            x = (grid[k] - t) / h
            x2 = x * x
            x3 = x2 * x
            for i in range(ny):
                Y[k, i] = (Q[0, i] * x + Q[1, i] * x2 + Q[2, i] * x3 + z[i]) + shift[i]
        k_out = write_rows(grid, Y, k_out, k_dense, t_new, zn, shift, p_idx)

        for i in range(ny):
            z[i] = zn[i]
            f[i] = fn[i]
        t = t_new
        if recompute_jac:
            _jacobian(t, t_b, z, f, shift, kernel, JT, n_motion, zj, ybuf, fj, counts)
            current_jac = True
        else:
            current_jac = False
        st[_S_HAS_OLD] = 1.0
        st[_S_H_OLD] = h_proposed
        # Hairer's erracc = max(1e-2, err): an exactly zero error (a state at
        # rest) must not drive the next prediction to h = 0
        st[_S_ERR_OLD] = error_norm if scipy_like else max(1e-2, error_norm)
        h_abs = h_abs * factor
        first = False

    st[_S_RESUME] = 1.0 if status == 1 else 0.0
    st[_S_T] = t
    st[_S_H_LU] = h_lu
    st[_S_CURRENT_JAC] = 1.0 if current_jac else 0.0
    if status == 0:
        t = t_b
    return status, t, h_abs, k_out

"""Compiled time steppers: one segment of y' = f(t, y) entirely in numba.

SciPy's ``solve_ivp`` steppers spend hundreds of µs of Python per step; the
steppers here run a whole segment [t_a, t_b] (or a chunk of it) inside one
nopython call, calling the compiled right-hand side ``evaluate`` directly,
so that a step costs a few µs beyond its right-hand-side evaluations.

Methods
-------
``rk4_segment``
    Classical Runge–Kutta 4, n = max(1, ceil((t_b − t_a)/dt − 1e-9)) equal
    steps (dt = min(dt_or_h0, h_max)), the last one landing exactly on t_b;
    f at each new point is evaluated once and reused (4 evaluations per
    step, 1 at the start); cubic Hermite dense output.
``dop853_segment``
    Explicit Dormand–Prince 8(5,3) with SciPy's ``DOP853`` step-size
    control, error norm (the 5th-order estimate corrected by the 3rd-order
    one), initial-step selection (``select_initial_step``) and 7th-order
    dense output (the 3 extra stages are evaluated only for steps that hold
    an output time strictly inside). The coefficient arrays are SciPy's
    (``scipy.integrate._ivp.dop853_coefficients``).
``radau_segment``
    Implicit Radau IIA of order 5 (3 stages), after Hairer & Wanner's RADAU5
    as in SciPy's ``Radau``: simplified Newton iteration in the variables
    transformed by the eigenvectors of the method's matrix (one real and one
    complex n×n system), convergence-rate control (at most 6 iterations,
    tolerance max(10 eps/rtol, min(0.03, sqrt(rtol)))), the embedded
    3rd-order error estimate filtered by (μ_r/h I − J)⁻¹, filtered once
    more with one more evaluation when it exceeds 1 on a segment's first
    step or after a rejection (Hairer's "first or reject"; SciPy only after
    a rejection), SciPy's predictive (Gustafsson) step-size controller with
    Hairer's bounds (accepted ratio ≥ 0.2, remembered error ≥ 1e-2), the
    collocation polynomial as dense output and as the Newton starting
    guess. The Jacobian is reused across steps and recomputed only when
    Newton converged slowly (more than 2 iterations and rate > 1e-3) or
    failed with an old Jacobian (then h is halved if it fails again). The LU
    factors are recomputed only when h changes (by more than 1e-6
    relatively: t_new − t rounds): h is kept when the proposed ratio is
    below 1.2, SciPy's rule (``_KEEP_H_LOW``; Hairer's quot1 = 1 would keep
    it only in [1, 1.2), which took 1.6 to 17 times more LUs on this
    module's checks, for fewer rejections). Coefficients T, T⁻¹, C, E, P, μ are SciPy's
    (``scipy.integrate._ivp.radau``).

Interface
---------
Every stepper is called once per segment (or per chunk of one)::

    status, t, h, k_out = <method>_segment(t_a, t_b, z, shift, d, rtol, atol,
                                           dt_or_h0, h_max, grid, Y, k_out,
                                           max_steps, p_idx, n_motion,
                                           counts, work)

and integrates the deviation z = y − shift (``evaluate`` receives
y = z + shift; shift is constant):

t_a, t_b : float [s]
    The segment, t_b > t_a (t_b ≤ t_a: nothing to do, status 0).
z : (ny,) float64
    State at t_a; overwritten with the state reached.
shift : (ny,) float64
    Constant offset, y = z + shift.
d : namedtuple of arrays
    The compiled scene, passed to ``evaluate`` untouched.
rtol : float; atol : (ny,) float64
    Tolerances (atol = 1e30 marks a quadrature: integrated, but in effect
    out of the error control). rk4 ignores both.
dt_or_h0 : float [s]
    rk4: the longest step; dop853, radau: the first step to try (0.0:
    automatic selection, SciPy's ``select_initial_step``).
h_max : float [s]
    Longest step allowed (may be inf); rk4 steps at most
    min(dt_or_h0, h_max).
grid : (k,) float64 [s]; Y : (k, ny) float64; k_out : int
    Output times, ascending; their rows; the first index not yet written.
    For each grid time in (t_old, t_new] of every accepted step,
    ``Y[k] = dense(grid[k]) + shift`` (a time within 1e-12·max(1, t_new) of
    t_new takes the step's end state), then each body's Euler parameters in
    Y[k] are normalised. Grid times at or before t_a must already be written.
max_steps : int
    Most accepted steps this call may take; reached before t_b: status 1
    (paused) with t, z and the next step h; call again with dt_or_h0 = h.
p_idx : (n_bodies, 4) int64
    Indices into y of every rotating body's Euler parameters (0 rows: none).
    rk4, dop853: projected onto |p| = 1 at the start and after every
    accepted step, the stored derivative's rows divided by the same |p|
    (ṗ is linear in p). radau: at the start of a call that does not resume
    a paused one (so that pausing does not change its numbers).
n_motion : int
    The first n_motion components are the motion; the others are
    quadratures nothing depends on (radau: their Jacobian columns are zero).
counts : (5,) int64
    Incremented in place: [right-hand sides (Jacobian differences included),
    accepted steps, rejected steps, Jacobians, LU decompositions (a real and
    a complex factorisation together count as one)].
work
    radau: the workspace from :func:`radau_workspace` (Jacobian, LU factors,
    the last step's dense output, controller history), so that a paused
    call resumes exactly where it stopped. rk4, dop853: ignored (pass ()).

Returns status (0: reached t_b, t == t_b exactly; 1: paused by max_steps;
-1: step size too small, |h| < 10·eps·|t| (radau: also after Newton
failures that halving h does not cure); -2: a step's new state or its
derivative is non-finite — the step is not taken and z holds the last
finite state), t [s] reached, h [s] the next step to try
(rk4: the step used), and k_out. Nothing inside raises for these.

Every array is allocated once per call, none per step. The functions are
compiled with ``error_model="numpy"``: a division by zero gives inf or nan
(caught by the finiteness checks) instead of raising.

LAPACK
------
radau factors with LAPACK ``dgetrf``/``zgetrf`` and solves with
``dgetrs``/``zgetrs`` (no inverse): their C entry points are taken from
``scipy.linalg.cython_lapack.__pyx_capi__`` (PyCapsule → address with
``ctypes.pythonapi.PyCapsule_GetPointer``) and wrapped as ``ctypes.CFUNCTYPE``
objects with all-pointer arguments. These ctypes objects travel in the
workspace tuple, i.e. as *arguments*: numba calls ctypes function pointers
in nopython mode, but one referenced as a global has its address frozen
into the machine code and cannot be cached (“uses dynamic globals”), while
an argument is read at run time and caches. Matrices are stored so that
their C order is the Fortran order LAPACK expects: the Jacobian is kept
transposed, ``JT[j, i] = ∂f_i/∂z_j`` (a difference column is then a
contiguous row), and ``LU[j, i] = M δ_ij − JT[j, i]`` is M I − J in
Fortran order; the solves use trans = 'N'. Scalars go as 1-element int32
arrays (LAPACK's int is 32-bit here).

Cache
-----
All functions are ``numba.njit(cache=True)``. Numba invalidates a cached
function only when its *own* source file changes, not when a compiled
function it calls does (the cached machine code contains the callee); so
this module keeps a hash of the sources of ``evaluate``'s module and of the
modules of its package that module uses, and flushes its own cache when
that hash changes (see :func:`_refresh_cache`).
"""

from __future__ import annotations

import ctypes
import hashlib
import math
import os
import sys
import types

import numba
import numpy as np
from numba.core.dispatcher import Dispatcher
from scipy.integrate._ivp import dop853_coefficients as _dop
from scipy.integrate._ivp import radau as _rad
from scipy.linalg import cython_lapack

from .kernel import evaluate

__all__ = ["rk4_segment", "dop853_segment", "radau_segment", "radau_workspace", "radau_reset",
           "N_COUNTS", "STATUS"]

N_COUNTS = 5
STATUS = {0: "reached t_b", 1: "paused (max_steps)", -1: "step size too small",
          -2: "non-finite state"}

_jit = numba.njit(cache=True, error_model="numpy")

_EPS = float(np.finfo(float).eps)
_SQRT_EPS = math.sqrt(_EPS)

# --- DOP853 coefficients (SciPy's) -------------------------------------------
_DA = np.ascontiguousarray(_dop.A, dtype=np.float64)          # (16, 16)
_DC = np.ascontiguousarray(_dop.C, dtype=np.float64)          # (16,)
_DB = np.ascontiguousarray(_dop.B, dtype=np.float64)          # (12,)
_DE3 = np.ascontiguousarray(_dop.E3, dtype=np.float64)        # (13,)
_DE5 = np.ascontiguousarray(_dop.E5, dtype=np.float64)        # (13,)
_DD = np.ascontiguousarray(_dop.D, dtype=np.float64)          # (4, 16)

# --- Radau IIA (order 5) coefficients (SciPy's) ------------------------------
_RT = np.ascontiguousarray(_rad.T, dtype=np.float64)          # (3, 3) eigenvectors of A
_RTI = np.ascontiguousarray(_rad.TI, dtype=np.float64)        # (3, 3) their inverse
_RC = np.ascontiguousarray(_rad.C, dtype=np.float64)          # (3,) stage times
_RE = np.ascontiguousarray(_rad.E, dtype=np.float64)          # (3,) error estimate
_RP = np.ascontiguousarray(_rad.P, dtype=np.float64)          # (3, 3) dense output
_MU_REAL = float(_rad.MU_REAL)
_MU_COMPLEX = complex(_rad.MU_COMPLEX)
_TIC0, _TIC1, _TIC2 = (complex(_RTI[1, k], _RTI[2, k]) for k in range(3))  # T⁻¹'s complex row
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
_N_STATE = 10


# ============================================================================
# LAPACK entry points
# ============================================================================

def _lapack_function(name: str):
    """ctypes function for scipy.linalg.cython_lapack's ``name`` (all arguments pointers)."""
    capsule = cython_lapack.__pyx_capi__[name]
    get_name = ctypes.pythonapi.PyCapsule_GetName
    get_name.restype = ctypes.c_char_p
    get_name.argtypes = [ctypes.py_object]
    get_pointer = ctypes.pythonapi.PyCapsule_GetPointer
    get_pointer.restype = ctypes.c_void_p
    get_pointer.argtypes = [ctypes.py_object, ctypes.c_char_p]
    address = get_pointer(capsule, get_name(capsule))
    n_args = {"dgetrf": 6, "zgetrf": 6, "dgetrs": 9, "zgetrs": 9}[name]
    return ctypes.CFUNCTYPE(None, *([ctypes.c_void_p] * n_args))(address)


# (dgetrf, dgetrs, zgetrf, zgetrs): getrf(m, n, a, lda, ipiv, info);
# getrs(trans, n, nrhs, a, lda, ipiv, b, ldb, info)
_LAPACK = tuple(_lapack_function(n) for n in ("dgetrf", "dgetrs", "zgetrf", "zgetrs"))


def radau_workspace(ny: int) -> tuple:
    """Workspace of :func:`radau_segment` for a state of ny components.

    Returns
    -------
    tuple
        (JT (ny, ny) float64, the Jacobian transposed: JT[j, i] = ∂f_i/∂z_j;
        LUr (ny, ny) float64, pivr (ny,) int32: LU of μ_r/h I − J (Fortran
        order); LUc (ny, ny) complex128, pivc (ny,) int32: LU of μ_c/h I − J;
        Q (3, ny) float64, z_old (ny,) float64: the last step's dense output
        z(t_old + x h) = z_old + Q[0] x + Q[1] x² + Q[2] x³; state (10,)
        float64: flags and scalars (resume flag, time, h of the LU factors,
        current-Jacobian flag, controller history, dense-output interval);
        (dgetrf, dgetrs, zgetrf, zgetrs) ctypes LAPACK functions).
        A new workspace (or :func:`radau_reset`) starts afresh.
    """
    ny = int(ny)
    return (np.zeros((ny, ny)), np.zeros((ny, ny)), np.zeros(ny, np.int32),
            np.zeros((ny, ny), np.complex128), np.zeros(ny, np.int32),
            np.zeros((3, ny)), np.zeros(ny), np.zeros(_N_STATE), _LAPACK)


def radau_reset(work: tuple) -> None:
    """Forget a paused call: the next :func:`radau_segment` starts afresh
    (new Jacobian, projection, no history)."""
    work[7][:] = 0.0


# ============================================================================
# Helpers
# ============================================================================

@_jit
def _rhs(t, seg_end, z, shift, ybuf, dz, d):
    """dz = f(t, z + shift); ybuf (ny,) scratch."""
    for i in range(z.size):
        ybuf[i] = z[i] + shift[i]
    evaluate(t, seg_end, ybuf, dz, d)


@_jit
def _finite(x):
    """Whether every entry of the 1-D array x is finite."""
    for i in range(x.size):
        if not math.isfinite(x[i]):
            return False
    return True


@_jit
def _project(z, shift, p_idx, f, scale_f):
    """Euler parameters of z + shift onto |p| = 1 (in z); if scale_f, the
    same rows of f divided by the same |p|."""
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
            if scale_f:
                f[j] /= nrm


@_jit
def _normalise_row(Y, k, p_idx):
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


@_jit
def _end_tol(t_new):
    """Grid times within this of t_new take the step's end state."""
    return 1e-12 * max(1.0, abs(t_new))


@_jit
def _put_end(Y, k, z_new, shift):
    """Y[k] = z_new + shift."""
    for i in range(z_new.size):
        Y[k, i] = z_new[i] + shift[i]


@_jit
def _initial_step(t0, t_b, z, f0, shift, d, rtol, atol, h_max, order, ybuf, z1, f1, counts):
    """SciPy's ``select_initial_step`` (Hairer, Nørsett & Wanner I, II.4).

    order : error-estimator order (dop853: 7; radau: 3). One evaluation.
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
    _rhs(t0 + h0, t_b, z1, shift, ybuf, f1, d)
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


# ============================================================================
# RK4
# ============================================================================

@_jit
def rk4_segment(t_a, t_b, z, shift, d, rtol, atol, dt_or_h0, h_max, grid, Y, k_out, max_steps,
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

    _project(z, shift, p_idx, f, False)
    _rhs(t_a, t_b, z, shift, ybuf, f, d)
    counts[0] += 1
    if not _finite(f):
        return -2, t_a, h, k_out
    t = t_a
    for step in range(n):
        if step >= max_steps:
            return 1, t, h, k_out
        t_new = t_b if step == n - 1 else t_a + (step + 1) * h
        hs = t_new - t
        for i in range(ny):
            zt[i] = z[i] + 0.5 * hs * f[i]
        _rhs(t + 0.5 * hs, t_b, zt, shift, ybuf, k2, d)
        for i in range(ny):
            zt[i] = z[i] + 0.5 * hs * k2[i]
        _rhs(t + 0.5 * hs, t_b, zt, shift, ybuf, k3, d)
        for i in range(ny):
            zt[i] = z[i] + hs * k3[i]
        _rhs(t_new, t_b, zt, shift, ybuf, k4, d)
        for i in range(ny):
            zn[i] = z[i] + (hs / 6.0) * (f[i] + 2.0 * (k2[i] + k3[i]) + k4[i])
        counts[0] += 3
        if not _finite(zn):
            return -2, t, h, k_out
        _rhs(t_new, t_b, zn, shift, ybuf, fn, d)
        counts[0] += 1
        if not _finite(fn):
            return -2, t, h, k_out
        counts[1] += 1

        # output: cubic Hermite on (z, f) -> (zn, fn)
        tol = _end_tol(t_new)
        while k_out < grid.size and grid[k_out] <= t_new + tol:
            tk = grid[k_out]
            if tk >= t_new - tol:
                _put_end(Y, k_out, zn, shift)
            else:
                s = (tk - t) / hs
                h00 = (1.0 + 2.0 * s) * (1.0 - s) ** 2
                h10 = s * (1.0 - s) ** 2
                h01 = s * s * (3.0 - 2.0 * s)
                h11 = s * s * (s - 1.0)
                for i in range(ny):
                    Y[k_out, i] = (h00 * z[i] + h10 * hs * f[i] + h01 * zn[i] + h11 * hs * fn[i]
                                   + shift[i])
            _normalise_row(Y, k_out, p_idx)
            k_out += 1

        for i in range(ny):
            z[i] = zn[i]
            f[i] = fn[i]
        _project(z, shift, p_idx, f, True)
        t = t_new
    return 0, t_b, h, k_out


# ============================================================================
# DOP853
# ============================================================================

@_jit
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


@_jit
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


@_jit
def dop853_segment(t_a, t_b, z, shift, d, rtol, atol, dt_or_h0, h_max, grid, Y, k_out, max_steps,
                   p_idx, n_motion, counts, work):
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

    _project(z, shift, p_idx, f, False)
    _rhs(t_a, t_b, z, shift, ybuf, f, d)
    counts[0] += 1
    if not _finite(f):
        return -2, t_a, dt_or_h0, k_out
    if dt_or_h0 > 0.0:
        h_abs = dt_or_h0
    else:
        h_abs = _initial_step(t_a, t_b, z, f, shift, d, rtol, atol, h_max, 7, ybuf, zt, ft, counts)
    t = t_a
    steps = 0
    while t < t_b:
        if steps >= max_steps:
            return 1, t, h_abs, k_out
        min_step = 10.0 * _EPS * abs(t)
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
                _rhs(t + _DC[s] * h, t_b, zt, shift, ybuf, K[s], d)
            _combine(zn, z, h, K, _DB, 12)
            _rhs(t_new, t_b, zn, shift, ybuf, K[12], d)
            counts[0] += 12
            if not (_finite(zn) and _finite(K[12])):
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

        # output: 7th-order dense output, its 3 extra stages only if needed
        tol = _end_tol(t_new)
        have_dense = False
        while k_out < grid.size and grid[k_out] <= t_new + tol:
            tk = grid[k_out]
            if tk >= t_new - tol:
                _put_end(Y, k_out, zn, shift)
            else:
                if not have_dense:
                    for s in range(13, 16):
                        _combine(zt, z, h, K, _DA[s], s)
                        _rhs(t + _DC[s] * h, t_b, zt, shift, ybuf, K[s], d)
                    counts[0] += 3
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
                    have_dense = True
                x = (tk - t) / h
                for i in range(ny):
                    acc = 0.0
                    for m in range(7):           # F[6], F[5], …, F[0]; ×x, ×(1−x) alternately
                        acc += F[6 - m, i]
                        if m % 2 == 0:
                            acc *= x
                        else:
                            acc *= 1.0 - x
                    Y[k_out, i] = acc + z[i] + shift[i]
            _normalise_row(Y, k_out, p_idx)
            k_out += 1

        for i in range(ny):
            z[i] = zn[i]
            f[i] = K[12, i]
        _project(z, shift, p_idx, f, True)
        t = t_new
    return 0, t_b, h_abs, k_out


# ============================================================================
# Radau IIA
# ============================================================================

@_jit
def _jacobian(t, t_b, z, f0, shift, d, JT, n_motion, zj, ybuf, fj, counts):
    """Forward differences over z[:n_motion] at (t, z), f0 = f(t, z):
    JT[j, i] = ∂f_i/∂z_j, steps sqrt(eps)·max(1, |z_j + shift_j|); rows
    n_motion… are zero. n_motion evaluations."""
    ny = z.size
    for i in range(ny):
        zj[i] = z[i]
    for j in range(n_motion):
        zj[j] = z[j] + _SQRT_EPS * max(1.0, abs(z[j] + shift[j]))
        delta = zj[j] - z[j]
        _rhs(t, t_b, zj, shift, ybuf, fj, d)
        for i in range(ny):
            JT[j, i] = (fj[i] - f0[i]) / delta
        zj[j] = z[j]
    for j in range(n_motion, ny):
        for i in range(ny):
            JT[j, i] = 0.0
    counts[0] += n_motion
    counts[3] += 1


@_jit
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


@_jit
def _rms3(dW, scale):
    """sqrt(mean((dW / scale)²)) over the (3, ny) array dW."""
    ny = scale.size
    s = 0.0
    for r in range(3):
        for i in range(ny):
            s += (dW[r, i] / scale[i]) ** 2
    return math.sqrt(s / (3 * ny))


@_jit
def _solve_real(lapack, trans, nn, one, LU, piv, b, info):
    """b ← (LU)⁻¹ b with the real factors of :func:`_factor` (in place)."""
    lapack[1](trans.ctypes, nn.ctypes, one.ctypes, LU.ctypes, nn.ctypes, piv.ctypes, b.ctypes,
              nn.ctypes, info.ctypes)


@_jit
def _solve_complex(lapack, trans, nn, one, LU, piv, b, info):
    """b ← (LU)⁻¹ b with the complex factors of :func:`_factor` (in place)."""
    lapack[3](trans.ctypes, nn.ctypes, one.ctypes, LU.ctypes, nn.ctypes, piv.ctypes, b.ctypes,
              nn.ctypes, info.ctypes)


@_jit
def _newton(t, t_b, z, h, Z0, scale, tol, shift, d, LUr, pivr, LUc, pivc, lapack, Z, W, F, dW,
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
            _rhs(t + h * _RC[r], t_b, zt, shift, ybuf, F[r], d)
        counts[0] += 3
        if not (_finite(F[0]) and _finite(F[1]) and _finite(F[2])):
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


@_jit
def _rms(x, scale):
    """sqrt(mean((x / scale)²)) over the 1-D array x."""
    s = 0.0
    for i in range(x.size):
        s += (x[i] / scale[i]) ** 2
    return math.sqrt(s / x.size)


@_jit
def _predict_factor(h_abs, h_abs_old, err, err_old, has_old):
    """Predictive step-size factor (Gustafsson; Hairer & Wanner II, IV.8)."""
    if not has_old or err == 0.0:
        mult = 1.0
    else:
        mult = h_abs / h_abs_old * (err_old / err) ** 0.25
    if err == 0.0:
        return math.inf
    return min(1.0, mult) * err ** -0.25


@_jit
def _radau_core(t_a, t_b, z, shift, d, rtol, atol, dt_or_h0, h_max, grid, Y, k_out, max_steps,
                p_idx, n_motion, counts, work, keep_lo, scipy_like):
    """Radau IIA (order 5) over [t_a, t_b]; see :func:`radau_segment`.

    keep_lo : float
        h is kept (and the LU factors with it) when the proposed ratio
        h_new/h lies in [keep_lo, 1.2) and the Jacobian is not recomputed:
        1.0 as Hairer's quot1 (:func:`radau_segment`); SciPy's ``Radau`` in
        effect uses −inf (h kept for every ratio below 1.2).
    scipy_like : bool
        For verification only: SciPy ``Radau``'s other choices where they
        differ from this module's — the LU factors reused after a step was
        cut at t_b (h changed), no extra error evaluation on a segment's
        first step, no bounds on the accepted step's ratio nor on the error
        remembered by the predictive controller (Hairer: ≥ 0.2, ≥ 1e-2).
        With keep_lo = −inf it takes SciPy's steps.
    """
    JT, LUr, pivr, LUc, pivc, Q, z_sol, st, lapack = work
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
        _project(z, shift, p_idx, f, False)
        st[_S_HAS_SOL] = 0.0
        st[_S_HAS_OLD] = 0.0
        st[_S_H_LU] = 0.0
    _rhs(t_a, t_b, z, shift, ybuf, f, d)
    counts[0] += 1
    if not _finite(f):
        return -2, t_a, dt_or_h0, k_out
    if resume:
        current_jac = st[_S_CURRENT_JAC] == 1.0
    else:
        _jacobian(t_a, t_b, z, f, shift, d, JT, n_motion, zj, ybuf, fj, counts)
        current_jac = True
    h_lu = st[_S_H_LU]                       # 0: no valid LU factors
    if dt_or_h0 > 0.0:
        h_abs = dt_or_h0
    else:
        h_abs = _initial_step(t_a, t_b, z, f, shift, d, rtol, atol, h_max, 3, ybuf, zt, fj,
                              counts)
    newton_tol = max(10.0 * _EPS / rtol, min(0.03, math.sqrt(rtol)))
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
        min_step = 10.0 * _EPS * abs(t)
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
                                                      d, LUr, pivr, LUc, pivc, lapack, Z, W, F,
                                                      dW, ybuf, zt, err, bc, nn, one, info, trans,
                                                      counts)
                if converged or current_jac:
                    break
                _jacobian(t, t_b, z, f, shift, d, JT, n_motion, zj, ybuf, fj, counts)
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
                _rhs(t, t_b, zt, shift, ybuf, fj, d)
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
        _rhs(t_new, t_b, zn, shift, ybuf, fn, d)
        counts[0] += 1
        if not (_finite(zn) and _finite(fn)):
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
        tol = _end_tol(t_new)
        while k_out < grid.size and grid[k_out] <= t_new + tol:
            tk = grid[k_out]
            if tk >= t_new - tol:
                _put_end(Y, k_out, zn, shift)
            else:
                x = (tk - t) / h
                x2 = x * x
                x3 = x2 * x
                for i in range(ny):
                    Y[k_out, i] = (Q[0, i] * x + Q[1, i] * x2 + Q[2, i] * x3 + z[i]) + shift[i]
            _normalise_row(Y, k_out, p_idx)
            k_out += 1

        for i in range(ny):
            z[i] = zn[i]
            f[i] = fn[i]
        t = t_new
        if recompute_jac:
            _jacobian(t, t_b, z, f, shift, d, JT, n_motion, zj, ybuf, fj, counts)
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


@_jit
def radau_segment(t_a, t_b, z, shift, d, rtol, atol, dt_or_h0, h_max, grid, Y, k_out, max_steps,
                  p_idx, n_motion, counts, work):
    """Radau IIA of order 5 over [t_a, t_b] (see the module docstring).

    work : tuple from :func:`radau_workspace` (ny). A call resumes the
    previous one (same Jacobian, LU factors, dense output and controller
    history; no projection) when that one paused (status 1) at t == t_a;
    otherwise it starts afresh: projects z, evaluates f and the Jacobian at
    (t_a, z) (1 + n_motion evaluations).
    """
    return _radau_core(t_a, t_b, z, shift, d, rtol, atol, dt_or_h0, h_max, grid, Y, k_out,
                       max_steps, p_idx, n_motion, counts, work, _KEEP_H_LOW, False)


# ============================================================================
# Cache freshness
# ============================================================================

def _kernel_stamp() -> str:
    """Hash of the sources of ``evaluate``'s module and of the modules of its
    package it uses, transitively (through compiled functions or modules it
    holds as globals): what the compiled steppers contain besides this file."""
    kernel_module = evaluate.py_func.__module__
    package = kernel_module.rpartition(".")[0] + "."
    seen = set()
    todo = [kernel_module]
    while todo:
        name = todo.pop()
        if name in seen or name == __name__ or not (name == kernel_module
                                                    or name.startswith(package)):
            continue
        seen.add(name)
        module = sys.modules.get(name)
        for value in list(vars(module).values()) if module is not None else ():
            if isinstance(value, Dispatcher):
                todo.append(value.py_func.__module__)
            elif isinstance(value, types.ModuleType):
                todo.append(value.__name__)
    digest = hashlib.sha256()
    for name in sorted(seen):
        path = getattr(sys.modules.get(name), "__file__", None)
        if path:
            digest.update(name.encode())
            with open(path, "rb") as fh:
                digest.update(fh.read())
    return digest.hexdigest()


def _refresh_cache() -> None:
    """Flush this module's numba cache when the kernel's sources changed.

    Numba checks only a cached function's own source file, so after an edit
    of the kernel the cached steppers would still run the old kernel. The
    stamp lives beside the cache files (``steppers.kernel-stamp``).
    """
    dispatchers = [v for v in globals().values()
                   if isinstance(v, Dispatcher) and v.py_func.__module__ == __name__]
    cache_dir = dispatchers[0].stats.cache_path if dispatchers else None
    if not cache_dir:
        return
    stamp_file = os.path.join(cache_dir, "steppers.kernel-stamp")
    stamp = _kernel_stamp()
    try:
        with open(stamp_file) as fh:
            if fh.read() == stamp:
                return
    except OSError:
        pass
    for disp in dispatchers:
        disp._cache.flush()
    try:
        os.makedirs(cache_dir, exist_ok=True)
        with open(stamp_file, "w") as fh:
            fh.write(stamp)
    except OSError:
        pass


_refresh_cache()

"""Compiled time steppers: one segment of y' = f(t, y) entirely in numba.

SciPy's ``solve_ivp`` steppers spend hundreds of µs of Python per step; the
steppers here run a whole segment [t_a, t_b] (or a chunk of it) inside one
nopython call, calling the compiled right-hand side through its pointer,
so that a step costs a few µs beyond its right-hand-side evaluations.
The steppers import NumPy, numba and SciPy's public LAPACK entry points
(``scipy.linalg.cython_lapack``), and of flexbed only
:mod:`flexbed.dynamics.jitcache`: the right-hand side comes in as an
argument.

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
    an output time strictly inside). The coefficients are Hairer's, the
    values SciPy's ``DOP853`` uses (:mod:`.dop853_coefficients`).
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
    module's checks, for fewer rejections). The constants T, T⁻¹, C, E,
    P, μ are the values SciPy's ``Radau`` uses (:mod:`.radau_coefficients`).

Interface
---------
Every stepper is called once per segment (or per chunk of one)::

    status, t, h, k_out = <method>_segment(t_a, t_b, z, shift, kernel, rtol, atol,
                                           dt_or_h0, h_max, grid, Y, k_out,
                                           max_steps, p_idx, n_motion,
                                           counts, work)

and integrates the deviation z = y − shift (the right-hand side receives
y = z + shift; shift is constant):

t_a, t_b : float [s]
    The segment, t_b > t_a (t_b ≤ t_a: nothing to do, status 0).
z : (ny,) float64
    State at t_a; overwritten with the state reached.
shift : (ny,) float64
    Constant offset, y = z + shift.
kernel : tuple (function, F, I)
    The compiled right-hand side and the scene's packed storage
    (:attr:`flexbed.dynamics.system.System.kernel`): the steppers call
    ``function(t, seg_end, y, dy, F, I)`` through its pointer, so they are
    compiled without the right-hand side's code and do not depend on it.
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
    Y[k] are normalised (:func:`.common.rows_inside` and
    :func:`.common.write_rows`, shared by the three). Grid times at or
    before t_a must already be written.
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

Modules
-------
:mod:`.common` (what the steppers share: the right-hand side's call,
projection, the output rows, the initial step), :mod:`.rk4`,
:mod:`.dop853` with :mod:`.dop853_coefficients` (its tableau),
:mod:`.radau` with :mod:`.radau_coefficients` (its constants) and
:mod:`.lapack` (its LAPACK entry points). The coefficient modules are
read-only data checked when imported; they import NumPy only, never
SciPy's private modules. The linear fast path's compiled loops (the
recursion over its pieces, the φ-functions, the error estimate's defect)
are in a room of their own, :mod:`flexbed.dynamics.linear`, which this
one does not import.
"""

from __future__ import annotations

from ..jitcache import refresh as _refresh

_refresh()   # before any compiled function is loaded (flexbed.dynamics.jitcache)

from .dop853 import dop853_segment
from .radau import radau_reset, radau_segment, radau_workspace
from .rk4 import rk4_segment

__all__ = ["rk4_segment", "dop853_segment", "radau_segment", "radau_workspace", "radau_reset",
           "N_COUNTS", "STATUS"]

N_COUNTS = 5
STATUS = {0: "reached t_b", 1: "paused (max_steps)", -1: "step size too small",
          -2: "non-finite state"}

"""Linear stability of the explicit methods and the stiffness check.

Stiff scenes and the explicit methods: before ``rk4`` or ``dop853``
starts, the eigenvalues λ of the Jacobian of the motion (the q and v
blocks of ``System.rhs``, by forward differences at t = 0 and y0; about
ny right-hand sides) give the longest step h for which every hλ lies in
the method's stability region |R(hλ)| ≤ 1, R being the method's stability
polynomial: |hλ| up to 2.79 along the negative real axis and 2.83 along
the imaginary axis for RK4, 6.39 and 5.96 for DOP853 (a growing mode's
real part is set to zero first: its growth is physics, not instability).

- ``rk4`` stops before its first step when ``dt`` exceeds that bound: a
  "stiff scene" pointing to the implicit methods when the stable step
  would take more than ``Settings.stiff_steps`` steps over [0, t_end],
  otherwise "rk4 step too long", asking for a shorter ``dt``.
- ``dop853`` stops before its first step when the bound forces more than
  ``Settings.stiff_steps`` steps (its step control would find the bound by
  itself, at that cost).

The run comes back incomplete (no step taken, the start state only) with
one line, e.g. ``stiff scene: the fastest rate 3.6e+05 1/s limits dop853
to steps below 1.8e-05 s (112483 steps for 2 s, more than stiff_steps =
100000); use integrator = "auto", "radau" or "bdf"`` (a flexible bed with 20
modes and β = 0.01); ``flexbed simulate`` prints it and exits with 1. The
estimate is the linearisation at the start: a hardening mount that
stiffens later is not seen, and a run that still goes unstable stops at
the first non-finite state (below). ``stiff_steps = 0`` turns the check
off. ``adams`` (LSODA switches to BDF by itself), ``bdf`` and ``radau``
are not checked.

``auto`` (the default) uses the same linearisation to choose: radau where
dop853 would be stability-bound, else dop853
(:func:`flexbed.dynamics.method_choice.auto_method`); it never refuses a
run.

The stable step is found cheaply (:func:`stable_step`): only the
eigenvalues that can set it are searched, by vectorised bracketing.

Large scenes (more than :data:`DENSE_EIG_LIMIT` coordinates and
velocities): a dense eigen-solution grows as the cube of the size (0.9 s of
a 1.2 s run with 128 pieces of equipment), so there the eigenvalues of
largest modulus alone are found, :data:`ARNOLDI_COUNT` of them by
implicitly restarted Arnoldi (ARPACK, :func:`scipy.sparse.linalg.eigs`) on
the block-sparse first-order operator ``[[0, I], [M⁻¹Kq, M⁻¹Kv]]`` of the
bodies' coordinates (:func:`flexbed.dynamics.block_linearisation.linearised`: central
differences by colour classes of the mount graph, O(N)). The largest
modulus is the dense solve's to the Arnoldi tolerance (1e-8 relative); the
stable step is exact when every eigenvalue within (lo/hi) of that modulus
is among those found, and otherwise within [lo, hi]/max|λ| of it
(:data:`_RADIUS_BOUNDS`, e.g. 5.8/max|λ| … 7.0/max|λ| for dop853).
"""

from __future__ import annotations

import math

import numpy as np
import scipy.sparse as sp
from scipy.sparse.linalg import ArpackNoConvergence, eigs

from .block_linearisation import block_inverse, linearised
from .jacobian import mount_graph
from .steppers.dop853_coefficients import DOP853, N_STAGES
from .system import System

__all__ = ["motion_eigenvalues", "largest_eigenvalues", "stable_step", "stable_step_at_start",
           "stiff_message", "jacobian_columns", "segments", "rk4_steps"]

_SQRT_EPS = math.sqrt(np.finfo(float).eps)

#: above this many coordinates and velocities (nq + nv) the eigenvalues of
#: largest modulus are found by Arnoldi iterations (see the module docstring)
DENSE_EIG_LIMIT = 400
#: how many eigenvalues of largest modulus the Arnoldi iterations find
ARNOLDI_COUNT = 24
#: central-difference step of the sparse linearisation [m, rad, m/s, rad/s]
_LIN_STEP = 1e-6


def _stability_polynomial(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Coefficients γ_0 … γ_s (rising powers) of the stability polynomial
    R(z) = 1 + z bᵀ (I − z a)⁻¹ 𝟙 of an explicit Runge–Kutta method
    (a : (s, s) strictly lower triangular, b : (s,))."""
    g = [1.0]
    v = np.ones(len(b))
    for _ in range(len(b)):
        g.append(float(b @ v))
        v = a @ v
    return np.array(g)


# R(z) of the explicit methods, highest power first (for np.polyval);
# DOP853's from its 12 stages (flexbed.dynamics.steppers.dop853_coefficients)
_STABILITY = {
    "rk4": np.array([1.0 / math.factorial(k) for k in range(4, -1, -1)]),
    "dop853": _stability_polynomial(DOP853.A[:N_STAGES, :N_STAGES], DOP853.B)[::-1].copy(),
}

#: Bounds [lo, hi] of the radius |hλ| at which each method's |R(hλ)| first
#: exceeds 1 along any direction of the left half-plane (measured by
#: :func:`stable_step` on 20,001 directions: rk4 2.6156 … 2.9601, dop853
#: 5.9604 … 6.7928; with a margin; a test checks them). An eigenvalue with
#: |λ| below (lo/hi) max|λ| cannot set the stable step.
_RADIUS_BOUNDS = {"rk4": (2.5, 3.1), "dop853": (5.8, 7.0)}


def jacobian_columns(fun, t: float, z: np.ndarray, n: int, size: np.ndarray) -> np.ndarray:
    """Forward differences of fun(t, z) (→ (ny,)) over z[:n].

    size : (ny,) magnitudes that set each step, sqrt(eps)·max(1, size_j).
    Returns (ny, n).
    """
    z = np.array(z, dtype=float)
    f0 = fun(t, z)
    jac = np.empty((f0.size, n))
    for j in range(n):
        zj = z[j]
        z[j] = zj + _SQRT_EPS * max(1.0, abs(size[j]))
        jac[:, j] = (fun(t, z) - f0) / (z[j] - zj)
        z[j] = zj
    return jac


def motion_eigenvalues(system: System, y: np.ndarray, t: float = 0.0,
                       seg_end: float = math.inf, sparse: bool | None = None) -> np.ndarray:
    """Eigenvalues of the Jacobian of the motion at (t, y).

    Forward differences of the right-hand side over the coordinates and
    velocities (q, v), steps of sqrt(eps)·max(1, |y_j|) (the states of
    :func:`jacobian_columns`, evaluated in one compiled call); the energy
    quadratures are left out (nothing depends on them); an elastomer mount's
    Maxwell states are in (:mod:`flexbed.dynamics.maxwell_terms`). Costs
    nq + nv + nz + 1 right-hand sides (counted in ``system.nfev``).

    Parameters
    ----------
    system : System
    y : (ny,) array
        State (see :mod:`flexbed.dynamics.layout`).
    t : float
        Time [s].
    seg_end : float
        End of the segment [s] whose one-sided limits the base's inputs
        give (inf: right-continuous), as for the right-hand side.
    sparse : bool, optional
        Only the :data:`ARNOLDI_COUNT` eigenvalues of largest modulus, by
        :func:`largest_eigenvalues`; default: above :data:`DENSE_EIG_LIMIT`.

    Returns
    -------
    (nq + nv + nz,) complex array [1/s] (sparse: (k,), k ≤ ARNOLDI_COUNT); all-NaN
    if the right-hand side is not finite there.
    """
    lay = system.layout
    n = lay.n_motion               # the Maxwell terms' states too: their rates 1/τ_i
    y = np.asarray(y, dtype=float)
    if sparse is None:
        sparse = n > DENSE_EIG_LIMIT
    if sparse:
        return largest_eigenvalues(system, y, t, seg_end)
    # the states of jacobian_columns, evaluated in one compiled call
    Y = np.tile(y, (n + 1, 1))
    j = np.arange(n)
    Y[j + 1, j] = y[:n] + _SQRT_EPS * np.maximum(1.0, np.abs(y[:n]))
    F, _ = system.rhs_batch(np.full(n + 1, float(t)), Y, seg_end=seg_end)
    jac = ((F[1:] - F[0]) / (Y[j + 1, j] - y[:n])[:, None]).T[:n]
    if not np.all(np.isfinite(jac)):
        return np.full(n, np.nan + 0j)
    return np.linalg.eigvals(jac)


def largest_eigenvalues(system: System, y: np.ndarray, t: float = 0.0,
                        seg_end: float = math.inf, count: int = ARNOLDI_COUNT) -> np.ndarray:
    """The ``count`` eigenvalues of largest modulus of the motion's
    linearisation at (t, y) [1/s] (complex, (k,)), by Arnoldi iterations on
    the sparse operator of the module docstring; all-NaN if the right-hand
    side is not finite there. The free base's own (three zero eigenvalues
    and its coupling) and the Euler parameters' norm (zero eigenvalues)
    are left out: they cannot set a step. The Maxwell terms' states
    (:mod:`flexbed.dynamics.maxwell_terms`) are not in the operator: their
    relaxation rates −1/τ_i (the diagonal of their block) are appended."""
    lam = _largest_of_bodies(system, y, t, seg_end, count)
    rates = system.data.mx_k[:, 1]
    return np.concatenate([lam, -np.unique(rates).astype(complex)]) if rates.size else lam


def _largest_of_bodies(system, y, t, seg_end, count):
    """:func:`largest_eigenvalues` of the bodies' coordinates alone."""
    y = np.asarray(y, dtype=float)
    g = mount_graph(system, True)
    steps = np.full(g.n, _LIN_STEP)
    lin = linearised(system, y, steps, steps, t=t, seg_end=seg_end)
    n = g.n
    if n == 0:
        return np.zeros(0, dtype=complex)
    if not (np.all(np.isfinite(lin.Kq.data)) and np.all(np.isfinite(lin.Kv.data))):
        return np.full(1, np.nan + 0j)
    Minv = block_inverse(system, lin.M)
    S = sp.bmat([[None, sp.identity(n)], [Minv @ lin.Kq, Minv @ lin.Kv]], format="csr")
    k = min(count, 2 * n - 2)
    if k < 1:
        return np.linalg.eigvals(S.toarray())
    try:
        lam = eigs(S, k=k, which="LM", tol=1e-8, maxiter=50 * S.shape[0],
                   return_eigenvectors=False, v0=np.cos(np.arange(S.shape[0]) + 0.5))
    except ArpackNoConvergence as exc:
        lam = exc.eigenvalues
        if lam.size == 0:
            lam = np.linalg.eigvals(S.toarray())
    return np.asarray(lam, dtype=complex)


def stable_step(method: str, eigenvalues: np.ndarray) -> tuple[float, float]:
    """Longest step of an explicit method that keeps every hλ stable.

    For each eigenvalue λ (a growing one's real part set to zero: its
    growth is physics), the step h is bounded by the first radius along
    λ's direction where |R(hλ)| exceeds 1 (R: the method's stability
    polynomial). That radius lies within the method's
    :data:`_RADIUS_BOUNDS` [lo, hi] in every direction, so

    - only the eigenvalues with |λ| ≥ (lo/hi) max|λ| can set the bound
      (any other gives a longer step than the largest one does);
    - for those, the first unstable point of the grid 0.01, 0.02, … within
      [lo, hi] brackets the radius (every radius below lo is stable), and
      five searches on 256 equal sub-points narrow the bracket to 1e-14
      (the same answer as 40 bisections, in 6 vectorised evaluations).

    Parameters
    ----------
    method : "rk4" or "dop853"
    eigenvalues : (n,) complex array [1/s]

    Returns
    -------
    h : float [s]
        The longest stable step (inf if no eigenvalue limits it).
    rate : float [1/s]
        |λ| of the eigenvalue that sets h (0 if none).
    """
    poly = _STABILITY[method]
    lam = np.asarray(eigenvalues, dtype=complex).ravel()
    lam = lam[np.isfinite(lam)]
    lam = np.minimum(lam.real, 0.0) + 1j * np.abs(lam.imag)
    mag = np.abs(lam)
    lam, mag = lam[mag > 0], mag[mag > 0]
    if lam.size == 0:
        return math.inf, 0.0
    r_lo, r_hi = _RADIUS_BOUNDS[method]
    can_limit = mag >= (1.0 - 1e-12) * (r_lo / r_hi) * mag.max()
    lam, mag = lam[can_limit], mag[can_limit]
    d = (lam / mag)[:, None]                               # directions, left half-plane

    def first_unstable(r):
        """Index of the first radius of each row of r (n, k) where |R| > 1
        (k if none)."""
        bad = np.abs(np.polyval(poly, r * d)) > 1.0 + 1e-12
        return np.where(bad.any(axis=1), bad.argmax(axis=1), r.shape[1])

    grid = 0.01 * np.arange(math.floor(r_lo / 0.01), math.ceil(r_hi / 0.01) + 1)
    k = first_unstable(np.broadcast_to(grid, (d.size, grid.size)))
    k = np.minimum(k, grid.size - 1)
    lo = grid[np.maximum(k - 1, 0)]
    hi = grid[k]
    frac = np.arange(1, 257) / 256.0
    for _ in range(5):
        r = lo[:, None] + (hi - lo)[:, None] * frac         # (n, 256), the last one is hi
        j = first_unstable(r)
        j = np.minimum(j, frac.size - 1)
        rows = np.arange(r.shape[0])
        hi = r[rows, j]
        lo = np.where(j > 0, r[rows, np.maximum(j - 1, 0)], lo)
    h = lo / mag
    i = int(np.argmin(h))
    return float(h[i]), float(mag[i])


def segments(system: System, t_end: float) -> list[tuple[float, float]]:
    """The segments [t_a, t_b] between breakpoints that the integrators run through."""
    bounds = [b for b in system.breakpoints if 0.0 < b < t_end] + [t_end]
    return list(zip([0.0] + bounds[:-1], bounds))


def rk4_steps(t_a: float, t_b: float, dt: float) -> int:
    """Number of equal rk4 steps on [t_a, t_b] (steps of at most dt)."""
    return max(1, int(math.ceil((t_b - t_a) / dt - 1e-9)))


def stable_step_at_start(system: System, y0: np.ndarray, t_end: float,
                         method: str) -> tuple[float, float]:
    """:func:`stable_step` of ``method`` for the linearisation at (0, y0),
    the inputs evaluated as on the first segment: (h [s], rate [1/s])."""
    return stable_step(method, motion_eigenvalues(system, y0,
                                                  seg_end=segments(system, t_end)[0][1]))


def stiff_message(system: System, y0: np.ndarray, settings) -> str | None:
    """Why an explicit method should not run this scene, or None.

    ``rk4``: its step exceeds the stable step of the linearisation at
    (0, y0); ``dop853``: the stable step forces more than
    ``settings.stiff_steps`` steps over [0, t_end]. Other methods, or
    ``stiff_steps = 0``: None without any evaluation.

    Parameters
    ----------
    system : System
    y0 : (ny,) array
        Start state.
    settings : Settings

    Returns
    -------
    str or None
        One line: the limiting rate [1/s], the stable step [s] and what to use.
    """
    method = settings.method
    if method not in _STABILITY or settings.stiff_steps == 0:
        return None
    segs = segments(system, settings.t_end)
    h, rate = stable_step_at_start(system, y0, settings.t_end, method)
    if not math.isfinite(h):
        return None
    use = 'use integrator = "auto", "radau" or "bdf"'
    limit = f"the fastest rate {rate:.1e} 1/s limits {method} to steps below {h:.1e} s"
    steps = math.ceil(settings.t_end / h)
    stiff = steps > settings.stiff_steps
    if method == "rk4":
        h_rk4 = max((b - a) / rk4_steps(a, b, settings.dt) for a, b in segs)
        if h_rk4 <= h:
            return None
        if stiff:
            return f"stiff scene: {limit} (dt = {settings.dt:g} s); {use}"
        return f"rk4 step too long: {limit} (dt = {settings.dt:g} s); use dt below {h:.1e} s"
    if not stiff:
        return None
    return (f"stiff scene: {limit} ({steps} steps for {settings.t_end:g} s, more than "
            f"stiff_steps = {settings.stiff_steps}); {use}")


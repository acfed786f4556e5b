"""The linear fast path: motion linearised about the static equilibrium and
propagated exactly, with an estimate of its error against the nonlinear model.

The model itself (coordinates, linearisation, the base's inputs) is in
:mod:`flexbed.dynamics.linear_model`.

Exact propagation
-----------------
Time is cut at the output samples and at every knot of the inputs (curve
samples, pulse corners, sinusoid window ends; analytic sinusoids also every
0.2/ω, see below). On each piece ``[t_k, t_k + h]`` each input is a
polynomial of degree ≤ 5 in ``σ = (t − t_k)/h`` — exactly so for the
scene's piecewise inputs (cubic spline loads, their first and second
integrals for drives: degree 5; pulses) — whose coefficients come from
six samples at Chebyshev points inside the piece. The state and the
inputs' σ-derivatives together obey a constant linear system,

    d/dσ [z; w] = [[h A, h G E₀], [0, I ⊗ S]] [z; w],

with ``S`` the shift (``w_m' = w_{m+1}``), so one matrix exponential per
distinct piece length gives ``z(t_k + h) = Φ z(t_k) + Ψ w_k`` without any
truncation error (Van Loan's block method). An analytic sinusoid (no
``sample``) is not a polynomial; pieces of at most 0.2/ω keep its degree-5
interpolation error below 1e-10 of its amplitude.

Error estimate against the nonlinear model
------------------------------------------
Along the linear solution the nonlinear model leaves the defect
``d(t) = f(z(t), t) − (A z + b0 + B Δu)``, evaluated at every output
sample (one right-hand side each). The nonlinear solution differs from the
linear one by ``e`` with ``ė = A e + d + O(e²)``; ``e`` is propagated
exactly with ``d`` piecewise linear between samples. The largest error it
implies in the position of a point that matters (the centres of mass of
bodies 2… and both ends of every mount on them, rotations and modes
included with their lever arms) is the reported estimate [m]; it is a
first-order
(Newton) estimate, reliable while ``e`` is small against the motion, which
:attr:`LinearRun.estimate_reliable` checks.

The energy quadratures of the state (works of mounts, loads, drive and
structural damping) are integrated from the powers at the samples by the
trapezoidal rule.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from scipy.linalg import expm

from .integrate import Run, Settings, Stats, output_grid
from .linear_model import Coordinates, Linearisation, linearise
from .system import System

__all__ = ["Coordinates", "Linearisation", "LinearRun", "linearise", "propagate",
           "run_linear", "estimate_error", "unstable_rate"]

_DEG = 5                                   # degree of the inputs' local polynomials
_NODES = 0.5 - 0.5 * np.cos((2 * np.arange(_DEG + 1) + 1) * np.pi / (2 * (_DEG + 1)))
_VINV = np.linalg.inv(_NODES[:, None] ** np.arange(_DEG + 1)[None, :])
_FACT = np.array([math.factorial(m) for m in range(_DEG + 1)], dtype=float)


def _pieces(lin: Linearisation, grid: np.ndarray) -> np.ndarray:
    """Piece boundaries: the output grid, the inputs' knots inside it, and
    extra cuts where a channel needs shorter pieces; near-coincident times
    (within 1e-9 of the output spacing) merged."""
    t_end = float(grid[-1])
    cuts = [grid]
    for c in lin.channels:
        kn = c.knots[(c.knots > 0.0) & (c.knots < t_end)]
        cuts.append(kn)
        if math.isfinite(c.max_piece):
            cuts.append(np.arange(0.0, t_end, c.max_piece))
    t = np.unique(np.concatenate(cuts))
    tol = 1e-9 * (float(np.min(np.diff(grid))) if grid.size > 1 else t_end)
    keep = np.concatenate([[True], np.diff(t) > tol])
    t = t[keep]
    # snap back onto the output grid where a knot replaced a grid point
    idx = np.clip(np.searchsorted(t, grid), 0, t.size - 1)
    left = np.clip(idx - 1, 0, t.size - 1)
    pick = np.where(np.abs(t[idx] - grid) <= np.abs(t[left] - grid), idx, left)
    t[pick] = grid
    return t


class _Propagators:
    """Φ and Ψ for each distinct piece length (cached; lengths equal to 1e-12
    relative share one)."""

    def __init__(self, A: np.ndarray, G: np.ndarray, degree: int):
        self.A, self.G, self.deg = A, G, degree
        self.cache: dict[float, tuple[np.ndarray, np.ndarray]] = {}

    def __call__(self, h: float) -> tuple[np.ndarray, np.ndarray]:
        key = float(f"{h:.12e}")
        got = self.cache.get(key)
        if got is None:
            got = self.cache[key] = self._build(h)
        return got

    def _build(self, h: float):
        nz, nu = self.G.shape
        d1 = self.deg + 1
        n = nz + nu * d1
        M = np.zeros((n, n))
        M[:nz, :nz] = h * self.A
        for j in range(nu):
            c0 = nz + j * d1
            M[:nz, c0] = h * self.G[:, j]
            for m in range(self.deg):
                M[c0 + m, c0 + m + 1] = 1.0
        E = expm(M)
        return E[:nz, :nz].copy(), E[:nz, nz:].copy()


def _sweep(Phi_Psi: _Propagators, t: np.ndarray, W: np.ndarray, z0: np.ndarray) -> np.ndarray:
    """z at every piece boundary t (k+1,) from the inputs' σ-derivatives W (k, nw)."""
    h = np.diff(t)
    keys = np.array([float(f"{x:.12e}") for x in h])
    P = np.empty((h.size, z0.size))
    Phis = {}
    for key in np.unique(keys):
        sel = keys == key
        Phi, Psi = Phi_Psi(float(key))
        Phis[key] = Phi
        P[sel] = W[sel] @ Psi.T
    Z = np.empty((t.size, z0.size))
    Z[0] = z = z0
    if len(Phis) == 1:
        Phi = next(iter(Phis.values()))
        for i in range(h.size):
            z = Phi @ z + P[i]
            Z[i + 1] = z
    else:
        for i in range(h.size):
            z = Phis[keys[i]] @ z + P[i]
            Z[i + 1] = z
    return Z


def propagate(lin: Linearisation, z0: np.ndarray, t_end: float,
              output_dt: float) -> tuple[np.ndarray, np.ndarray, int]:
    """Exact solution of the linear model on the output grid.

    Returns
    -------
    t : (k,) [s]; Z : (k, nz) deviations; pieces : int, pieces propagated.
    """
    grid = output_grid(t_end, output_dt)
    t = _pieces(lin, grid)
    h = np.diff(t)
    nu = len(lin.channels)
    G = np.column_stack([lin.B, lin.b0]) if nu else lin.b0[:, None]
    # inputs on each piece: degree-5 fit in σ at Chebyshev points inside it
    if nu:
        ts = t[:-1, None] + h[:, None] * _NODES[None, :]               # (k, 6)
        U = lin.inputs(ts.reshape(-1)).reshape(h.size, _DEG + 1, nu)
        C = np.einsum("mi,kiu->kum", _VINV, U)                          # σ^m coefficients
        Wu = C * _FACT                                                  # σ-derivatives at 0
    else:
        Wu = np.zeros((h.size, 0, _DEG + 1))
    W1 = np.zeros((h.size, 1, _DEG + 1))
    W1[:, 0, 0] = 1.0                                                   # b0: constant 1
    W = np.concatenate([Wu, W1], axis=1).reshape(h.size, -1)
    Z = _sweep(_Propagators(lin.A, G, _DEG), t, W, np.asarray(z0, dtype=float))
    on_grid = np.searchsorted(t, grid)
    return grid, Z[on_grid], int(h.size)


@dataclass
class ErrorEstimate:
    """First-order estimate of the linear model's error against the nonlinear one.

    position : float [m], the largest error |δP| of a point that matters:
    the centres of mass of bodies 2… and both ends of every mount on them
    (so that rotations and, on a flexible bed, the modes count with their
    lever arms); rotation : float [rad], the largest rotation error;
    motion : float [m], the largest displacement of those points in the
    linear solution from the equilibrium; e : (k, nz);
    reliable : bool, ``position <= 0.1 × motion`` (or both tiny);
    evaluations : right-hand sides it took.
    """

    position: float
    rotation: float
    motion: float
    e: np.ndarray
    reliable: bool
    evaluations: int
    powers: np.ndarray = field(repr=False, default=None)


def _point_map(system: System, coords: Coordinates) -> np.ndarray:
    """(P, 3, nz) first-order map from the deviations z to the inertial
    displacements of every point that matters: the centres of mass of
    bodies 2… and both ends of every mount on them,
    δP = δr + A_eq (δθ × (s̄ + Φ_e a_eq) + Φ_e δa)."""
    from .rotation import A as rotation_matrix

    lay = system.layout
    rows = []
    where = {b: k for k, b in enumerate(lay.rigid)}
    modal_at, offset = {}, 0
    for body, n in lay.modal:
        modal_at[body] = coords.a_index[offset:offset + n]
        offset += n
    A_eq = rotation_matrix(coords.p_eq) if coords.n_rigid else np.zeros((0, 3, 3))
    end_phi = np.asarray(system.data.end_phi)
    points = [(b, np.zeros(3), None) for b in lay.rigid]
    points += [(int(b), np.asarray(s, dtype=float), e)
               for e, (b, s) in enumerate(zip(system.end_body, system.S)) if int(b) in where]
    for body, s, end in points:
        k = where[body]
        if end is not None and body in modal_at:      # the lever arm includes the sag
            idx = modal_at[body]
            phi = end_phi[end][:, :idx.size]
            s = s + phi @ coords.y_eq[coords.y_a[idx - coords.a_index[0]]]
        T = np.zeros((3, coords.nz))
        T[:, coords.r_index[k]] = np.eye(3)
        # δθ × s̄ = −s̃ δθ, turned into the inertial frame
        s_tilde = np.array([[0.0, -s[2], s[1]], [s[2], 0.0, -s[0]], [-s[1], s[0], 0.0]])
        T[:, coords.th_index[k]] = -A_eq[k] @ s_tilde
        if end is not None and body in modal_at:
            T[:, idx] = A_eq[k] @ phi
        rows.append(T)
    return np.array(rows) if rows else np.zeros((0, 3, coords.nz))


def _largest_displacement(Z: np.ndarray, coords: Coordinates, to_points: np.ndarray) -> float:
    """Largest |δP| [m] over the samples (k, nz) and the points of :func:`_point_map`."""
    if not to_points.shape[0]:
        return 0.0
    d = np.einsum("pij,kj->kpi", to_points, Z)
    return float(np.sqrt(np.max(np.sum(d * d, axis=2))))


def estimate_error(system: System, lin: Linearisation, t: np.ndarray,
                   Z: np.ndarray) -> ErrorEstimate:
    """Defect of the linear solution in the nonlinear equations, propagated
    (see the module docstring). Also returns the powers at the samples
    (k, 4) [W] for the energy quadratures."""
    coords = lin.coords
    nfev0 = system.nfev
    Y = coords.to_y(Z)
    lay = system.layout
    rhs = system.rhs
    dY = np.array([rhs(tk, yk) for tk, yk in zip(t.tolist(), Y)])
    powers = dY[:, lay.work]
    D = coords.rate(dY) - (Z @ lin.A.T + lin.b0 + lin.inputs(t) @ lin.B.T)
    # ė = A e + d, d linear between samples: one piece per sample interval
    h = np.diff(t)
    nz = coords.nz
    keys = np.array([float(f"{x:.12e}") for x in h])
    E = np.zeros_like(Z)
    e = np.zeros(nz)
    cache = {}
    for i in range(h.size):
        key = keys[i]
        if key not in cache:
            M = np.zeros((3 * nz, 3 * nz))
            M[:nz, :nz] = key * lin.A
            M[:nz, nz:2 * nz] = key * np.eye(nz)
            M[nz:2 * nz, 2 * nz:] = np.eye(nz)
            X = expm(M)
            cache[key] = (X[:nz, :nz], X[:nz, nz:2 * nz], X[:nz, 2 * nz:])
        Phi, P0, P1 = cache[key]
        e = Phi @ e + P0 @ D[i] + P1 @ (D[i + 1] - D[i])
        E[i + 1] = e
    to_points = _point_map(system, coords)
    pos = _largest_displacement(E, coords, to_points)
    rot = float(np.max(np.abs(E[:, coords.th_index]))) if coords.n_rigid else 0.0
    motion = _largest_displacement(Z, coords, to_points)
    reliable = pos <= 0.1 * motion or pos < 1e-12
    return ErrorEstimate(pos, rot, motion, E, reliable, system.nfev - nfev0, powers)


@dataclass(frozen=True)
class LinearRun:
    """What :func:`run_linear` returns: ``run`` (a :class:`dynamics.integrate.Run`
    whose states are the linear solution), the estimate, and the timings [s]
    of the linearisation, the propagation and the estimate."""

    run: Run
    estimate: ErrorEstimate
    linearisation: Linearisation
    time_linearise: float
    time_propagate: float
    time_estimate: float
    pieces: int

    @property
    def solve_time(self) -> float:
        """Linearisation plus propagation [s] (the estimate not included)."""
        return self.time_linearise + self.time_propagate


def unstable_rate(lin: Linearisation) -> float | None:
    """The fastest growth rate [1/s] of the linearisation's motion when the
    equilibrium is unstable (an eigenvalue of A with a real part above
    1e-6 of the largest |λ|, which is far above the central differences'
    noise and leaves the neutral modes of a free base alone), else None."""
    lam = np.linalg.eigvals(lin.A)
    if not lam.size:
        return None
    scale = float(np.max(np.abs(lam)))
    rate = float(np.max(lam.real))
    return rate if rate > 1e-6 * max(scale, 1.0) else None


def run_linear(system: System, y_eq: np.ndarray, y0: np.ndarray,
               settings: Settings) -> LinearRun:
    """Linearise about ``y_eq``, propagate from ``y0`` (ny,) to
    ``settings.t_end`` on the output grid, estimate the error and integrate
    the energy quadratures (trapezoidal rule on the samples).
    """
    w0 = time.perf_counter()
    lin = linearise(system, y_eq)
    w1 = time.perf_counter()
    growth = unstable_rate(lin)
    if growth is not None:
        # an unstable equilibrium: the linear model's motion grows without
        # bound and says nothing of the nonlinear one; nothing is propagated
        y_start = np.asarray(y0, dtype=float)[None, :].copy()
        stats = Stats(method="linear", rhs_evaluations=lin.evaluations, jacobian_evaluations=1,
                      wall_time=w1 - w0, rejected_source="none (not propagated)")
        message = (f"unstable equilibrium: the linearisation has a growing mode (rate "
                   f"{growth:.3g} 1/s, doubling in {math.log(2.0) / growth:.3g} s); the linear "
                   f"model does not apply")
        run = Run(t=np.zeros(1), y=y_start, complete=False, message=message, stats=stats,
                  settings=settings, t_reached=0.0)
        est = ErrorEstimate(math.inf, math.inf, 0.0, np.zeros((1, lin.coords.nz)), False,
                            0, np.zeros((1, system.layout.work.stop - system.layout.work.start)))
        return LinearRun(run, est, lin, w1 - w0, 0.0, 0.0, 0)
    z0 = lin.coords.to_z(np.asarray(y0, dtype=float))
    t, Z, pieces = propagate(lin, z0, settings.t_end, settings.output_dt)
    w2 = time.perf_counter()
    est = estimate_error(system, lin, t, Z)
    w3 = time.perf_counter()
    Y = lin.coords.to_y(Z)
    work = np.zeros((t.size, est.powers.shape[1]))
    work[1:] = np.cumsum(0.5 * (est.powers[1:] + est.powers[:-1]) * np.diff(t)[:, None], axis=0)
    Y[:, system.layout.work] = np.asarray(y0)[system.layout.work] + work
    stats = Stats(method="linear", steps=pieces, rhs_evaluations=lin.evaluations + est.evaluations,
                  jacobian_evaluations=1, segments=1, wall_time=w3 - w0,
                  rejected_source="none (exact propagation)")
    message = (f"linear model: estimated position error {est.position:.2e} m against the "
               f"nonlinear model")
    run = Run(t=t, y=Y, complete=True, message=message, stats=stats, settings=settings,
              t_reached=float(t[-1]))
    return LinearRun(run, est, lin, w1 - w0, w2 - w1, w3 - w2, pieces)

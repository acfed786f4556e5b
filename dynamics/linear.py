"""The linear fast path: motion linearised about the static equilibrium and
propagated exactly, with an estimate of its error against the nonlinear model.

The model itself (coordinates, linearisation, the base's inputs) is in
:mod:`flexbed.dynamics.linear_model`.

Exact propagation
-----------------
By :mod:`flexbed.dynamics.linear_propagation`: one matrix exponential of
the state augmented with the inputs (polynomial pieces, analytic
sinusoids as rotating pairs) per distinct piece length, the recursion in
compiled code.

Error estimate against the nonlinear model
------------------------------------------
Along the linear solution the nonlinear model leaves the defect
``d(t) = f(z(t), t) − (A z + b0 + B Δu)``. The nonlinear solution differs
from the linear one by ``e`` with ``ė = A e + d + O(e²)``; ``e`` is
propagated exactly with ``d`` piecewise linear. ``d`` is evaluated (the
right-hand side in one compiled batch) on every m-th output sample (the
nodes), m ≤ 16 the largest for which straight lines between those samples
follow the linear solution's point displacements to 1e-3 of their largest
value (the defect, quadratic in the motion, to a few 1e-3), and taken as
linear in between; one compiled scan of the point displacements gives
that choice and the largest motion. ``e`` is then propagated from node to
node with the propagators of the stride (the short last interval its
own), in one compiled pass that also takes the defect from the nonlinear
rates and the largest errors; on every sample only when asked for
(:attr:`ErrorEstimate.e`, e.g. for the first-order correction): the
defect between the nodes is linear, so the nodes' values are the same. The
largest error it implies at the nodes in the position of a point that
matters (the centres of mass of bodies 2… and both ends of every mount on
them, rotations and modes included with their lever arms) is the reported
estimate [m] (the nodes resolve the motion to 1e-3; on the reference
scene's rigid bed the largest over every sample is 0.16 % above it); it
is a first-order (Newton) estimate, reliable while ``e`` is small against
the motion, which :attr:`ErrorEstimate.reliable` checks.

The energy quadratures of the state (works of mounts, loads, drive and
structural damping) are integrated by the trapezoidal rule on every
sample from the powers at the nodes, interpolated in between by
not-a-knot cubic splines (linear interpolation made them 15–60 times less
accurate on the reference scene).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from scipy.linalg import expm

from .integrate import Run, Settings, Stats
from .linear_model import Coordinates, Linearisation, linearise
from .linear_propagation import _lengths, propagate
from .piecewise import spline_with_tails
from .steppers.propagate import defect_sweep, linear_sweep, point_scan
from .system import System

__all__ = ["Coordinates", "Linearisation", "LinearRun", "linearise", "propagate",
           "run_linear", "estimate_error", "unstable_rate"]


@dataclass
class ErrorEstimate:
    """First-order estimate of the linear model's error against the nonlinear one.

    position : float [m], the largest error |δP| of a point that matters
    (the centres of mass of bodies 2… and both ends of every mount on
    them, so that rotations and, on a flexible bed, the modes count with
    their lever arms) over the samples where the defect is evaluated;
    rotation : float [rad], the largest rotation error there;
    motion : float [m], the largest displacement of those points in the
    linear solution from the equilibrium, over every sample;
    reliable : bool, ``position <= 0.1 × motion`` (or both tiny);
    evaluations : right-hand sides it took; powers : (k, 4) [W] at every
    sample; nodes : (n,) int, the samples where the defect is evaluated;
    e_nodes : (n, nz), the error there. :attr:`e` gives it on every sample
    (k, nz), computed when first asked for.
    """

    position: float
    rotation: float
    motion: float
    reliable: bool
    evaluations: int
    powers: np.ndarray = field(repr=False, default=None)
    nodes: np.ndarray = field(repr=False, default=None)
    e_nodes: np.ndarray = field(repr=False, default=None)
    _every_sample: object = field(repr=False, default=None)
    _e: np.ndarray = field(repr=False, default=None)

    @property
    def e(self) -> np.ndarray:
        """The error e (k, nz) on every sample: the defect interpolated
        linearly between its nodes and propagated sample by sample."""
        if self._e is None:
            self._e = self._every_sample()
        return self._e


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
    T = to_points.reshape(-1, to_points.shape[2])                      # (3P, nz)
    d = (Z @ T.T).reshape(Z.shape[0], -1, 3)
    return float(np.sqrt(np.max(np.sum(d * d, axis=2))))


#: the defect is evaluated on every m-th sample, m the largest of these ...
_STRIDES = (16, 8, 4, 2)
#: ... whose straight lines follow the linear solution's point displacements
#: to this share of their largest value (the defect, quadratic in them, then
#: to about 4 times that)
_DEFECT_SHARE = 1e-3


def _interpolate(t: np.ndarray, nodes: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Values (n, c) at the samples t[nodes] interpolated linearly onto
    every sample t (k,) → (k, c); nodes ascending, first 0 and last k − 1."""
    if nodes.size == t.size:
        return values
    j = np.clip(np.searchsorted(nodes, np.arange(t.size), side="right") - 1, 0, nodes.size - 2)
    a, b = nodes[j], nodes[j + 1]
    w = ((t - t[a]) / (t[b] - t[a]))[:, None]
    return values[j] * (1.0 - w) + values[j + 1] * w


def _smooth(t: np.ndarray, nodes: np.ndarray, values: np.ndarray) -> np.ndarray:
    """Values (n, c) at t[nodes] on every sample t (k,) → (k, c) by
    not-a-knot cubic splines (the powers of the energy quadratures: smooth
    between the nodes, their integrals to O(H⁴)); linear below 4 nodes."""
    if nodes.size == t.size or nodes.size < 4:
        return _interpolate(t, nodes, values)
    tn = t[nodes]
    return np.column_stack([spline_with_tails(tn, values[:, j], left="hold", right="hold")
                            .evaluate(t) for j in range(values.shape[1])])


def _defect_nodes(t: np.ndarray, dP: np.ndarray) -> tuple[np.ndarray, float]:
    """The samples where the defect is evaluated, and the largest |δP| [m].

    Every m-th sample (and the last), m the largest of :data:`_STRIDES`
    whose straight lines between them miss the point displacements dP
    (k, 3P) at the midway samples by at most :data:`_DEFECT_SHARE` of their
    largest value; else every sample. One compiled pass
    (:func:`flexbed.dynamics.steppers.propagate.point_scan`)."""
    k = t.size
    strides = np.array(_STRIDES, dtype=np.int64)
    misses = np.empty(strides.size)
    motion, scale = point_scan(t, np.ascontiguousarray(dP), strides, misses)
    for m, miss in zip(_STRIDES, misses):
        nodes = np.arange(0, k, m)
        if nodes[-1] != k - 1:
            nodes = np.append(nodes, k - 1)
        if nodes.size < 3 or nodes.size == k:
            continue
        if miss <= _DEFECT_SHARE * scale:
            return nodes, motion
    return np.arange(k), motion


#: the Taylor series of the propagators are summed over L / 2^s, ‖A‖ L / 2^s at most this ...
_TAYLOR_NORM = 0.5
#: ... to this many terms (the next is below 1e-17 of the first)
_TAYLOR_TERMS = 15


def defect_propagators(A: np.ndarray, lengths: np.ndarray) -> tuple:
    """Φ, P0, P1 (m, nz, nz) of ė = A e + d over each length L (m,) [s],
    d rising linearly from d0 to d1 on it: ``e(L) = Φ e(0) + P0 d0 + P1
    (d1 − d0)``, i.e. the blocks of Van Loan's exponential. Scaling and
    squaring on the nz × nz blocks: the Taylor series over h = L / 2^s,
    ‖hA‖₁ ≤ 1/2 (to (hA)^16), Φ = Σ (hA)^k/k!, P0 = h Σ (hA)^k/(k + 1)!,
    P1 = h Σ (hA)^k/(k + 2)!, then s exact doublings
    Φ ← Φ², P0 ← (Φ + 1) P0, P1 ← (Φ P1 + P0 + P1)/2."""
    nz = A.shape[0]
    norm = float(np.linalg.norm(A, 1))
    Phis = np.empty((lengths.size, nz, nz))
    P0s, P1s = np.empty_like(Phis), np.empty_like(Phis)
    eye = np.eye(nz)
    for i, L in enumerate(lengths):
        x = norm * L
        s = max(0, math.ceil(math.log2(x / _TAYLOR_NORM))) if x > _TAYLOR_NORM else 0
        h = L / 2.0 ** s
        X = h * A
        powers = [eye, X]
        for _ in range(_TAYLOR_TERMS):
            powers.append(powers[-1] @ X)
        Phi, P0, P1 = (np.zeros((nz, nz)) for _ in range(3))
        for k in range(len(powers) - 1, -1, -1):       # the smallest terms first
            Phi += powers[k] / math.factorial(k)
            P0 += powers[k] / math.factorial(k + 1)
            P1 += powers[k] / math.factorial(k + 2)
        P0 *= h
        P1 *= h
        for _ in range(s):
            P1 = 0.5 * (Phi @ P1 + P0 + P1)
            P0 = P0 + Phi @ P0
            Phi = Phi @ Phi
        Phis[i], P0s[i], P1s[i] = Phi, P0, P1
    return Phis, P0s, P1s


def _error_on_every_sample(A: np.ndarray, t: np.ndarray, nodes: np.ndarray,
                           D: np.ndarray) -> np.ndarray:
    """e (k, nz) on every sample: the defect D (n, nz) at the nodes
    interpolated linearly and propagated sample by sample from e(0) = 0."""
    Dk = _interpolate(t, nodes, D)
    lengths, which = _lengths(np.diff(t))
    Phis, P0s, P1s = defect_propagators(A, lengths)
    nz = A.shape[0]
    Q = np.empty((t.size - 1, nz))
    for i in range(lengths.size):
        sel = np.flatnonzero(which == i)
        Q[sel] = Dk[sel] @ P0s[i].T + (Dk[sel + 1] - Dk[sel]) @ P1s[i].T
    E = np.empty((t.size, nz))
    linear_sweep(Phis, which, Q, np.zeros(nz), E)
    return E


def estimate_error(system: System, lin: Linearisation, t: np.ndarray,
                   Z: np.ndarray) -> ErrorEstimate:
    """Defect of the linear solution in the nonlinear equations, propagated
    (see the module docstring). Also returns the powers at the samples
    (k, 4) [W] for the energy quadratures."""
    coords = lin.coords
    nfev0 = system.nfev
    lay = system.layout
    nz = coords.nz
    T = _point_map(system, coords).reshape(-1, nz)                      # (3P, nz)
    nodes, motion = _defect_nodes(t, Z @ T.T)
    Zn = Z[nodes]
    tn = t[nodes]
    system.set_segment(None)
    dY, _ = system.rhs_batch(tn, coords.to_y(Zn))
    R = coords.rate(dY) - lin.b0 - lin.inputs(tn) @ lin.B.T
    powers = _smooth(t, nodes, dY[:, lay.work])
    # ė = A e + d, d linear between the nodes: Φ, P0, P1 per distinct interval
    lengths, which = _lengths(np.diff(tn))
    Phis, P0s, P1s = defect_propagators(lin.A, lengths)
    A = np.ascontiguousarray(lin.A)
    D = np.empty_like(Zn)
    En = np.empty_like(Zn)
    pos, rot = defect_sweep(R, Zn, A, Phis, P0s, P1s, which, T,
                            coords.th_index.reshape(-1).astype(np.int64), D, En)
    reliable = pos <= 0.1 * motion or pos < 1e-12
    return ErrorEstimate(pos, rot, motion, reliable, system.nfev - nfev0, powers, nodes, En,
                         lambda: _error_on_every_sample(A, t, nodes, D))


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
        est = ErrorEstimate(math.inf, math.inf, 0.0, False, 0,
                            np.zeros((1, system.layout.work.stop - system.layout.work.start)),
                            np.zeros(1, dtype=np.int64), np.zeros((1, lin.coords.nz)),
                            _e=np.zeros((1, lin.coords.nz)))
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

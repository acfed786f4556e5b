"""One run of the linear fast path: linearise about the static equilibrium
(:func:`flexbed.dynamics.linear.model.linearise`), propagate exactly over
the output samples and the inputs' knots
(:func:`flexbed.dynamics.linear.propagation.propagate_pieces`), estimate
the error against the nonlinear model and integrate the energy
quadratures (:func:`flexbed.dynamics.linear.estimate.estimate_error`),
and hand back the states as an integrator's
:class:`flexbed.dynamics.integrate.Run` with the timings of each part. An
unstable equilibrium is reported, not propagated.
"""

from __future__ import annotations

import math
import time
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Iterator

import numpy as np
from numba.core import event as numba_event

from ..integrate import Run, Settings, Stats
from ..system import System
from .estimate import ErrorEstimate, estimate_error
from .model import Linearisation, linearise
from .propagation import propagate_pieces

__all__ = ["LinearRun", "run_linear", "unstable_rate"]


@dataclass(frozen=True)
class LinearRun:
    """What :func:`run_linear` returns: ``run`` (a
    :class:`flexbed.dynamics.integrate.Run` whose states are the linear
    solution), the estimate, and the timings [s] of the linearisation, the
    propagation and the estimate."""

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


@contextmanager
def _loading() -> Iterator[list]:
    """Inside the block, the time numba spends loading or compiling [s]:
    the yielded list holds it once the block ends (empty if none). numba's
    event API times every hold of its compiler lock, which a call of a
    compiled function takes only when it loads (from the cache) or
    compiles code, so the run's timings are its own (a fresh install's
    first linear run compiles for tens of seconds) without a warm-up run,
    which cost a seventh of a warm call."""
    seconds: list[float] = []
    with numba_event.install_timer("numba:compiler_lock", seconds.append):
        yield seconds


def run_linear(system: System, y_eq: np.ndarray, y0: np.ndarray,
               settings: Settings) -> LinearRun:
    """Linearise about ``y_eq``, propagate from ``y0`` (ny,) to
    ``settings.t_end`` on the output grid, estimate the error and integrate
    the energy quadratures (the powers' cubics between the estimate's nodes).
    """
    l0 = time.perf_counter()
    _ = system.kernel          # loads (or compiles) the right-hand side outside the timings
    system.rhs_batch(np.zeros(0), np.zeros((0, system.ny)))
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
                            np.zeros((1, system.layout.work.stop - system.layout.work.start)),
                            _e=np.zeros((1, lin.coords.nz)))
        return LinearRun(run, est, lin, w1 - w0, 0.0, 0.0, 0)
    z0 = lin.coords.to_z(np.asarray(y0, dtype=float))
    w1b = time.perf_counter()              # from w1 to here: the stability check
    with _loading() as propagation_load:
        tp, Zp, samples = propagate_pieces(lin, z0, settings.t_end, settings.output_dt)
    pieces = tp.size - 1
    w2 = time.perf_counter()
    with _loading() as estimate_load:
        est = estimate_error(system, lin, tp, Zp, samples)
    w3 = time.perf_counter()
    loading = sum(propagation_load) + sum(estimate_load)
    t, Z = (tp, Zp) if samples.size == tp.size else (tp[samples], Zp[samples])
    Y = lin.coords.to_y(Z)
    Y[:, system.layout.work] = np.asarray(y0)[system.layout.work] + est.works
    stats = Stats(method="linear", steps=pieces, rhs_evaluations=lin.evaluations + est.evaluations,
                  jacobian_evaluations=1, segments=1,
                  wall_time=(w3 - w0) - loading, load_time=(w0 - l0) + loading,
                  rejected_source="none (exact propagation)")
    message = (f"linear model: estimated position error {est.position:.2e} m against the "
               f"nonlinear model")
    run = Run(t=t, y=Y, complete=True, message=message, stats=stats, settings=settings,
              t_reached=float(t[-1]))
    return LinearRun(run, est, lin, w1 - w0, w2 - w1b - sum(propagation_load),
                     w3 - w2 - sum(estimate_load), pieces)

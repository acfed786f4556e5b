"""The linear fast path: motion linearised about the static equilibrium and
propagated exactly, with an estimate of its error against the nonlinear model.

The model itself (coordinates, linearisation, the base's inputs) is in
:mod:`flexbed.dynamics.linear_model`.

Exact propagation
-----------------
By :mod:`flexbed.dynamics.linear_propagation`: one matrix exponential of
the state augmented with the inputs (polynomial pieces, analytic
sinusoids as rotating pairs) per distinct piece length (a small multiple
of the shortest takes the shortest's power; without sinusoids by the
φ-functions' series on the balanced A), the recursion in compiled
code.

Error estimate against the nonlinear model
------------------------------------------
By :mod:`flexbed.dynamics.linear_estimate`: the defect of the linear
solution in the nonlinear right-hand side at nodes among the pieces' ends,
refined where its local cubics need it, propagated exactly through the
linear model; also the energy quadratures' works.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import numpy as np

from .integrate import Run, Settings, Stats
from .linear_estimate import (ErrorEstimate, _largest_displacement, _point_map,  # noqa: F401
                              estimate_error)
from .linear_model import Coordinates, Linearisation, linearise
from .linear_propagation import propagate, propagate_pieces
from .system import System

__all__ = ["Coordinates", "Linearisation", "LinearRun", "linearise", "propagate",
           "run_linear", "estimate_error", "unstable_rate"]


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
    the energy quadratures (the powers' cubics between the estimate's nodes).
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
                            np.zeros((1, system.layout.work.stop - system.layout.work.start)),
                            _e=np.zeros((1, lin.coords.nz)))
        return LinearRun(run, est, lin, w1 - w0, 0.0, 0.0, 0)
    z0 = lin.coords.to_z(np.asarray(y0, dtype=float))
    tp, Zp, samples = propagate_pieces(lin, z0, settings.t_end, settings.output_dt)
    pieces = tp.size - 1
    w2 = time.perf_counter()
    est = estimate_error(system, lin, tp, Zp, samples)
    w3 = time.perf_counter()
    t, Z = (tp, Zp) if samples.size == tp.size else (tp[samples], Zp[samples])
    Y = lin.coords.to_y(Z)
    Y[:, system.layout.work] = np.asarray(y0)[system.layout.work] + est.works
    stats = Stats(method="linear", steps=pieces, rhs_evaluations=lin.evaluations + est.evaluations,
                  jacobian_evaluations=1, segments=1, wall_time=w3 - w0,
                  rejected_source="none (exact propagation)")
    message = (f"linear model: estimated position error {est.position:.2e} m against the "
               f"nonlinear model")
    run = Run(t=t, y=Y, complete=True, message=message, stats=stats, settings=settings,
              t_reached=float(t[-1]))
    return LinearRun(run, est, lin, w1 - w0, w2 - w1, w3 - w2, pieces)

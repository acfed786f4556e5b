"""The benchmark's reference solution and the errors measured against it.

Reference: the project's own fixed-step RK4 at a step far below any the
ladders use — ``dt_max`` (5e-5 s by default), lowered to 1 / (the fastest
rate of the bed's modes) so that the run with twice the step is still well
inside RK4's stability interval (|hλ| ≤ 2 < 2.79) — then made a divisor of
the output spacing. Its own error is estimated by Richardson extrapolation
from the run with 2·dt: for a 4th-order method, e(dt) ≈ |y(dt) − y(2 dt)| / 15.
Fixed steps, unlike adaptive methods at tight tolerances, converge at a
known rate, so the estimate is trustworthy where the ladders are not.

Errors: at the output samples (``output_dt`` apart), the largest deviation of
any position coordinate of bodies 2… (bed and equipment) [m], and of any
mount force along its axes, ``System.observe(t, y).f`` (M, 3) [N].
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from flexbed.dynamics.integrate import Run, Settings, integrate
from flexbed.dynamics.system import System

from flexbed.bench.cases import Case, divisor_step, fastest_rate
from flexbed.errors import NumericalError

__all__ = ["Samples", "Reference", "sample", "reference_step", "compute_reference", "errors"]


@dataclass(frozen=True)
class Samples:
    """What the errors are measured on, at the output samples.

    t : (k,) [s]; r : (k, nb − 1, 3) [m] positions of bodies 2…;
    f : (k, M, 3) [N] mount forces along the mount axes.
    """

    t: np.ndarray
    r: np.ndarray
    f: np.ndarray

    @property
    def motion(self) -> np.ndarray:
        """(k, nb − 1, 3) [m] positions from the start (the static equilibrium)."""
        return self.r - self.r[:1]


def sample(system: System, run: Run) -> Samples:
    """Positions and mount forces of a run at its output samples."""
    r = np.array(system.layout.split(run.y)["r"], dtype=float)
    f = np.array([system.observe(t, y).f for t, y in zip(run.t, run.y)], dtype=float)
    return Samples(t=np.array(run.t, dtype=float), r=r, f=f.reshape(len(run.t), -1, 3))


def errors(ref: Samples, s: Samples) -> tuple[float, float]:
    """(max position error [m], max mount-force error [N]) of ``s`` against
    ``ref`` over the samples they share (a complete run has them all)."""
    k = min(len(ref.t), len(s.t))
    if k == 0 or not np.allclose(ref.t[:k], s.t[:k], rtol=0, atol=1e-9):
        raise ValueError("samples on different output grids")
    return (float(np.max(np.abs(s.r[:k] - ref.r[:k]))),
            float(np.max(np.abs(s.f[:k] - ref.f[:k]))))


@dataclass(frozen=True)
class Reference:
    """A case's reference solution.

    samples : Samples
        Of the run with ``dt``.
    dt : float [s]
        RK4's largest step (each stretch between the loads' breakpoints is
        cut into equal steps no longer than this).
    position_error, force_error : float
        Richardson estimates of its own error [m], [N].
    rate : float [1/s]
        Fastest rate of the bed's modes (0: rigid bed).
    wall_time : float [s]
        Of the run with ``dt``.
    rhs_evaluations : int
        Of the run with ``dt``.
    """

    samples: Samples
    dt: float
    position_error: float
    force_error: float
    rate: float
    wall_time: float
    rhs_evaluations: int

    @property
    def seconds_per_rhs(self) -> float:
        """Wall time per right-hand side of RK4, overhead included [s]."""
        return self.wall_time / max(1, self.rhs_evaluations)


def reference_step(system: System, output_dt: float, dt_max: float = 5e-5) -> float:
    """The reference's step [s] (see the module docstring)."""
    rate = fastest_rate(system)
    dt = dt_max if rate == 0.0 else min(dt_max, 1.0 / rate)
    return divisor_step(dt, output_dt)


def compute_reference(case: Case, output_dt: float, dt_max: float = 5e-5,
                      log=lambda m: None) -> Reference:
    """RK4 runs with dt and 2·dt; the first is the reference, their
    difference / 15 its error estimate."""
    system = case.system
    dt = reference_step(system, output_dt, dt_max)
    runs = []
    for h in (dt, 2 * dt):
        log(f"bench {case.spec.key}: reference RK4, dt = {h:.4g} s ...")
        run = integrate(system, case.y0, Settings("rk4", t_end=case.t_end, dt=h,
                                                  output_dt=output_dt))
        if not run.complete:
            raise NumericalError(f"{case.label}: the reference run (RK4, dt = {h:.4g} s) "
                                 f"failed: {run.message}")
        runs.append(run)
    fine, coarse = sample(system, runs[0]), sample(system, runs[1])
    e_pos, e_force = errors(fine, coarse)
    return Reference(samples=fine, dt=dt, position_error=e_pos / 15.0,
                     force_error=e_force / 15.0, rate=fastest_rate(system),
                     wall_time=runs[0].stats.wall_time,
                     rhs_evaluations=runs[0].stats.rhs_evaluations)

"""Modelling choices as error against cost: how many modes to keep, and the
full invariants against the first-order set.

Each variant is the same scene and the same integrator setting (accurate
enough that its own error is far below the modelling error measured, see
the integrator tables), so the differences are the model's:

- modes kept: the damped flexible bed keeping n modes against the one
  keeping many (:data:`MODE_REFERENCE`); errors of the positions of bodies
  2… (which include the static sag, itself truncated), of their motion from
  their own equilibrium, and of the mount forces; the solve time and one
  right-hand side.
- invariants: ``invariants = "first_order"`` (inertia linear in the modal
  coordinates) against ``"full"``, both measured against the case's RK4
  reference (full invariants), so the "full" row shows the integrator's own
  error and the difference between the rows is the truncation's.
"""

from __future__ import annotations

import math
import statistics
from dataclasses import dataclass

import numpy as np

from flexbed.dynamics.integrate import Settings, integrate

from flexbed.bench.cases import Case, CaseSpec, ModesStore, build_case, rhs_cost
from flexbed.bench.reference import Reference, Samples, errors, sample
from flexbed.errors import NumericalError
from flexbed.files.scene import SceneFile

__all__ = ["MODE_COUNTS", "QUICK_MODE_COUNTS", "MODE_REFERENCE", "QUICK_MODE_REFERENCE",
           "ModelRun", "solve", "modes_count_runs", "invariants_runs", "highest_frequency"]

MODE_COUNTS = (1, 2, 4, 6, 10, 20, 30)
MODE_REFERENCE = 40
QUICK_MODE_COUNTS = (1, 2, 4)
QUICK_MODE_REFERENCE = 10


@dataclass
class ModelRun:
    """One model variant solved once (or a few times when cheap).

    name : str; case : Case; samples : Samples; wall_time : median [s];
    runs : int; steps, rhs_evaluations : int; rhs_us : one right-hand side [µs];
    position_error [m], motion_error [m], force_error [N] : against the
    variant's reference (NaN until measured).
    """

    name: str
    case: Case
    samples: Samples
    wall_time: float
    runs: int
    steps: int
    rhs_evaluations: int
    rhs_us: float
    position_error: float = math.nan
    motion_error: float = math.nan
    force_error: float = math.nan

    def measure_against(self, ref: Samples) -> None:
        """Fill in the errors against ``ref`` (same output grid)."""
        self.position_error, self.force_error = errors(ref, self.samples)
        k = min(len(ref.t), len(self.samples.t))
        self.motion_error = float(np.max(np.abs(self.samples.motion[:k] - ref.motion[:k])))


def solve(name: str, case: Case, method: str, rtol: float, output_dt: float, *,
          repeats: int = 1, rhs_seconds: float = 0.2) -> ModelRun:
    """Solve a variant with one integrator setting; time its right-hand side.

    ``repeats`` further runs are made only while a run takes under 1 s.
    """
    st = Settings(method, t_end=case.t_end, rtol=rtol, atol=1e-3 * rtol, output_dt=output_dt)
    with np.errstate(all="ignore"):
        run = integrate(case.system, case.y0, st)
    if not run.complete:
        raise NumericalError(f"{case.label} ({method}, rtol = {rtol:g}): {run.message}")
    walls = [run.stats.wall_time]
    while len(walls) < repeats and walls[0] < 1.0:
        with np.errstate(all="ignore"):
            walls.append(integrate(case.system, case.y0, st).stats.wall_time)
    return ModelRun(name=name, case=case, samples=sample(case.system, run),
                    wall_time=statistics.median(walls), runs=len(walls),
                    steps=run.stats.steps, rhs_evaluations=run.stats.rhs_evaluations,
                    rhs_us=rhs_cost(case, seconds=rhs_seconds, repeat=3))


def highest_frequency(case: Case) -> float:
    """The highest undamped frequency of the bed's kept modes [Hz] (0: rigid)."""
    f = 0.0
    for fc in case.system.flex_compiled:
        k = np.diag(fc.eom.K) / np.diag(fc.eom.I6)
        f = max(f, float(np.sqrt(np.max(k, initial=0.0))) / (2 * math.pi))
    return f


def modes_count_runs(sf: SceneFile, store: ModesStore, counts, reference_count: int, *,
                     t_end: float, output_dt: float, method: str = "radau", rtol: float = 1e-8,
                     damped: bool = True, repeats: int = 1, rhs_seconds: float = 0.2,
                     log=lambda m: None) -> tuple[list[ModelRun], ModelRun]:
    """The bed keeping each of ``counts`` modes, and ``reference_count``
    modes as the reference; returns (runs with their errors, reference run)."""
    store.ensure(max(max(counts), reference_count))
    out = []
    for n in list(counts) + [reference_count]:
        log(f"bench modes kept: {n} ...")
        case = build_case(sf, CaseSpec(f"modes-{n}", n_modes=n, damped=damped), store, t_end)
        out.append(solve(f"{n}", case, method, rtol, output_dt, repeats=repeats,
                         rhs_seconds=rhs_seconds))
    ref = out.pop()
    for r in out:
        r.measure_against(ref.samples)
    ref.measure_against(ref.samples)
    return out, ref


def invariants_runs(sf: SceneFile, store: ModesStore, spec: CaseSpec, ref: Reference, *,
                    t_end: float, output_dt: float, method: str, rtol: float,
                    repeats: int = 1, rhs_seconds: float = 0.2,
                    log=lambda m: None) -> list[ModelRun]:
    """``spec`` with the full and with the first-order invariants, each
    measured against ``ref`` (the case's reference, full invariants)."""
    out = []
    for inv in ("full", "first_order"):
        log(f"bench invariants: {spec.key}, {inv} ...")
        vspec = CaseSpec(spec.key, n_modes=spec.n_modes, damped=spec.damped, invariants=inv)
        case = build_case(sf, vspec, store, t_end)
        run = solve(inv, case, method, rtol, output_dt, repeats=repeats,
                    rhs_seconds=rhs_seconds)
        run.measure_against(ref.samples)
        out.append(run)
    return out

"""An optimisation run from start to end: the cluster, the evaluator, the
method from each start (or a Pareto front), the catalogue snap, the
result; the files (:mod:`flexbed.optimization.report`) when a folder is given.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from flexbed.optimization.evaluate import Evaluation, Evaluator
from flexbed.optimization.methods import best_of, evolve, local, starts
from flexbed.optimization.problem import Problem

__all__ = ["Optimum", "optimize_problem"]


@dataclass(frozen=True)
class Optimum:
    """The result of an optimisation.

    problem : Problem; values : dict path → value (the variables, scene
    units); x, x0 : (n,) the variables at the optimum and at the first start;
    best, initial : Evaluation; feasible : bool; objective : float;
    violation : float (largest, a share of its bound); evaluations : int
    (points computed in this run); reused : int (points met again: cache or
    an earlier run's log); wall_time : float [s]; outcomes : list of the
    methods' ends (one per start); pareto : list of Evaluation (a
    two-objective front, else empty); history : list of Evaluation, in the
    order asked; message : str.
    """

    problem: Problem
    values: dict
    x: np.ndarray
    x0: np.ndarray
    best: Evaluation
    initial: Evaluation
    feasible: bool
    objective: float
    violation: float
    evaluations: int
    reused: int
    wall_time: float
    outcomes: list = field(default_factory=list)
    pareto: list = field(default_factory=list)
    history: list = field(default_factory=list)
    message: str = ""

    @property
    def scene(self):
        """The optimum's scene (SceneFile)."""
        return self.problem.scene(self.x)


def _snap(ev: Evaluator, best: Evaluation) -> Evaluation:
    p = ev.problem
    if all(v.values is None for v in p.variables):
        return best
    return ev.one(p.values(p.unit(best.x), snap=True))


def _pareto(ev: Evaluator, problem: Problem, spec, budget: int) -> list:
    """The weighted sums w, 1 − w of the two objectives, w from 0 to 1, each
    from the previous one's optimum."""
    front, u = [], problem.u0
    for w in np.linspace(0.0, 1.0, spec.pareto):
        out = local(ev, u, "slsqp" if spec.method == "differential_evolution" else spec.method,
                    step=spec.step, central=spec.differences == "central",
                    tolerance=spec.tolerance, budget=budget, weights=[w, 1.0 - w])
        front.append(out.best)
        u = out.u
    return front


def optimize_problem(problem: Problem, client, folder: Path | None = None) -> Optimum:
    """Run ``problem`` on the Dask ``client``; log into ``folder``."""
    spec = problem.spec
    t0 = time.perf_counter()
    ev = Evaluator(problem, client, folder)
    logged = ev.evaluations
    budget = ev.evaluations + spec.max_evaluations
    initial = ev.one(problem.values(problem.u0))
    outcomes, front = [], []
    if spec.pareto:
        front = _pareto(ev, problem, spec, budget)
    elif spec.method == "differential_evolution":
        outcomes.append(evolve(ev, seed=spec.seed, population=spec.population,
                               tolerance=spec.tolerance, budget=budget))
        polish = local(ev, outcomes[-1].u, "slsqp", step=spec.step,
                       central=spec.differences == "central", tolerance=spec.tolerance,
                       budget=budget + 20 * (problem.n + 1))
        outcomes.append(polish)
    else:
        for i, u0 in enumerate(starts(problem.u0, spec.starts, problem.n, spec.seed)):
            outcomes.append(local(ev, u0, spec.method, step=spec.step,
                                  central=spec.differences == "central",
                                  tolerance=spec.tolerance, budget=budget, start=i))
    # the methods' ends, and the best point seen at all (a stencil's point,
    # a line search's trial may beat where a method stopped)
    candidates = [o.best for o in outcomes] + front + [initial, best_of(ev.history)]
    best = _snap(ev, best_of(candidates))
    message = "; ".join(f"start {o.start + 1}: {o.message}" for o in outcomes) or \
        f"Pareto front of {len(front)} points"
    return Optimum(problem, problem.changes(best.x), best.x, problem.values(problem.u0), best,
                   initial, best.feasible, best.objective, best.violation, ev.evaluations - logged,
                   ev.reused, time.perf_counter() - t0, outcomes, front, list(ev.history),
                   message)

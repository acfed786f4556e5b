"""The optimisers: SciPy's SLSQP and trust-constr with finite-difference
gradients whose evaluations run together, differential evolution with its
population evaluated together, and multi-start around them.

Every method works in unit coordinates (:mod:`flexbed.optimization.problem`).
A gradient is forward (n + 1 points) or central (2n + 1) differences of
step h = ``step`` in unit coordinates (backward at the upper bound), and
the objective's and every constraint's gradient come from the same points,
evaluated as one batch (:class:`Stencil`). Differential evolution minimises
the objective plus 10³ × the sum of the violations (a penalty: SciPy's own
constraint handling would evaluate the population one point at a time),
then the best point is polished by SLSQP.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import Bounds, NonlinearConstraint, differential_evolution, minimize
from scipy.stats import qmc

from flexbed.optimization.evaluate import Evaluation, Evaluator

__all__ = ["Stencil", "Outcome", "local", "evolve", "starts", "best_of"]

#: weight of the violations in differential evolution's penalised objective
PENALTY = 1e3


class _Budget(Exception):
    """The evaluation budget is spent."""


class Stencil:
    """The objective, the constraints and their gradients at unit
    coordinates u, from one batch of evaluations per u (cached)."""

    def __init__(self, ev: Evaluator, step: float, central: bool, weights=None,
                 budget: int = 10 ** 9):
        self.ev, self.h, self.central, self.weights = ev, step, central, weights
        self.budget = budget
        self._at: dict = {}

    def _f(self, e: Evaluation) -> float:
        if self.weights is None or not e.ok:
            return e.objective
        return self.ev.problem.objective(e.result.values, self.weights)

    def _points(self, u) -> tuple:
        key = tuple(np.round(np.asarray(u, dtype=float), 15))
        if key in self._at:
            return self._at[key]
        if self.ev.evaluations >= self.budget:
            raise _Budget
        p, u = self.ev.problem, np.clip(np.asarray(u, dtype=float), 0.0, 1.0)
        pts = [u]
        steps = []
        for i in range(p.n):
            h = self.h if u[i] + self.h <= 1.0 else -self.h
            e = np.zeros(p.n)
            e[i] = h
            pts.append(u + e)
            steps.append(h)
            if self.central:
                pts.append(np.clip(u - e, 0.0, 1.0))
        evs = self.ev.many([p.values(q) for q in pts])
        f = np.array([self._f(e) for e in evs])
        c = np.array([e.constraints for e in evs])
        gf, gc = np.zeros(p.n), np.zeros((c.shape[1], p.n))
        for i, h in enumerate(steps):
            if self.central:
                hi, lo = 1 + 2 * i, 2 + 2 * i
                d = pts[hi][i] - pts[lo][i]
                gf[i], gc[:, i] = (f[hi] - f[lo]) / d, (c[hi] - c[lo]) / d
            else:
                gf[i], gc[:, i] = (f[1 + i] - f[0]) / h, (c[1 + i] - c[0]) / h
        self._at[key] = (f[0], c[0], gf, gc, evs[0])
        return self._at[key]

    def fun(self, u):
        return self._points(u)[0]

    def jac(self, u):
        return self._points(u)[2]

    def cons(self, u):
        return self._points(u)[1]

    def cons_jac(self, u):
        return self._points(u)[3]


@dataclass(frozen=True)
class Outcome:
    """A method's end: u (n,) unit coordinates; best : Evaluation (at u);
    iterations : int; message : str; start : int (0-based)."""

    u: np.ndarray
    best: Evaluation
    iterations: int
    message: str
    start: int


def local(ev: Evaluator, u0, method: str, *, step: float, central: bool, tolerance: float,
          budget: int, weights=None, start: int = 0) -> Outcome:
    """SLSQP or trust-constr from ``u0``."""
    s = Stencil(ev, step, central, weights, budget)
    n_con = s.cons(u0).size
    try:
        if method == "slsqp":
            cons = [{"type": "ineq", "fun": s.cons, "jac": s.cons_jac}] if n_con else []
            r = minimize(s.fun, np.asarray(u0, dtype=float), jac=s.jac, method="SLSQP",
                         bounds=[(0.0, 1.0)] * ev.problem.n, constraints=cons,
                         options={"ftol": tolerance, "maxiter": 500})
        else:
            cons = [NonlinearConstraint(s.cons, 0.0, np.inf, jac=s.cons_jac)] if n_con else []
            r = minimize(s.fun, np.asarray(u0, dtype=float), jac=s.jac, method="trust-constr",
                         hess=lambda u: np.zeros((len(u), len(u))),
                         bounds=Bounds(0.0, 1.0), constraints=cons,
                         options={"xtol": tolerance, "gtol": tolerance, "maxiter": 1000})
        u, message, nit = np.clip(r.x, 0.0, 1.0), str(r.message), int(getattr(r, "nit", 0))
    except _Budget:
        u, message, nit = None, "the evaluation budget (max_evaluations) is spent", -1
    if u is None:
        best = best_of([e for e in ev.history])
        return Outcome(ev.problem.unit(best.x), best, nit, message, start)
    return Outcome(u, s._points(u)[4], nit, message, start)


def evolve(ev: Evaluator, *, seed: int, population: int, tolerance: float,
           budget: int) -> Outcome:
    """Differential evolution over the unit box, the population evaluated
    as one batch per generation; catalogue variables snapped."""
    p = ev.problem

    def score(e: Evaluation) -> float:
        return e.objective + PENALTY * float(np.sum(np.maximum(0.0, -e.constraints)))

    def batch(func, population_u):
        pts = list(population_u)
        if ev.evaluations >= budget:
            return [np.inf] * len(pts)
        return [score(e) for e in ev.many([p.values(u, snap=True) for u in pts])]

    gens = max(1, budget // max(1, population * p.n) - 1)
    r = differential_evolution(lambda u: score(ev.one(p.values(u, snap=True))),
                               [(0.0, 1.0)] * p.n, seed=seed, popsize=population,
                               tol=tolerance, maxiter=gens, polish=False, workers=batch,
                               updating="deferred", init="latinhypercube")
    u = np.asarray(r.x, dtype=float)
    return Outcome(u, ev.one(p.values(u, snap=True)), int(r.nit), str(r.message), 0)


def starts(u0, count: int, n: int, seed: int) -> list:
    """The first start ``u0``, then ``count − 1`` Latin-hypercube points."""
    out = [np.asarray(u0, dtype=float)]
    if count > 1:
        out += list(qmc.LatinHypercube(d=n, seed=seed).random(count - 1))
    return out


def best_of(evals) -> Evaluation:
    """The best of ``evals``: the feasible one of least objective, else the
    one of least violation."""
    feasible = [e for e in evals if e.feasible]
    if feasible:
        return min(feasible, key=lambda e: e.objective)
    ok = [e for e in evals if e.ok] or list(evals)
    return min(ok, key=lambda e: (e.violation, e.objective))

"""An optimisation file checked against its scene, as a problem in unit
coordinates.

The optimisers work in u ∈ [0, 1]ⁿ, one coordinate per variable (x = low +
u (high − low)), so that SLSQP and trust-constr see variables of one size
and a finite-difference step is a share of each range. A point's scene is
the base scene with every variable's paths set (``tie``: the same value,
``mirror``: its negative, ``link``: factor × value + offset); a
catalogue variable (``values``) is relaxed to its range by the gradient
methods and snapped to the nearest value at the end (differential
evolution snaps at every evaluation).

Objective (minimised): Σ wᵢ sᵢ rᵢ / scaleᵢ, sᵢ = +1 (minimize) or −1
(maximize), rᵢ the metric's column, or its columns reduced (``reduce``,
default the sum). Constraints, each column (or the reduced value) within
[lower, upper]: cⱼ = (v − lower)/|lower| ≥ 0 and (upper − v)/|upper| ≥ 0
(divided by 1 when a bound is 0), so that a violation reads as a share of
its bound.
"""

from __future__ import annotations

import hashlib
import json
import tomllib
from dataclasses import dataclass

import numpy as np

from flexbed.errors import InputError
from flexbed.files.scene import SceneFile, load_scene
from flexbed.files.variants import split_path, vary
from flexbed.optimization.spec import Goal, OptimizeSpec, Variable
from flexbed.study.analyses import ordered
from flexbed.study.metrics import KINDS

__all__ = ["Problem", "make_problem", "scene_value"]

_REDUCE = {"sum": np.sum, "max": np.max, "min": np.min, "mean": np.mean}
#: what a failed point scores: the objective's and every constraint's value
FAILED_OBJECTIVE, FAILED_CONSTRAINT = 1e10, -1e3


def scene_value(scene: SceneFile, path: str):
    """The value at ``path`` in the scene's TOML, or None when absent."""
    node = tomllib.loads(scene.text)
    for step in split_path(path):
        if isinstance(node, dict) and isinstance(step, str):
            node = node.get(step)
        elif isinstance(node, list) and isinstance(step, int):
            node = node[step] if 0 <= step < len(node) else None
        elif isinstance(node, list):
            named = [x for x in node if isinstance(x, dict) and x.get("name") == step]
            node = named[0] if len(named) == 1 else None
        else:
            return None
        if node is None:
            return None
    return node


@dataclass(frozen=True)
class Problem:
    """A checked optimisation.

    spec : OptimizeSpec; base : SceneFile (``[optimize.set]`` applied);
    variables : tuple of Variable; metrics : tuple — one metric object per
    goal (objectives first, then constraints); goals : tuple of Goal (same
    order); analyses : tuple of str; u0 : (n,) the first start in unit
    coordinates; signature : str — hash of the variables, metrics and
    goals (a log with another signature is not reused).
    """

    spec: OptimizeSpec
    base: SceneFile
    variables: tuple
    metrics: tuple
    goals: tuple
    analyses: tuple
    u0: np.ndarray
    signature: str

    # ------------------------------------------------------------ variables
    @property
    def n(self) -> int:
        return len(self.variables)

    def values(self, u, snap: bool = False) -> np.ndarray:
        """(n,) the variables' values [scene units] at unit coordinates u;
        ``snap``: catalogue variables at their nearest catalogue value."""
        u = np.clip(np.asarray(u, dtype=float), 0.0, 1.0)
        x = np.array([v.low + ui * (v.high - v.low) for v, ui in zip(self.variables, u)])
        if snap:
            for i, v in enumerate(self.variables):
                if v.values is not None:
                    cat = np.array(v.values)
                    x[i] = cat[np.argmin(np.abs(cat - x[i]))]
        return x

    def unit(self, x) -> np.ndarray:
        """Unit coordinates of the variables' values ``x``."""
        return np.array([(xi - v.low) / (v.high - v.low) for v, xi in zip(self.variables, x)])

    def changes(self, x) -> dict:
        """path → value for every path the variables set."""
        return {p: float(factor * xi + offset) + 0.0 for v, xi in zip(self.variables, x)
                for p, factor, offset in v.paths}

    def scene(self, x) -> SceneFile:
        """The base scene with the variables at ``x`` (checked)."""
        return vary(self.base, self.changes(x))

    # ---------------------------------------------------------------- goals
    @property
    def columns(self) -> tuple:
        """The log's metric columns: ``<role><index>:<metric column>``."""
        return tuple(f"{g.role}{g.index}:{c}" for g, m in zip(self.goals, self.metrics)
                     for c in m.columns)

    def _split(self, row) -> list:
        out, i = [], 0
        for m in self.metrics:
            k = len(m.columns)
            out.append(np.asarray(row[i:i + k], dtype=float))
            i += k
        return out

    def objectives(self, row) -> np.ndarray:
        """Each objective's value (reduced, signed for minimising, scaled)."""
        parts = self._split(row)
        out = []
        for g, v in zip(self.goals, parts):
            if g.role == "objective":
                r = _REDUCE[g.reduce or "sum"](v)
                out.append((1.0 if g.sense == "minimize" else -1.0) * r / g.scale)
        return np.array(out)

    def objective(self, row, weights=None) -> float:
        """The weighted sum of the objectives (0 without objectives)."""
        obj = self.objectives(row)
        w = np.array([g.weight for g in self.goals if g.role == "objective"]) \
            if weights is None else np.asarray(weights, dtype=float)
        return float(np.dot(w, obj)) if obj.size else 0.0

    def constraints(self, row) -> np.ndarray:
        """Every constraint's margin (≥ 0 where it holds), as a share of its
        bound."""
        parts = self._split(row)
        out = []
        for g, v in zip(self.goals, parts):
            if g.role != "constraint":
                continue
            v = np.atleast_1d(_REDUCE[g.reduce](v)) if g.reduce else v
            if g.lower is not None:
                out.extend((v - g.lower) / (abs(g.lower) or 1.0))
            if g.upper is not None:
                out.extend((g.upper - v) / (abs(g.upper) or 1.0))
        return np.array(out, dtype=float)


def _start(where: str, base: SceneFile, i: int, v: Variable) -> float:
    if v.start is not None:
        return v.start
    value = scene_value(base, v.path)
    if value is None:
        raise InputError(f"{where}: variable {i} ({v.path}): the scene gives no value there; "
                         f"give start = ...")
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(f"{where}: variable {i} ({v.path}): the scene's value "
                         f"{str(value)[:40]} is not a number (give a path to one number, "
                         f"e.g. \"mount.M5.k[2]\")")
    return float(min(max(value, v.low), v.high))


def _metric(where: str, goal: Goal, base: SceneFile):
    kind = goal.metric.kind
    if kind not in KINDS:
        raise InputError(f"{where}: {goal.role} {goal.index}: unknown metric kind {kind!r} "
                         f"(known: {', '.join(KINDS)})")
    return KINDS[kind].build(goal.metric, base, f"{where}: {goal.entry}")


def make_problem(spec: OptimizeSpec) -> Problem:
    """Check the optimisation against its scene before anything runs.

    Raises InputError (one line naming the file, the entry and the value)
    on a variable path the scene does not have or whose value the scene
    refuses at either bound, an unknown metric kind or key, or a metric
    naming no body, mount or mode of the scene.
    """
    where = spec.source.name
    base = load_scene(spec.scene)
    if spec.fixed:
        try:
            base = vary(base, dict(spec.fixed))
        except InputError as exc:
            raise InputError(f"{where}: [optimize.set]: {exc}") from None
    x0 = []
    for i, v in enumerate(spec.variables, 1):
        for end in (v.low, v.high):
            try:
                vary(base, {p: f * end + o for p, f, o in v.paths})
            except InputError as exc:
                raise InputError(f"{where}: variable {i} ({v.path}) = {end!r}: {exc}") from None
        x0.append(_start(where, base, i, v))
    goals = spec.objectives + spec.constraints
    metrics = tuple(_metric(where, g, base) for g in goals)
    analyses = ordered({m.analysis for m in metrics})
    signature = hashlib.sha256(json.dumps(
        {"scene": base.digest, "variables": [repr(v) for v in spec.variables],
         "goals": [[g.role, g.metric.kind, list(map(list, g.metric.options))] for g in goals]},
        sort_keys=True, default=str).encode()).hexdigest()[:16]
    problem = Problem(spec, base, spec.variables, metrics, goals, analyses,
                      np.zeros(len(x0)), signature)
    object.__setattr__(problem, "u0", problem.unit(np.array(x0)))
    return problem

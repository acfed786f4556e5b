"""The optimisation file (TOML) read into frozen dataclasses.

In the study file's manner (:mod:`flexbed.study.spec`): a base scene, the
changes every evaluation shares (``[optimize.set]``), the design variables
by their path in the scene (:mod:`flexbed.files.variants`), the objectives
and the constraints as metric tables (any study metric kind, with its keys).
This module checks the file's own shape; :mod:`flexbed.optimization.problem`
checks it against the scene. Errors are one line naming the file, the entry
and the value (InputError).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from flexbed.errors import InputError
from flexbed.files.destination import check_source
from flexbed.files.table_reader import is_finite_number, short_repr
from flexbed.study.spec import MetricTable

__all__ = ["Variable", "Goal", "OptimizeSpec", "METHODS", "REDUCTIONS", "read_optimize",
           "parse_optimize"]

#: the methods: SciPy's SLSQP and trust-constr (finite-difference gradients,
#: their evaluations in parallel) and differential evolution
METHODS = ("slsqp", "trust-constr", "differential_evolution")
#: how a metric's columns (one per mount, per mode …) become one number
REDUCTIONS = ("sum", "max", "min", "mean")
DIFFERENCES = ("forward", "central")
#: the most evaluations one optimisation may ask for
MAX_EVALUATIONS = 100_000

_TOP = ("optimize", "variable", "objective", "constraint")
_HEAD_KEYS = ("name", "scene", "method", "starts", "seed", "set", "max_evaluations",
              "tolerance", "step", "differences", "pareto", "population")
_VARIABLE_KEYS = ("path", "low", "high", "values", "start", "tie", "mirror", "link")
_GOAL_KEYS = ("weight", "sense", "reduce", "scale")
_CONSTRAINT_KEYS = ("lower", "upper", "excitation")


@dataclass(frozen=True, slots=True)
class Variable:
    """One design variable.

    path : str — a scene entry (a number; ``"mount.M5.k[2]"`` a component);
    low, high : float — its bounds (for ``values``, the smallest and the
    largest); values : tuple of float or None — a catalogue (the variable
    takes one of them); start : float or None (None: the scene's value);
    tie : tuple of str — entries set to the same value; mirror : tuple of
    str — entries set to its negative (a symmetric layout's other side);
    link : tuple of (path, factor, offset) — entries set to factor × value
    + offset (a mount's point on the bed that follows its point on the
    equipment).
    """

    path: str
    low: float
    high: float
    values: tuple | None = None
    start: float | None = None
    tie: tuple = ()
    mirror: tuple = ()
    link: tuple = ()

    @property
    def paths(self) -> tuple:
        """Every (path, factor, offset) this variable sets."""
        return ((self.path, 1.0, 0.0),) + tuple((p, 1.0, 0.0) for p in self.tie) \
            + tuple((p, -1.0, 0.0) for p in self.mirror) + self.link


@dataclass(frozen=True, slots=True)
class Goal:
    """An objective or a constraint: a metric table and what is asked of it.

    metric : MetricTable; role : "objective" or "constraint"; index : int
    (1-based within its role); weight : float and sense : "minimize" |
    "maximize" (objectives); scale : float — the objective divided by it;
    reduce : one of :data:`REDUCTIONS` or None (a constraint holds for each
    column when None); lower, upper : float or None (constraints).
    """

    metric: MetricTable
    role: str
    index: int
    weight: float = 1.0
    sense: str = "minimize"
    reduce: str | None = None
    scale: float = 1.0
    lower: float | None = None
    upper: float | None = None

    @property
    def entry(self) -> str:
        return f"{self.role} {self.index} ({self.metric.kind})"


@dataclass(frozen=True, slots=True)
class OptimizeSpec:
    """An optimisation file, read.

    source : Path; name : str; scene : Path or None (the built-in scene);
    method : one of :data:`METHODS`; starts : int — starting points (the
    scene's values first, then Latin-hypercube points in the bounds);
    seed : int; fixed : ((path, value), ...); variables : tuple of
    Variable; objectives, constraints : tuple of Goal; max_evaluations :
    int; tolerance : float (the method's); step : float — finite-difference
    step, relative to each variable's range; differences : "forward" |
    "central"; pareto : int — points of a two-objective Pareto front (0:
    none, the weighted sum); population : int (differential evolution's
    ``popsize``).
    """

    source: Path
    name: str
    scene: Path | None
    method: str
    starts: int
    seed: int
    fixed: tuple
    variables: tuple
    objectives: tuple
    constraints: tuple
    max_evaluations: int = 2000
    tolerance: float = 1e-10
    step: float = 1e-6
    differences: str = "forward"
    pareto: int = 0
    population: int = 8


def read_optimize(path: str | Path) -> OptimizeSpec:
    """Read and check an optimisation file's shape."""
    path = check_source(path, "optimisation file")
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(f"{path}: cannot read the optimisation file "
                         f"({exc.strerror or exc})") from None
    except UnicodeDecodeError:
        raise InputError(f"{path.name}: not a UTF-8 text file") from None
    return parse_optimize(text, path)


def _known(table: dict, keys: tuple, where: str, entry: str) -> None:
    for key in table:
        if key not in keys:
            raise InputError(f"{where}: {entry}: unknown key {key!r} (known: {', '.join(keys)})")


def _tables(data: dict, key: str, where: str) -> list:
    value = data.get(key, [])
    if not isinstance(value, list) or not all(isinstance(t, dict) for t in value):
        raise InputError(f"{where}: {key} must be an array of tables ([[{key}]])")
    return value


def _integer(value: Any, where: str, key: str, low: int, high: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
        raise InputError(f"{where}: [optimize] {key} = {short_repr(value)} must be an integer "
                         f"in {low} - {high}")
    return value


def _positive(value: Any, where: str, entry: str, key: str) -> float:
    if not is_finite_number(value) or isinstance(value, bool) or value <= 0:
        raise InputError(f"{where}: {entry} {key} = {short_repr(value)} must be a number > 0")
    return float(value)


def parse_optimize(text: str, source: Path) -> OptimizeSpec:
    """Check an optimisation file given as TOML text; ``source`` names it
    in messages and is the folder a relative ``scene`` is found from."""
    source = Path(source)
    where = source.name
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{where}: not valid TOML: {exc}") from None
    _known(data, _TOP, where, "top level")
    head = data.get("optimize", {})
    if not isinstance(head, dict):
        raise InputError(f"{where}: [optimize] must be a table")
    _known(head, _HEAD_KEYS, where, "[optimize]")
    name = head.get("name", source.stem)
    if not isinstance(name, str) or not name:
        raise InputError(f"{where}: [optimize] name = {short_repr(name)} must be a non-empty "
                         f"string")
    scene = head.get("scene")
    if scene is not None:
        if not isinstance(scene, str) or not scene:
            raise InputError(f"{where}: [optimize] scene = {short_repr(scene)} must be a file "
                             f"name")
        scene = source.parent / scene
    method = head.get("method", "slsqp")
    if method not in METHODS:
        raise InputError(f"{where}: [optimize] method = {short_repr(method)} must be one of "
                         f"{', '.join(METHODS)}")
    differences = head.get("differences", "forward")
    if differences not in DIFFERENCES:
        raise InputError(f"{where}: [optimize] differences = {short_repr(differences)} must "
                         f"be one of {', '.join(DIFFERENCES)}")
    fixed = head.get("set", {})
    if not isinstance(fixed, dict):
        raise InputError(f"{where}: [optimize.set] must be a table of path = value")
    step = head.get("step", 1e-6)
    if not is_finite_number(step) or isinstance(step, bool) or not 0 < step < 0.1:
        raise InputError(f"{where}: [optimize] step = {short_repr(step)} must be a number in "
                         f"(0, 0.1) (a share of each variable's range)")
    variables = tuple(_variable(where, i + 1, t)
                      for i, t in enumerate(_tables(data, "variable", where)))
    if not variables:
        raise InputError(f"{where}: no [[variable]]: name at least one scene entry to vary")
    _check_paths(where, variables)
    objectives = tuple(_goal(where, "objective", i + 1, t)
                       for i, t in enumerate(_tables(data, "objective", where)))
    constraints = tuple(_goal(where, "constraint", i + 1, t)
                        for i, t in enumerate(_tables(data, "constraint", where)))
    if not objectives and not constraints:
        raise InputError(f"{where}: no [[objective]] and no [[constraint]]: nothing to aim at")
    pareto = _integer(head.get("pareto", 0), where, "pareto", 0, 100)
    if pareto and (len(objectives) != 2 or pareto < 2):
        raise InputError(f"{where}: [optimize] pareto = {pareto} needs exactly two "
                         f"[[objective]] tables and at least 2 points "
                         f"(objectives: {len(objectives)})")
    return OptimizeSpec(
        source=source, name=name, scene=scene, method=method,
        starts=_integer(head.get("starts", 1), where, "starts", 1, 1000),
        seed=_integer(head.get("seed", 0), where, "seed", 0, 2 ** 32 - 1),
        fixed=tuple(fixed.items()), variables=variables, objectives=objectives,
        constraints=constraints,
        max_evaluations=_integer(head.get("max_evaluations", 2000), where, "max_evaluations",
                                 1, MAX_EVALUATIONS),
        tolerance=_positive(head.get("tolerance", 1e-10), where, "[optimize]", "tolerance"),
        step=float(step), differences=differences, pareto=pareto,
        population=_integer(head.get("population", 8), where, "population", 2, 1000))


def _paths(value: Any, where: str, entry: str, key: str) -> tuple:
    if value is None:
        return ()
    if not isinstance(value, list) or not all(isinstance(p, str) and p for p in value):
        raise InputError(f"{where}: {entry}: {key} = {short_repr(value)} must be a list of "
                         f"scene paths")
    return tuple(value)


def _variable(where: str, i: int, t: dict) -> Variable:
    entry = f"variable {i}"
    _known(t, _VARIABLE_KEYS, where, entry)
    path = t.get("path")
    if not isinstance(path, str) or not path:
        raise InputError(f"{where}: {entry}: path = {short_repr(path)} must name an entry of "
                         f"the scene (e.g. \"mount.M5.k[2]\")")
    entry = f"variable {i} ({path})"
    tie, mirror = (_paths(t.get(k), where, entry, k) for k in ("tie", "mirror"))
    link = _links(t.get("link"), where, entry)
    start = t.get("start")
    if start is not None and (not is_finite_number(start) or isinstance(start, bool)):
        raise InputError(f"{where}: {entry}: start = {short_repr(start)} must be a finite "
                         f"number")
    if "values" in t:
        for key in ("low", "high"):
            if key in t:
                raise InputError(f"{where}: {entry}: give values (a catalogue) or low and "
                                 f"high, not both")
        values = t["values"]
        if (not isinstance(values, list) or len(values) < 2
                or not all(is_finite_number(v) and not isinstance(v, bool) for v in values)):
            raise InputError(f"{where}: {entry}: values = {short_repr(values)} must be a list "
                             f"of at least two finite numbers")
        values = tuple(sorted(float(v) for v in set(values)))
        return Variable(path, values[0], values[-1], values, start, tie, mirror, link)
    lo, hi = t.get("low"), t.get("high")
    for key, v in (("low", lo), ("high", hi)):
        if v is None or not is_finite_number(v) or isinstance(v, bool):
            raise InputError(f"{where}: {entry}: {key} = {short_repr(v)} must be a finite "
                             f"number (or give values = [...])")
    if not lo < hi:
        raise InputError(f"{where}: {entry}: low = {lo!r} must be below high = {hi!r}")
    if start is not None and not lo <= start <= hi:
        raise InputError(f"{where}: {entry}: start = {start!r} lies outside [{lo!r}, {hi!r}]")
    return Variable(path, float(lo), float(hi), None,
                    None if start is None else float(start), tie, mirror, link)


def _links(value: Any, where: str, entry: str) -> tuple:
    if value is None:
        return ()
    if not isinstance(value, list) or not all(isinstance(t, dict) for t in value):
        raise InputError(f"{where}: {entry}: link must be a list of tables {{path = ..., "
                         f"factor = ..., offset = ...}}")
    out = []
    for t in value:
        _known(t, ("path", "factor", "offset"), where, f"{entry}: link")
        p = t.get("path")
        if not isinstance(p, str) or not p:
            raise InputError(f"{where}: {entry}: link path = {short_repr(p)} must be a scene "
                             f"path")
        f, o = t.get("factor", 1.0), t.get("offset", 0.0)
        for key, v in (("factor", f), ("offset", o)):
            if not is_finite_number(v) or isinstance(v, bool):
                raise InputError(f"{where}: {entry}: link {p!r}: {key} = {short_repr(v)} must "
                                 f"be a finite number")
        out.append((p, float(f), float(o)))
    return tuple(out)


def _check_paths(where: str, variables: tuple) -> None:
    seen: dict = {}
    for v in variables:
        for p, _, _ in v.paths:
            if p in seen:
                raise InputError(f"{where}: path {p!r} is set by variable {seen[p]} and by "
                                 f"{v.path!r}")
            seen[p] = repr(v.path)


def _goal(where: str, role: str, i: int, t: dict) -> Goal:
    kind = t.get("kind")
    entry = f"{role} {i}"
    if not isinstance(kind, str) or not kind:
        raise InputError(f"{where}: {entry}: kind = {short_repr(kind)} must name a metric")
    entry = f"{role} {i} ({kind})"
    own = _GOAL_KEYS if role == "objective" else _CONSTRAINT_KEYS + ("reduce",)
    opts = {k: v for k, v in t.items() if k not in own and k != "kind"}
    got = {k: v for k, v in t.items() if k in own}
    reduce = got.get("reduce")
    if reduce is not None and reduce not in REDUCTIONS:
        raise InputError(f"{where}: {entry}: reduce = {short_repr(reduce)} must be one of "
                         f"{', '.join(REDUCTIONS)}")
    metric = MetricTable(index=i, kind=kind, options=tuple(opts.items()))
    if role == "objective":
        sense = got.get("sense", "minimize")
        if sense not in ("minimize", "maximize"):
            raise InputError(f"{where}: {entry}: sense = {short_repr(sense)} must be minimize "
                             f"or maximize")
        weight = got.get("weight", 1.0)
        if not is_finite_number(weight) or isinstance(weight, bool) or weight < 0:
            raise InputError(f"{where}: {entry}: weight = {short_repr(weight)} must be a "
                             f"number >= 0")
        scale = _positive(got.get("scale", 1.0), where, entry + ":", "scale")
        return Goal(metric, role, i, float(weight), sense, reduce, scale)
    lower, upper = got.get("lower"), got.get("upper")
    exc = got.get("excitation")
    if exc is not None:
        if upper is not None:
            raise InputError(f"{where}: {entry}: give upper or excitation (upper = "
                             f"excitation / sqrt(2)), not both")
        upper = _positive(exc, where, entry + ":", "excitation") / math.sqrt(2.0)
    for key, v in (("lower", lower), ("upper", upper)):
        if v is not None and (not is_finite_number(v) or isinstance(v, bool)):
            raise InputError(f"{where}: {entry}: {key} = {short_repr(v)} must be a finite "
                             f"number")
    if lower is None and upper is None:
        raise InputError(f"{where}: {entry}: give lower, upper or both (or excitation [Hz])")
    if lower is not None and upper is not None and not lower < upper:
        raise InputError(f"{where}: {entry}: lower = {lower!r} must be below upper = "
                         f"{upper!r}")
    return Goal(metric, role, i, reduce=reduce,
                lower=None if lower is None else float(lower),
                upper=None if upper is None else float(upper))

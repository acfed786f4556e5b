"""The study file (TOML) read into frozen dataclasses.

A study file names a base scene, the changes every point shares, the
parameters to vary (by their path in the scene, :mod:`flexbed.files.variants`),
how to sample them, the analyses and the metrics. See "Study file" in the
README for every key. This module checks the file's own shape (keys, types,
counts); :mod:`flexbed.study.plan` checks it against the scene. Errors are
one line naming the file, the entry and the value (InputError).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from flexbed.errors import InputError
from flexbed.files.destination import check_source
from flexbed.files.table_reader import is_finite_number

__all__ = ["Study", "Parameter", "MetricTable", "SAMPLINGS", "SCALES", "MAX_POINTS",
           "point_count", "read_study", "parse_study"]

SAMPLINGS = ("grid", "zip", "list", "lhs")
#: the most points one study may have: each is a scene checked and kept in
#: memory while the study plans (about 1 ms and tens of kB each), and a
#: solve of tens of ms on a worker; 10^5 points is hours on a laptop
MAX_POINTS = 100_000
SCALES = ("linear", "log")

_TOP = ("study", "parameter", "point", "metric")
_STUDY_KEYS = ("name", "scene", "sampling", "samples", "seed", "analyses", "set", "batch")
_PARAMETER_KEYS = ("path", "values", "from", "to", "num", "low", "high", "scale")


@dataclass(frozen=True, slots=True)
class Parameter:
    """One varied entry of the scene.

    path : str — e.g. ``"mount.M5.k"``; values : tuple or None — the values
    given one by one (grid, zip); low, high : number or tuple of numbers, or
    None — the ends of a range (``from``/``to`` with ``num`` for grid and
    zip, ``low``/``high`` for lhs; a vector entry moves along the segment
    between them); num : int or None; scale : "linear" or "log" (geometric
    spacing, both ends > 0).
    """

    path: str
    values: tuple | None = None
    low: Any = None
    high: Any = None
    num: int | None = None
    scale: str = "linear"


@dataclass(frozen=True, slots=True)
class MetricTable:
    """One ``[[metric]]`` table as written: ``kind`` and its other keys
    (checked by :mod:`flexbed.study.metrics`); ``index`` 1-based."""

    index: int
    kind: str
    options: tuple          # ((key, value), ...) in file order


@dataclass(frozen=True, slots=True)
class Study:
    """A study file, read.

    source : Path; name : str; scene : Path or None (None: the built-in
    scene); sampling : one of :data:`SAMPLINGS`; parameters : tuple of
    Parameter; points : tuple of ((path, value), ...) — ``[[point]]``
    tables (sampling "list"); samples : int or None (lhs); seed : int (lhs);
    fixed : ((path, value), ...) — ``[study.set]``, applied to every point;
    analyses : tuple of str or None (None: what the metrics need);
    metrics : tuple of MetricTable; batch : int or None — points per Dask
    task (None: chosen from the study's and the cluster's sizes, large
    batches first, single points last: :func:`flexbed.study.runner.auto_sizes`).
    """

    source: Path
    name: str
    scene: Path | None
    sampling: str
    parameters: tuple
    points: tuple
    samples: int | None
    seed: int
    fixed: tuple
    analyses: tuple | None
    metrics: tuple
    batch: int | None = None


def read_study(path: str | Path) -> Study:
    """Read and check a study file's shape."""
    path = check_source(path, "study file")
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(f"{path}: cannot read the study file ({exc.strerror or exc})") from None
    except UnicodeDecodeError:
        raise InputError(f"{path.name}: not a UTF-8 text file") from None
    return parse_study(text, path)


def parse_study(text: str, source: Path) -> Study:
    """Check a study given as TOML text; ``source`` names it in messages and
    is the folder a relative ``scene`` is found from."""
    source = Path(source)
    where = source.name
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{where}: not valid TOML: {exc}") from None
    _known(data, _TOP, where, "top level")
    head = data.get("study", {})
    if not isinstance(head, dict):
        raise InputError(f"{where}: [study] must be a table")
    _known(head, _STUDY_KEYS, where, "[study]")
    name = head.get("name", source.stem)
    if not isinstance(name, str) or not name:
        raise InputError(f"{where}: [study] name = {name!r} must be a non-empty string")
    scene = head.get("scene")
    if scene is not None:
        if not isinstance(scene, str) or not scene:
            raise InputError(f"{where}: [study] scene = {scene!r} must be a file name")
        scene = source.parent / scene
    sampling = head.get("sampling", "grid")
    if sampling not in SAMPLINGS:
        raise InputError(f"{where}: [study] sampling = {sampling!r} must be one of "
                         f"{', '.join(SAMPLINGS)}")
    samples = head.get("samples")
    if sampling == "lhs":
        if not _count(samples):
            raise InputError(f"{where}: [study] samples = {samples!r} must be an integer >= 1 "
                             f"(sampling = \"lhs\")")
    elif samples is not None:
        raise InputError(f"{where}: [study] samples applies to sampling = \"lhs\" only")
    seed = head.get("seed", 0)
    if isinstance(seed, bool) or not isinstance(seed, int) or seed < 0:
        raise InputError(f"{where}: [study] seed = {seed!r} must be an integer >= 0")
    analyses = head.get("analyses")
    if analyses is not None:
        if (not isinstance(analyses, list) or not analyses
                or not all(isinstance(a, str) for a in analyses)):
            raise InputError(f"{where}: [study] analyses = {analyses!r} must be a list of names")
        analyses = tuple(dict.fromkeys(analyses))
    batch = head.get("batch", "auto")
    if batch != "auto" and not _count(batch):
        raise InputError(f"{where}: [study] batch = {batch!r} must be an integer >= 1 (points "
                         f"per task) or \"auto\"")
    fixed = head.get("set", {})
    if not isinstance(fixed, dict):
        raise InputError(f"{where}: [study.set] must be a table of path = value")
    parameters = tuple(_parameter(where, i + 1, t, sampling)
                       for i, t in enumerate(_tables(data, "parameter", where)))
    points = tuple(_point(where, i + 1, t) for i, t in enumerate(_tables(data, "point", where)))
    _check_sampling(where, sampling, parameters, points)
    _check_size(where, sampling, parameters, len(points), samples)
    metrics = tuple(_metric(where, i + 1, t) for i, t in enumerate(_tables(data, "metric", where)))
    if not metrics:
        raise InputError(f"{where}: no [[metric]]: name at least one metric to keep")
    return Study(source=source, name=name, scene=scene, sampling=sampling,
                 parameters=parameters, points=points,
                 samples=samples if sampling == "lhs" else None, seed=seed,
                 fixed=tuple(fixed.items()), analyses=analyses, metrics=metrics,
                 batch=None if batch == "auto" else batch)


def _known(table: dict, keys: tuple, where: str, entry: str) -> None:
    for key in table:
        if key not in keys:
            raise InputError(f"{where}: {entry}: unknown key {key!r} (known: {', '.join(keys)})")


def _tables(data: dict, key: str, where: str) -> list:
    value = data.get(key, [])
    if not isinstance(value, list) or not all(isinstance(t, dict) for t in value):
        raise InputError(f"{where}: {key} must be an array of tables ([[{key}]])")
    return value


def _count(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value >= 1


def _number_or_vector(value: Any) -> bool:
    def number(x):
        return is_finite_number(x)
    return number(value) or (isinstance(value, list) and bool(value)
                             and all(number(x) for x in value))


def _parameter(where: str, i: int, t: dict, sampling: str) -> Parameter:
    entry = f"parameter {i}"
    _known(t, _PARAMETER_KEYS, where, entry)
    path = t.get("path")
    if not isinstance(path, str) or not path:
        raise InputError(f"{where}: {entry}: path = {path!r} must name an entry of the scene "
                         f"(e.g. \"mount.M5.k\")")
    entry = f"parameter {i} ({path})"
    scale = t.get("scale", "linear")
    if scale not in SCALES:
        raise InputError(f"{where}: {entry}: scale = {scale!r} must be one of "
                         f"{', '.join(SCALES)}")
    if sampling == "list":
        raise InputError(f"{where}: {entry}: sampling = \"list\" takes its points from "
                         f"[[point]] tables, not [[parameter]]")
    if sampling == "lhs":
        for key in ("values", "from", "to", "num"):
            if key in t:
                raise InputError(f"{where}: {entry}: {key} does not apply to sampling = "
                                 f"\"lhs\" (give low and high)")
        lo, hi = t.get("low"), t.get("high")
        _range_ends(where, entry, "low", "high", lo, hi, scale)
        return Parameter(path=path, low=lo, high=hi, scale=scale)
    for key in ("low", "high"):
        if key in t:
            raise InputError(f"{where}: {entry}: {key} applies to sampling = \"lhs\" "
                             f"(give values, or from, to and num)")
    if "values" in t:
        for key in ("from", "to", "num"):
            if key in t:
                raise InputError(f"{where}: {entry}: give values or from/to/num, not both")
        values = t["values"]
        if not isinstance(values, list) or not values:
            raise InputError(f"{where}: {entry}: values = {values!r} must be a non-empty list")
        return Parameter(path=path, values=tuple(values), scale=scale)
    lo, hi, num = t.get("from"), t.get("to"), t.get("num")
    if lo is None or hi is None or num is None:
        raise InputError(f"{where}: {entry}: give values, or from, to and num")
    _range_ends(where, entry, "from", "to", lo, hi, scale)
    if not _count(num):
        raise InputError(f"{where}: {entry}: num = {num!r} must be an integer >= 1")
    return Parameter(path=path, low=lo, high=hi, num=num, scale=scale)


def _range_ends(where, entry, klo, khi, lo, hi, scale) -> None:
    for key, v in ((klo, lo), (khi, hi)):
        if not _number_or_vector(v):
            raise InputError(f"{where}: {entry}: {key} = {v!r} must be a finite number or a "
                             f"list of them")
    if isinstance(lo, list) != isinstance(hi, list) or (
            isinstance(lo, list) and len(lo) != len(hi)):
        raise InputError(f"{where}: {entry}: {klo} = {lo!r} and {khi} = {hi!r} must have the "
                         f"same shape")
    if scale == "log":
        ends = (lo if isinstance(lo, list) else [lo]) + (hi if isinstance(hi, list) else [hi])
        if min(ends) <= 0:
            raise InputError(f"{where}: {entry}: scale = \"log\" needs {klo} and {khi} > 0 "
                             f"(got {lo!r}, {hi!r})")


def _point(where: str, i: int, t: dict) -> tuple:
    if not t:
        raise InputError(f"{where}: point {i}: empty (give path = value pairs)")
    return tuple(t.items())


def point_count(sampling: str, parameters, n_points: int, samples: int | None) -> int:
    """The number of points a study's sampling makes (exact; before any is
    made)."""
    if sampling == "list":
        return n_points
    if sampling == "lhs":
        return samples if parameters else 1
    sizes = [len(p.values) if p.values is not None else p.num for p in parameters]
    if sampling == "zip":
        return min(sizes) if sizes else 1
    return math.prod(sizes)


def _check_size(where, sampling, parameters, n_points, samples) -> None:
    n = point_count(sampling, parameters, n_points, samples)
    if n > MAX_POINTS:
        shown = f"{n:,}" if n < 10 ** 15 else f"about 10^{len(str(n)) - 1}"
        raise InputError(f"{where}: the study has {shown} points; the limit is {MAX_POINTS:,} "
                         f"(split it, or sample it: sampling = \"lhs\")")


def _check_sampling(where, sampling, parameters, points) -> None:
    if sampling == "list":
        if not points:
            raise InputError(f"{where}: sampling = \"list\" needs [[point]] tables")
        first = [k for k, _ in points[0]]
        for i, p in enumerate(points[1:], start=2):
            keys = [k for k, _ in p]
            if sorted(keys) != sorted(first):
                raise InputError(f"{where}: point {i}: sets {', '.join(keys)}; every point "
                                 f"must set the same paths as point 1 ({', '.join(first)})")
        return
    if points:
        raise InputError(f"{where}: [[point]] tables need sampling = \"list\" "
                         f"(sampling is {sampling!r})")
    paths = [p.path for p in parameters]
    for p in parameters:
        if paths.count(p.path) > 1:
            raise InputError(f"{where}: parameter {p.path!r} is given twice")
    if sampling == "zip" and parameters:
        sizes = {p.path: (len(p.values) if p.values is not None else p.num) for p in parameters}
        if len(set(sizes.values())) > 1:
            raise InputError(f"{where}: sampling = \"zip\" pairs the parameters' values one to "
                             f"one, but their counts differ: "
                             f"{', '.join(f'{k} {v}' for k, v in sizes.items())}")


def _metric(where: str, i: int, t: dict) -> MetricTable:
    kind = t.get("kind")
    if not isinstance(kind, str) or not kind:
        raise InputError(f"{where}: metric {i}: kind = {kind!r} must name a metric")
    return MetricTable(index=i, kind=kind, options=tuple((k, v) for k, v in t.items()
                                                          if k != "kind"))

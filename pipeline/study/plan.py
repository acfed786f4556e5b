"""A study checked as a whole before anything runs: the base scene, every
parameter path, every point's scene (built and checked as a scene file is),
the analyses and the metrics. Every refusal is one line naming the study
file and the entry.

Each point is keyed by its scene's hash (``SceneFile.digest``): two points
with the same scene are one computation, and a re-run skips the keys its
table already holds (with the same analyses and metrics: the plan's
``signature``).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from dataclasses import dataclass
from typing import Any

from flexbed.errors import InputError
from flexbed.files.scene import SceneFile, load_scene
from flexbed.files.variants import vary
from flexbed.study.analyses import ANALYSES, ordered
from flexbed.study.metrics import build_metric
from flexbed.study.samplers import points as sample_points
from flexbed.study.spec import Study

__all__ = ["Plan", "PlannedPoint", "ParameterColumn", "make_plan", "modes_scene"]


@dataclass(frozen=True)
class ParameterColumn:
    """One column of the table for a parameter: ``path``, ``component``
    (index into a vector entry, or None), ``numeric``."""

    name: str
    path: str
    component: int | None
    numeric: bool


@dataclass(frozen=True)
class PlannedPoint:
    """index : int (0-based, the study's order); values : dict path → value;
    scene : SceneFile (the variant, checked); key : str (its scene hash);
    modes_key : str or None (the plate request whose modes it needs)."""

    index: int
    values: dict
    scene: SceneFile
    key: str
    modes_key: str | None


@dataclass(frozen=True)
class Plan:
    """A study ready to run.

    study : Study; base : SceneFile; analyses : tuple of str (in run
    order); metrics : tuple of metric objects; points : tuple of
    PlannedPoint; parameter_columns : tuple of ParameterColumn;
    signature : str (hash of the analyses and metrics).
    """

    study: Study
    base: SceneFile
    analyses: tuple
    metrics: tuple
    points: tuple
    parameter_columns: tuple
    signature: str

    @property
    def metric_columns(self) -> tuple:
        return tuple(c for m in self.metrics for c in m.columns)

    @property
    def metric_units(self) -> tuple:
        return tuple(u for m in self.metrics for u in m.units)

    def parameter_row(self, values: dict) -> tuple:
        """A point's values as the table's parameter cells."""
        return tuple(values[c.path] if c.component is None else values[c.path][c.component]
                     for c in self.parameter_columns)


def modes_scene(scene: SceneFile) -> SceneFile:
    """The scene with its bed flexible (the one whose modes ``compare`` needs)."""
    if scene.bed.flexible:
        return scene
    return dataclasses.replace(scene, bed=dataclasses.replace(scene.bed, model="flexible"))


def _modes_key(scene: SceneFile) -> str:
    from flexbed.api.bed_modes import modes_request
    return hashlib.sha256(repr(modes_request(modes_scene(scene))).encode()).hexdigest()[:16]


def _plain(value: Any) -> Any:
    return value.tolist() if hasattr(value, "tolist") else value


def make_plan(study: Study, progress=None) -> Plan:
    """Check the study against its scene; build every point's scene.

    ``progress(i, n)``, optional, is called after each of the ``n`` points'
    scenes is built (a few ms a point: a large study takes seconds to plan).

    Raises InputError (one line naming the study file, the entry and the
    value) on an unknown parameter path, analysis or metric, a metric
    naming no body, mount or point of the scene, or a point whose scene
    the scene file's rules refuse.
    """
    where = study.source.name
    base = load_scene(study.scene)
    fixed = dict(study.fixed)
    if fixed:
        try:
            base = vary(base, fixed)
        except InputError as exc:
            raise InputError(f"{where}: [study.set]: {exc}") from None
    metrics = tuple(build_metric(t, base, where) for t in study.metrics)
    columns = [c for m in metrics for c in m.columns]
    for c in columns:
        if columns.count(c) > 1:
            raise InputError(f"{where}: two metrics make the column {c!r}; give one a name")
    needed = {m.analysis for m in metrics}
    if study.analyses is not None:
        for name in study.analyses:
            if name not in ANALYSES:
                raise InputError(f"{where}: [study] analyses: unknown analysis {name!r} "
                                 f"(known: {', '.join(ANALYSES)})")
        missing = sorted(needed - set(study.analyses))
        if missing:
            raise InputError(f"{where}: [study] analyses = {list(study.analyses)!r} lacks "
                             f"{', '.join(missing)}, which the metrics need")
        needed |= set(study.analyses)
    analyses = ordered(needed)
    raw = sample_points(study)
    # every path alone first, so an unknown one is named plainly
    for path, value in raw[0].items():
        try:
            vary(base, {path: value})
        except InputError as exc:
            raise InputError(f"{where}: parameter {path!r}: {exc}") from None
    pcols = _parameter_columns(where, raw)
    flexible = any(ANALYSES[a].needs_bed_modes for a in analyses)
    planned = []
    for i, values in enumerate(raw):
        values = {k: _plain(v) for k, v in values.items()}
        try:
            scene = vary(base, values) if values else base
        except InputError as exc:
            shown = ", ".join(f"{k} = {v!r}" for k, v in values.items())
            raise InputError(f"{where}: point {i} ({shown}): {exc}") from None
        needs_modes = scene.bed.flexible or flexible
        planned.append(PlannedPoint(i, values, scene, scene.digest,
                                    _modes_key(scene) if needs_modes else None))
        if progress is not None:
            progress(i + 1, len(raw))
    signature = hashlib.sha256(json.dumps(
        {"analyses": analyses, "metrics": [[t.kind, list(map(list, t.options))]
                                           for t in study.metrics]},
        sort_keys=True, default=str).encode()).hexdigest()[:16]
    return Plan(study, base, analyses, metrics, tuple(planned), tuple(pcols), signature)


def _parameter_columns(where: str, raw: list[dict]) -> list[ParameterColumn]:
    cols = []
    for path, first in raw[0].items():
        shape = len(first) if isinstance(first, list) else None
        for i, values in enumerate(raw):
            v = values[path]
            if (len(v) if isinstance(v, list) else None) != shape:
                raise InputError(f"{where}: parameter {path!r}: value {v!r} of point {i} has "
                                 f"another shape than {first!r}")
        if shape is None:
            numeric = all(isinstance(p[path], (int, float)) and not isinstance(p[path], bool)
                          for p in raw)
            cols.append(ParameterColumn(path, path, None, numeric))
        else:
            for j in range(shape):
                numeric = all(isinstance(p[path][j], (int, float))
                              and not isinstance(p[path][j], bool) for p in raw)
                cols.append(ParameterColumn(f"{path}[{j}]", path, j, numeric))
    return cols

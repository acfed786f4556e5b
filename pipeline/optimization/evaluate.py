"""Evaluations of an optimisation: many points at once on the Dask engine,
each logged, none computed twice.

A batch of points (a finite-difference stencil, a population) is split
into one task per worker and run with the study's own worker function
(:func:`flexbed.study.point.run_batch`), so a point's numbers are those a
``flexbed sweep`` of the same scene gives. A point is keyed by its scene's
hash: a point met again — in this run or in the log of an earlier one with
the same signature (``evaluations.csv``) — is not computed again. A
flexible bed's modes are computed once per plate (its modes request) and
shared by every point whose variables leave the bed alone.

The log, ``evaluations.csv``: one line per point computed, appended and
flushed as the results come (an interrupted run keeps what it computed):
``evaluation`` (1-based), ``status``, ``objective``, ``violation`` (the
largest constraint violation, a share of its bound, 0 when feasible), the
variables (scene units), the metric columns, ``message``,
``scene_hash``, ``signature``, ``solve_time`` [s].
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from flexbed.api.bed_modes import modes_request
from flexbed.errors import InputError, one_line
from flexbed.optimization.problem import FAILED_CONSTRAINT, FAILED_OBJECTIVE, Problem
from flexbed.study.plan import modes_scene
from flexbed.study.point import PointResult, bed_modes, pack, run_batch

__all__ = ["Evaluation", "Evaluator", "LOG"]

LOG = "evaluations.csv"


@dataclass(frozen=True)
class Evaluation:
    """One point: x (n,) [scene units]; key : str (scene hash); result :
    PointResult; objective : float; constraints : (c,) margins (≥ 0 hold);
    number : int (1-based, in the log; 0 for a point read from an earlier
    log)."""

    x: np.ndarray
    key: str
    result: PointResult
    objective: float
    constraints: np.ndarray
    number: int

    @property
    def ok(self) -> bool:
        return self.result.status == "ok"

    @property
    def violation(self) -> float:
        """The largest violation (a share of its bound), 0 when all hold."""
        return float(max(0.0, -self.constraints.min())) if self.constraints.size else 0.0

    @property
    def feasible(self) -> bool:
        return self.ok and self.violation <= 1e-9


class Evaluator:
    """Evaluates points of ``problem`` on ``client``, logging into
    ``folder`` (None: no log).

    ``evaluations`` counts the points computed in this run, ``reused``
    those found in the cache or the log; ``history`` holds every
    evaluation in order.
    """

    def __init__(self, problem: Problem, client, folder: Path | None):
        self.problem, self.client, self.folder = problem, client, folder
        self.cache: dict[str, Evaluation] = {}
        self.history: list[Evaluation] = []
        self.evaluations = self.reused = 0
        self._modes: dict = {}
        self._setup = pack((problem.analyses, problem.metrics, False))
        self._workers = max(1, len(client.scheduler_info().get("workers", {})))
        self._header = (["evaluation", "status", "objective", "violation"]
                        + [v.path for v in problem.variables] + list(problem.columns)
                        + ["message", "scene_hash", "signature", "solve_time"])
        if folder is not None:
            self._read_log(folder / LOG)

    # ------------------------------------------------------------------ log
    def _read_log(self, path: Path) -> None:
        if not path.is_file():
            return
        with path.open(newline="", encoding="utf-8") as fh:
            rows = list(csv.reader(fh))
        if not rows or rows[0] != self._header:
            raise InputError(f"{path}: a log of another optimisation (its columns differ): "
                             f"write elsewhere (-o) or remove it")
        n_var, n_col = self.problem.n, len(self.problem.columns)
        for row in rows[1:]:
            if len(row) != len(self._header) or row[-2] != self.problem.signature:
                continue                                # a line cut short, or another setting
            x = np.array([float(v) for v in row[4:4 + n_var]])
            values = tuple(float(v) for v in row[4 + n_var:4 + n_var + n_col])
            res = PointResult(row[1], row[-4], values, float(row[-1]), float("nan"))
            self.cache[row[-3]] = self._score(x, row[-3], res, 0)
        self.evaluations = len(rows) - 1

    def _write(self, ev: Evaluation) -> None:
        if self.folder is None:
            return
        path = self.folder / LOG
        new = not path.is_file()
        if new:
            self.folder.mkdir(parents=True, exist_ok=True)
        with path.open("a", newline="", encoding="utf-8") as fh:
            w = csv.writer(fh)
            if new:
                w.writerow(self._header)
            w.writerow([ev.number, ev.result.status, repr(ev.objective), repr(ev.violation)]
                       + [repr(float(v)) for v in ev.x] + [repr(v) for v in ev.result.values]
                       + [ev.result.message, ev.key, self.problem.signature,
                          repr(ev.result.solve_time)])

    # ---------------------------------------------------------- evaluation
    def _score(self, x, key, res: PointResult, number: int) -> Evaluation:
        p = self.problem
        if res.status == "ok":
            f, c = p.objective(res.values), p.constraints(res.values)
        else:
            f = FAILED_OBJECTIVE
            c = np.full(p.constraints(np.zeros(len(p.columns))).size, FAILED_CONSTRAINT)
        return Evaluation(np.asarray(x, dtype=float), key, res, f, c, number)

    def _modes_for(self, scene):
        if not scene.bed.flexible:
            return None
        key = repr(modes_request(modes_scene(scene)))
        if key not in self._modes:
            self._modes[key] = self.client.submit(bed_modes, scene, pure=False)
        return self._modes[key]

    def many(self, xs) -> list[Evaluation]:
        """Evaluate the points ``xs`` (each (n,) [scene units]) in parallel;
        the same scene twice is computed once."""
        scenes, keys = [], []
        for x in xs:
            scene = self.problem.scene(x)
            scenes.append(scene)
            keys.append(scene.digest)
        todo = {}
        for x, scene, key in zip(xs, scenes, keys):
            if key not in self.cache and key not in todo:
                todo[key] = (x, scene)
        if todo:
            self._run(todo)
        out = []
        for key in keys:
            out.append(self.cache[key])
        self.reused += len(keys) - len(todo)
        self.history.extend(out)
        return out

    def one(self, x) -> Evaluation:
        return self.many([x])[0]

    def _run(self, todo: dict) -> None:
        items = list(todo.items())
        by_modes: dict = {}
        for key, (_, scene) in items:
            by_modes.setdefault(id(self._modes_for(scene)), []).append(key)
        groups = []
        for keys in by_modes.values():
            size = max(1, math.ceil(len(keys) / self._workers))
            groups += [keys[i:i + size] for i in range(0, len(keys), size)]
        futures = self.client.map(
            run_batch, [[pack(todo[k][1]) for k in keys] for keys in groups],
            [self._setup] * len(groups), [self._modes_for(todo[keys[0]][1]) for keys in groups],
            pure=False)
        for keys, fut in zip(groups, futures):
            try:
                results = fut.result()
            except Exception as exc:                    # a worker lost, every retry
                results = [PointResult("failed", one_line(exc),
                                       (float("nan"),) * len(self.problem.columns),
                                       float("nan"), float("nan"))] * len(keys)
            for key, res in zip(keys, results):
                self.evaluations += 1
                ev = self._score(todo[key][0], key, res, self.evaluations)
                self.cache[key] = ev
                self._write(ev)

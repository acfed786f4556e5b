"""The study's table: one row per point — ``point`` (its index in the
study), the parameters (a vector entry as one column per component,
``mount.M5.k[0]`` …), the metrics, ``status`` ("ok" or "failed"),
``message``, ``solve_time`` and ``cpu_time`` [s] on the worker and
``scene_hash`` (the point's key) — as CSV (``table.csv``) and HDF5
(``table.h5``, schema ``flexbed.study``), both written atomically.

HDF5 layout: a dataset per column under ``table/`` (its name, with any
"/" written as "|"; a ``units`` attribute each; parameters' units are those
of the scene file, SI); at the root ``study``, ``study_file``, ``complete``
(False while running or after an interrupt), ``points_planned``,
``points_done``, ``signature`` (the analyses and metrics it holds),
``columns``, ``parameters``, ``metrics`` and ``analyses`` (JSON lists of
names). CSV: the same
columns, a header of names with the metrics' units in brackets, floats
written exactly (shortest repr) so that they read back bit for bit.
"""

from __future__ import annotations

import csv
import io
import json
import fcntl
import math
import os
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

import numpy as np

from flexbed.errors import InputError, os_error_text
from flexbed.files.destination import check_destination, write_text

__all__ = ["Row", "StudyTable", "build_table", "write_table", "read_done", "check_folder",
           "folder_lock", "LOCK",
           "SCHEMA"]

SCHEMA = "flexbed.study"
VERSION = "1.0"
_TAIL = (("status", ""), ("message", ""), ("solve_time", "s"), ("cpu_time", "s"),
         ("scene_hash", ""))


@dataclass(frozen=True)
class Row:
    """One finished point: index, parameters (cells), values (metric cells),
    status, message, solve_time [s], cpu_time [s], scene_hash."""

    index: int
    parameters: tuple
    values: tuple
    status: str
    message: str
    solve_time: float
    cpu_time: float
    scene_hash: str


@dataclass(frozen=True)
class StudyTable:
    """A study's results: ``table["peak_mount_force.M5"]`` is a column
    (ndarray, one entry per finished point, in the study's order).

    name : str; columns : dict name → ndarray; units : dict name → str;
    parameters, metrics : tuple of column names; complete : bool (every
    planned point has its row); planned : int; folder : Path or None
    (where the table files are).
    """

    name: str
    columns: dict
    units: dict
    parameters: tuple
    metrics: tuple
    complete: bool
    planned: int
    folder: Path | None = None

    def __getitem__(self, column: str) -> np.ndarray:
        try:
            return self.columns[column]
        except KeyError:
            raise InputError(f"study {self.name!r}: no column {column!r} (columns: "
                             f"{', '.join(self.columns)})") from None

    def __len__(self) -> int:
        return len(self.columns["point"])

    @property
    def ok(self) -> np.ndarray:
        """(n,) bool: the rows whose point succeeded."""
        return self.columns["status"] == "ok"

    def rows(self) -> list[dict]:
        """The rows as dicts column → value."""
        names = list(self.columns)
        return [{k: self.columns[k][i].item() if hasattr(self.columns[k][i], "item")
                 else self.columns[k][i] for k in names} for i in range(len(self))]

    def csv(self) -> str:
        """The table as CSV text (see the module)."""
        buf = io.StringIO()
        w = csv.writer(buf, lineterminator="\n")
        w.writerow([f"{k} [{self.units[k]}]" if k in self.metrics and self.units[k] else k
                    for k in self.columns])
        for i in range(len(self)):
            w.writerow([_cell(self.columns[k][i]) for k in self.columns])
        return buf.getvalue()


def _cell(v) -> str:
    if isinstance(v, (float, np.floating)):
        return "nan" if math.isnan(v) else repr(float(v))
    if isinstance(v, (np.integer,)):
        return str(int(v))
    return str(v)


def _column(values: list) -> np.ndarray:
    if all(isinstance(v, (int, float, np.number)) and not isinstance(v, bool) for v in values):
        if all(isinstance(v, (int, np.integer)) for v in values):
            return np.array(values, dtype=np.int64)
        return np.array(values, dtype=float)
    return np.array([str(v) for v in values], dtype=object)


def build_table(plan, rows: dict, complete: bool, folder: Path | None = None) -> StudyTable:
    """The table of ``rows`` (dict point index → Row) of ``plan``."""
    order = sorted(rows)
    cols: dict = {"point": np.array(order, dtype=np.int64)}
    units: dict = {"point": ""}
    for j, c in enumerate(plan.parameter_columns):
        cols[c.name] = _column([rows[i].parameters[j] for i in order]) if order else \
            np.zeros(0)
        units[c.name] = "scene"
    for j, (name, unit) in enumerate(zip(plan.metric_columns, plan.metric_units)):
        cols[name] = np.array([rows[i].values[j] for i in order], dtype=float)
        units[name] = unit
    for name, unit in _TAIL:
        vals = [getattr(rows[i], name) for i in order]
        cols[name] = np.array(vals, dtype=float) if unit else np.array(vals, dtype=object)
        units[name] = unit
    return StudyTable(plan.study.name, cols, units,
                      tuple(c.name for c in plan.parameter_columns), plan.metric_columns,
                      complete, len(plan.points), folder)


def check_folder(folder) -> Path:
    """``folder`` as a Path if a study may write there (absent, or a folder
    whose ``table.csv`` and ``table.h5`` are absent or regular files); else
    InputError naming it. Checked before anything runs."""
    folder = Path(folder)
    if folder.exists() and not folder.is_dir():
        raise InputError(f"{folder}: is not a folder; a study writes its table, plots and "
                         f"results into a folder (choose another name)")
    for name in ("table.csv", "table.h5"):
        check_destination(folder / name)
    return folder


#: the lock file a running study holds in its folder
LOCK = ".flexbed-study.lock"


@contextmanager
def folder_lock(folder: Path) -> Iterator[None]:
    """Hold ``folder`` for one study while it runs: an exclusive ``flock`` on
    ``folder/.flexbed-study.lock`` (created with the folder if need be; it
    holds the process id). A second study into the same folder at the same
    time is refused with InputError naming the process that holds it; the
    lock goes when the study ends or its process dies."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd = os.open(folder / LOCK, os.O_RDWR | os.O_CREAT, 0o666)
    except OSError as exc:
        raise InputError(f"{folder}: cannot write in it ({os_error_text(exc)})") from None
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            holder = os.pread(fd, 32, 0).decode(errors="replace").strip() or "?"
            raise InputError(f"{folder}: another study is writing into this folder now "
                             f"(process {holder}); wait for it to end, or choose another "
                             f"folder (-o)") from None
        os.ftruncate(fd, 0)
        os.pwrite(fd, f"{os.getpid()}\n".encode(), 0)
        yield
    finally:
        os.close(fd)                        # releases the lock


def _dataset_name(column: str) -> str:
    return "table/" + column.replace("/", "|")


def write_table(table: StudyTable, plan, folder: Path) -> tuple[Path, Path]:
    """Write ``table.csv`` and ``table.h5`` into ``folder`` (atomically)."""
    from flexbed.files.store import Dataset, write_file

    # the pair is written whole or not at all: the CSV under a staging name
    # first, then the HDF5 file; the CSV takes its name only when both are in
    csv_path = folder / "table.csv"
    staged = write_text(folder / ".table.csv.staged", table.csv())
    datasets = {}
    for name, values in table.columns.items():
        data = values if values.dtype != object else values.astype(str)
        datasets[_dataset_name(name)] = Dataset(data, table.units[name] or "",
                                                missing=name in table.metrics
                                                or name in ("solve_time", "cpu_time"))
    attrs = {"": {"study": table.name, "study_file": str(plan.study.source),
                  "complete": bool(table.complete), "points_planned": int(table.planned),
                  "points_done": int(len(table)), "signature": plan.signature,
                  "columns": json.dumps(list(table.columns)),
                  "parameters": json.dumps(list(table.parameters)),
                  "metrics": json.dumps(list(table.metrics)),
                  "analyses": json.dumps(list(plan.analyses))}}
    try:
        h5 = write_file(folder / "table.h5", schema=SCHEMA, version=VERSION,
                        datasets=datasets, attrs=attrs)
        os.replace(staged, csv_path)
    except BaseException:
        staged.unlink(missing_ok=True)
        raise
    return csv_path, h5


def read_done(folder: Path, plan, log=None) -> dict:
    """The rows a previous run of this study left in ``folder/table.h5``,
    by scene hash: dict key → (status, message, values, solve_time,
    cpu_time). Empty when there is no table, or it holds other analyses
    or metrics (``log`` is told why)."""
    from flexbed.files.store import read_file

    path = folder / "table.h5"
    if not path.exists():
        return {}
    c = read_file(path, schema=SCHEMA, major=1)
    root = c.attrs.get("", {})
    theirs = (root.get("study"), json.loads(root.get("parameters", "[]")))
    ours = (plan.study.name, [p.name for p in plan.parameter_columns])
    if theirs != ours:
        raise InputError(f"{folder}: holds the table of another study ({theirs[0]!r}, "
                         f"parameters {', '.join(theirs[1]) or 'none'}); a study writes into "
                         f"a folder of its own: choose another (-o), or remove that table")
    if root.get("signature") != plan.signature:
        raise InputError(f"{folder}: holds this study's table made with other analyses or "
                         f"metrics ({root.get('metrics', '?')}); choose another folder (-o), "
                         f"or remove that table to run every point again")
    names = list(plan.metric_columns)

    def col(name):
        return np.atleast_1d(c.get(_dataset_name(name)))

    keys = col("scene_hash")
    status, message = col("status"), col("message")
    wall, cpu = col("solve_time"), col("cpu_time")
    metric = [col(n) for n in names]
    return {str(keys[i]): (str(status[i]), str(message[i]),
                           tuple(float(m[i]) for m in metric), float(wall[i]), float(cpu[i]))
            for i in range(keys.size)}

"""The scene file (TOML, see "Scene file reference" in README.md) read into frozen dataclasses.

:func:`load_scene` returns a :class:`SceneFile`: the dynamics
:class:`~flexbed.dynamics.scene.Scene`, the ``[bed]`` section, the solver settings,
the points of interest, the source and the hashes. Every unknown key is an
error; every error is one line naming the file, the entry and the value,
raised as :class:`~flexbed.errors.InputError`.

Without a path the built-in reference scene (``pipeline/scenes/lee1999.toml``)
is read.
"""

from __future__ import annotations

import hashlib
import json
import math
import tomllib
from dataclasses import dataclass, replace
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np

from flexbed.dynamics.errors import SceneError
from flexbed.dynamics.integrate import METHODS, Settings
from flexbed.dynamics.laws import CurveLaw, LinearLaw, PolynomialLaw
from flexbed.dynamics.rotation import A as rotation_matrix
from flexbed.dynamics.rotation import p_from_angles
from flexbed.dynamics.scene import DIRECTIONS, Base, Body, Drive, Load, Mount, Scene
from flexbed.dynamics.shapes import Curve, Sinusoid, Trapezoid, Triangle, sampled

from flexbed.files.bed_section import BedSection, read_bed
from flexbed.errors import InputError

__all__ = ["SceneFile", "SolverSection", "PointOfInterest", "load_scene", "builtin_scene_path",
           "BUILTIN"]

BUILTIN = "lee1999.toml"

_TOP = ("scene", "body", "base", "bed", "mount", "solver", "point")
_SCENE_KEYS = ("name", "description", "gravity")
_BODY_KEYS = ("name", "mass", "inertia", "position", "orientation_deg")
_BASE_KEYS = ("motion", "support", "drive", "force")
_SHAPE_KEYS = {
    "sinusoid": ("amplitude", "frequency", "phase_deg", "start", "duration"),
    "triangle": ("peak", "start", "rise", "fall"),
    "trapezoid": ("peak", "start", "rise", "flat", "fall"),
    "curve": ("time", "value", "file"),
}
_ALL_SHAPE_KEYS = ("direction", "shape", "sample") + tuple(
    sorted({k for v in _SHAPE_KEYS.values() for k in v}))
_MOUNT_KEYS = ("name", "body_i", "body_j", "point_i", "point_j", "axes_deg", "axes", "law",
               "k", "c", "stiffness", "damping", "spring_curve", "damper_curve")
_LAW_KEYS = {"linear": ("k", "c"), "polynomial": ("stiffness", "damping"),
             "curve": ("spring_curve", "damper_curve")}
_SOLVER_KEYS = ("t_end", "integrator", "dt", "rtol", "atol", "output_dt", "start", "static_tol",
                "model", "linear_tol")
MODELS = ("nonlinear", "linear", "auto")
_POINT_KEYS = ("name", "body", "position", "relative_to")


@dataclass(frozen=True, slots=True)
class SolverSection:
    """``[solver]``: see the README. Times [s], tolerances as stated there."""

    t_end: float = 3.0
    integrator: str = "auto"
    dt: float = 1e-3
    rtol: float = 1e-8
    atol: float = 1e-10
    output_dt: float = 1e-3
    start: str = "equilibrium"
    static_tol: float = 1e-6
    model: str = "nonlinear"
    linear_tol: float = 1e-6

    def settings(self, **overrides) -> Settings:
        """Integration settings, with command-line overrides (None = keep)."""
        args = dict(method=self.integrator, t_end=self.t_end, dt=self.dt, rtol=self.rtol,
                    atol=self.atol, output_dt=self.output_dt)
        args.update({k: v for k, v in overrides.items() if v is not None})
        return Settings(**args)


@dataclass(frozen=True, slots=True)
class PointOfInterest:
    """``[[point]]``: a point of a body [m, body frame], optionally relative to another body."""

    name: str
    body: str
    position: tuple
    relative_to: str | None = None


@dataclass(frozen=True, slots=True)
class SceneFile:
    """A scene file, read and checked.

    scene : Scene; bed : BedSection; solver : SolverSection; points : tuple
    of PointOfInterest; source : Path; text : str (the TOML as read);
    digest : str (sha256 of the canonical JSON of the parsed data plus the
    referenced CSV files); statics_digest : str (the same over only what the
    static equilibrium depends on: gravity, bodies, mounts, bed and
    static_tol).
    """

    scene: Scene
    bed: BedSection
    solver: SolverSection
    points: tuple
    source: Path
    text: str
    digest: str
    statics_digest: str


def builtin_scene_path() -> Path:
    """Path of the built-in reference scene."""
    return Path(str(resources.files("flexbed") / "scenes" / BUILTIN))


def load_scene(path: str | Path | None = None) -> SceneFile:
    """Read and check a scene file (the built-in reference scene if path is None)."""
    path = builtin_scene_path() if path is None else Path(path)
    label = path.name
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: cannot read the scene file ({exc.strerror or exc})") from None
    try:
        text = raw.decode("utf-8")
        data = tomllib.loads(text)
    except UnicodeDecodeError:
        raise InputError(f"{label}: not a UTF-8 text file") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{label}: not valid TOML: {exc}") from None
    reader = _Reader(label, path.parent)
    return reader.read(data, path, text)


# ----------------------------------------------------------------- helpers
def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


class _Reader:
    def __init__(self, label: str, folder: Path):
        self.label = label
        self.folder = folder
        self.csv: dict[str, str] = {}

    # errors ------------------------------------------------------------
    def fail(self, where: str, msg: str):
        raise InputError(f"{self.label}: {where}: {msg}" if where else f"{self.label}: {msg}")

    def keys(self, where: str, table: Any, allowed: tuple, required: tuple = ()) -> dict:
        if not isinstance(table, dict):
            self.fail(where, f"must be a table, got {table!r}")
        for key in table:
            if key not in allowed:
                self.fail(where, f"unknown key '{key}' (known: {', '.join(allowed)})")
        for key in required:
            if key not in table:
                self.fail(where, f"'{key}' is required")
        return table

    # values ------------------------------------------------------------
    def number(self, where, key, value, *, positive=False, non_negative=False) -> float:
        if not _is_number(value):
            self.fail(where, f"{key} = {value!r} must be a number")
        v = float(value)
        if not math.isfinite(v):
            self.fail(where, f"{key} = {v!r} must be finite")
        if positive and not v > 0:
            self.fail(where, f"{key} = {v!r} must be > 0")
        if non_negative and v < 0:
            self.fail(where, f"{key} = {v!r} must be >= 0")
        return v

    def numbers(self, where, key, value, n=None, *, positive=False, non_negative=False,
                min_len=1) -> list[float]:
        if not isinstance(value, list):
            self.fail(where, f"{key} = {value!r} must be a list of numbers")
        if n is not None and len(value) != n:
            self.fail(where, f"{key} = {value!r} must have {n} numbers, has {len(value)}")
        if len(value) < min_len:
            self.fail(where, f"{key} has {len(value)} numbers, needs at least {min_len}")
        return [self.number(where, f"{key}[{i}]", v, positive=positive, non_negative=non_negative)
                for i, v in enumerate(value)]

    def string(self, where, key, value, choices=None) -> str:
        if not isinstance(value, str):
            self.fail(where, f"{key} = {value!r} must be a string")
        if choices is not None and value not in choices:
            self.fail(where, f"{key} = {value!r} must be one of {', '.join(map(repr, choices))}")
        return value

    def tables(self, where, value) -> list:
        if not isinstance(value, list) or not all(isinstance(v, dict) for v in value):
            self.fail("", f"{where} must be an array of tables ([[{where}]])")
        return value

    # sections ----------------------------------------------------------
    def read(self, data: dict, path: Path, text: str) -> SceneFile:
        self.keys("", data, _TOP)
        sc = self.keys("scene", data.get("scene", {}), _SCENE_KEYS)
        name = self.string("scene", "name", sc["name"]) if "name" in sc else path.stem
        if "description" in sc:
            self.string("scene", "description", sc["description"])
        gravity = (self.numbers("scene", "gravity", sc["gravity"], 3) if "gravity" in sc
                   else [0.0, 0.0, -9.81])
        bodies_raw = self.tables("body", data.get("body", []))
        if not bodies_raw:
            self.fail("", "no [[body]] tables: body 1, the base, is required")
        bodies = [self.body(i, b) for i, b in enumerate(bodies_raw)]
        names = [b.name for b in bodies]
        base = self.base(data.get("base", {}))
        mounts = [self.mount(i, m, names) for i, m in enumerate(self.tables("mount", data.get("mount", [])))]
        bed = read_bed(data.get("bed", {}), f"{self.label}: bed")
        if bed.body is not None and bed.body not in names:
            self.fail("bed", f"body = {bed.body!r} is not a body (bodies: {', '.join(names)})")
        solver = self.solver(data.get("solver", {}))
        points = self.points(data.get("point", []), names)
        try:
            scene = Scene(tuple(bodies), base, tuple(mounts), np.array(gravity), name)
        except SceneError as exc:
            self.fail("", str(exc))
        if bed.auto == ():
            bed = self.resolve_auto_modes(scene, bed, solver)
        digest = _digest(data, self.csv)
        statics = {"gravity": gravity, "body": data.get("body"), "mount": data.get("mount", []),
                   "bed": data.get("bed", {}), "static_tol": solver.static_tol}
        return SceneFile(scene=scene, bed=bed, solver=solver, points=tuple(points),
                         source=path, text=text, digest=digest,
                         statics_digest=_digest(statics, {}))

    def resolve_auto_modes(self, scene: Scene, bed: BedSection, solver) -> BedSection:
        """``[bed] modes = "auto"`` → fmax = f_cut (see :mod:`flexbed.stages.modes_auto`)."""
        from flexbed.stages.modes_auto import cutoff
        try:
            f_cut, f_in, f_sus = cutoff(scene, solver.t_end, bed.auto_factor, solver.static_tol)
        except RuntimeError as exc:
            self.fail("bed", f"modes = \"auto\" needs the static equilibrium with a rigid "
                             f"bed: {exc}")
        return replace(bed, fmax=float(f_cut), auto=(float(f_cut), f_in, f_sus))

    def body(self, i: int, t: dict) -> Body:
        where = f"body {t['name']!r}" if isinstance(t, dict) and isinstance(t.get("name"), str) \
            else f"body {i + 1}"
        self.keys(where, t, _BODY_KEYS, ("name", "mass", "inertia", "position"))
        name = self.string(where, "name", t["name"])
        mass = self.number(where, "mass", t["mass"], positive=True)
        inertia = t["inertia"]
        if isinstance(inertia, list) and inertia and all(isinstance(r, list) for r in inertia):
            if len(inertia) != 3:
                self.fail(where, f"inertia must be 3 numbers or 3 × 3, has {len(inertia)} rows")
            J = [self.numbers(where, f"inertia[{r}]", row, 3) for r, row in enumerate(inertia)]
        else:
            J = self.numbers(where, "inertia", inertia, 3)
        position = self.numbers(where, "position", t["position"], 3)
        ang = self.numbers(where, "orientation_deg", t.get("orientation_deg", [0, 0, 0]), 3)
        p = p_from_angles(*np.radians(ang))
        try:
            return Body(name, mass, np.array(J, dtype=float), np.array(position), p)
        except SceneError as exc:
            self.fail("", str(exc))

    def shape(self, where: str, t: dict, *, is_force: bool):
        kind = self.string(where, "shape", t["shape"], tuple(_SHAPE_KEYS))
        allowed = ("direction", "shape", "sample") + _SHAPE_KEYS[kind]
        for key in t:
            if key not in allowed:
                self.fail(where, f"key '{key}' does not apply to shape = {kind!r} "
                                 f"(known: {', '.join(allowed)})")
        try:
            if kind == "sinusoid":
                for key in ("amplitude", "frequency"):
                    if key not in t:
                        self.fail(where, f"'{key}' is required for shape = 'sinusoid'")
                dur = t.get("duration", math.inf)
                shape = Sinusoid(
                    self.number(where, "amplitude", t["amplitude"]),
                    self.number(where, "frequency", t["frequency"], positive=True),
                    math.radians(self.number(where, "phase_deg", t.get("phase_deg", 0.0))),
                    self.number(where, "start", t.get("start", 0.0), non_negative=True),
                    dur if dur == math.inf else self.number(where, "duration", dur, positive=True))
            elif kind in ("triangle", "trapezoid"):
                need = ("peak", "rise", "fall") + (("flat",) if kind == "trapezoid" else ())
                for key in need:
                    if key not in t:
                        self.fail(where, f"'{key}' is required for shape = {kind!r}")
                peak = self.number(where, "peak", t["peak"])
                start = self.number(where, "start", t.get("start", 0.0), non_negative=True)
                rise = self.number(where, "rise", t["rise"], positive=True)
                fall = self.number(where, "fall", t["fall"], positive=True)
                if kind == "triangle":
                    shape = Triangle(peak, rise, fall, start)
                else:
                    flat = self.number(where, "flat", t["flat"], non_negative=True)
                    shape = Trapezoid(peak, rise, flat, fall, start)
            else:
                if "file" in t:
                    if "time" in t or "value" in t:
                        self.fail(where, "give either 'file' or 'time'/'value', not both")
                    times, values = self.csv_file(where, self.string(where, "file", t["file"]))
                else:
                    for key in ("time", "value"):
                        if key not in t:
                            self.fail(where, f"'{key}' is required for shape = 'curve' "
                                             f"(or give 'file')")
                    times = self.numbers(where, "time", t["time"])
                    values = self.numbers(where, "value", t["value"])
                shape = Curve(np.array(times), np.array(values))
            if "sample" in t:
                if kind == "curve":
                    self.fail(where, "sample applies to sinusoid, triangle and trapezoid "
                                     "(curve data are already samples)")
                shape = sampled(shape, self.number(where, "sample", t["sample"], positive=True))
        except SceneError as exc:
            self.fail(where, str(exc))
        return shape

    def csv_file(self, where: str, name: str):
        p = (self.folder / name)
        try:
            text = p.read_text(encoding="utf-8")
        except OSError as exc:
            self.fail(where, f"file = {name!r}: cannot read it ({exc.strerror or exc})")
        self.csv[name] = text
        times, values = [], []
        for lineno, line in enumerate(text.splitlines(), 1):
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            cells = [c.strip() for c in s.split(",")]
            try:
                nums = [float(c) for c in cells]
            except ValueError:
                if not times:      # a header line
                    continue
                self.fail(where, f"file = {name!r}: line {lineno}: {s!r} is not two numbers")
            if len(nums) != 2:
                self.fail(where, f"file = {name!r}: line {lineno}: {len(nums)} columns, "
                                 f"expected 2 (time, value)")
            times.append(nums[0])
            values.append(nums[1])
        return times, values

    def base(self, t: dict) -> Base:
        where = "base"
        self.keys(where, t, _BASE_KEYS)
        motion = self.string(where, "motion", t.get("motion", "fixed"), ("fixed", "driven", "free"))
        support: Any = "none"
        if "support" in t:
            if isinstance(t["support"], str):
                support = self.string(where, "support", t["support"], ("static",))
            else:
                support = np.array(self.numbers(where, "support", t["support"], 3))
        drives, loads = [], []
        for kind, out, cls in (("drive", drives, Drive), ("force", loads, Load)):
            for i, d in enumerate(self.tables(f"base.{kind}", t.get(kind, []))):
                w = f"base.{kind} {i + 1}"
                self.keys(w, d, _ALL_SHAPE_KEYS, ("direction", "shape"))
                direction = self.string(w, "direction", d["direction"], DIRECTIONS)
                shape = self.shape(w, d, is_force=kind == "force")
                out.append(cls(DIRECTIONS.index(direction), shape))
        try:
            return Base(motion, tuple(drives), tuple(loads), support)
        except SceneError as exc:
            self.fail("", str(exc))

    def mount(self, i: int, t: dict, names: list[str]) -> Mount:
        where = f"mount {t['name']!r}" if isinstance(t, dict) and isinstance(t.get("name"), str) \
            else f"mount {i + 1}"
        self.keys(where, t, _MOUNT_KEYS, ("name", "body_i", "body_j", "point_i", "point_j", "law"))
        name = self.string(where, "name", t["name"])
        for key in ("body_i", "body_j"):
            v = self.string(where, key, t[key])
            if v not in names:
                self.fail(where, f"{key} = {v!r} is not a body (bodies: {', '.join(names)})")
        pi = self.numbers(where, "point_i", t["point_i"], 3)
        pj = self.numbers(where, "point_j", t["point_j"], 3)
        if "axes" in t and "axes_deg" in t:
            self.fail(where, "give either 'axes' or 'axes_deg', not both")
        if "axes" in t:
            rows = t["axes"]
            if not isinstance(rows, list) or len(rows) != 3:
                self.fail(where, f"axes = {rows!r} must be 3 rows u1, u2, u3 of 3 numbers")
            U = np.array([self.numbers(where, f"axes[{r}]", row, 3) for r, row in enumerate(rows)])
            err = float(np.max(np.abs(U @ U.T - np.eye(3))))
            if err > 1e-9:
                self.fail(where, f"axes = {U.tolist()} are not orthonormal "
                                 f"(max |U Uᵀ − I| = {err:.3g}, tolerance 1e-9)")
        else:
            ang = self.numbers(where, "axes_deg", t.get("axes_deg", [0, 0, 0]), 3)
            U = rotation_matrix(p_from_angles(*np.radians(ang))).T
        law = self.string(where, "law", t["law"], tuple(_LAW_KEYS))
        for key in _MOUNT_KEYS[9:]:
            if key in t and key not in _LAW_KEYS[law]:
                self.fail(where, f"key '{key}' does not apply to law = {law!r} "
                                 f"(it takes {', '.join(_LAW_KEYS[law])})")
        laws = self.laws(where, law, t)
        try:
            return Mount(name, t["body_i"], t["body_j"], np.array(pi), np.array(pj), U, laws)
        except SceneError as exc:
            self.fail("", str(exc))

    def laws(self, where: str, law: str, t: dict) -> tuple:
        try:
            if law == "linear":
                if "k" not in t:
                    self.fail(where, "'k' is required for law = 'linear'")
                k = self.numbers(where, "k", t["k"], 3, positive=True)
                c = self.numbers(where, "c", t.get("c", [0, 0, 0]), 3, non_negative=True)
                return tuple(LinearLaw(k[d], c[d]) for d in range(3))
            if law == "polynomial":
                if "stiffness" not in t:
                    self.fail(where, "'stiffness' is required for law = 'polynomial'")
                ks = self.coefficient_lists(where, "stiffness", t["stiffness"])
                cs = self.coefficient_lists(where, "damping", t.get("damping", [[0], [0], [0]]))
                return tuple(PolynomialLaw(tuple(ks[d]), tuple(cs[d])) for d in range(3))
            if "spring_curve" not in t:
                self.fail(where, "'spring_curve' is required for law = 'curve'")
            springs = self.curve_tables(where, "spring_curve", t["spring_curve"], "deflection")
            dampers = (self.curve_tables(where, "damper_curve", t["damper_curve"], "rate")
                       if "damper_curve" in t else [None] * 3)
            out = []
            for d in range(3):
                try:
                    out.append(CurveLaw(springs[d], dampers[d]))
                except SceneError as exc:
                    self.fail(where, f"direction {d + 1}: {exc}")
            return tuple(out)
        except SceneError as exc:
            self.fail(where, str(exc))

    def coefficient_lists(self, where, key, value) -> list:
        if not isinstance(value, list) or len(value) != 3 or not all(isinstance(v, list) for v in value):
            self.fail(where, f"{key} must be 3 lists of coefficients (one per direction)")
        out = []
        for d, row in enumerate(value):
            if len(row) > 9:
                self.fail(where, f"{key}[{d}] has degree {len(row) - 1} ({len(row)} coefficients), "
                                 f"at most 8 allowed")
            out.append(self.numbers(where, f"{key}[{d}]", row))
        return out

    def curve_tables(self, where, key, value, xkey) -> list:
        if not isinstance(value, list) or len(value) != 3 or not all(isinstance(v, dict) for v in value):
            self.fail(where, f"{key} must be 3 tables {{{xkey} = [...], force = [...]}} "
                             f"(one per direction)")
        out = []
        for d, tab in enumerate(value):
            w = f"{where}: {key}[{d}]"
            self.keys(w, tab, (xkey, "force"), (xkey, "force"))
            x = self.numbers(w, xkey, tab[xkey])
            f = self.numbers(w, "force", tab["force"])
            out.append((np.array(x), np.array(f)))
        return out

    def solver(self, t: dict) -> SolverSection:
        where = "solver"
        self.keys(where, t, _SOLVER_KEYS)
        args: dict[str, Any] = {}
        for key in ("t_end", "dt", "rtol", "atol", "output_dt", "static_tol", "linear_tol"):
            if key in t:
                args[key] = self.number(where, key, t[key], positive=True)
        if "integrator" in t:
            args["integrator"] = self.string(where, "integrator", t["integrator"], METHODS)
        if "start" in t:
            args["start"] = self.string(where, "start", t["start"], ("equilibrium", "initial"))
        if "model" in t:
            args["model"] = self.string(where, "model", t["model"], MODELS)
        return SolverSection(**args)

    def points(self, value, names) -> list:
        out = []
        seen = set()
        for i, t in enumerate(self.tables("point", value)):
            where = f"point {t['name']!r}" if isinstance(t.get("name"), str) else f"point {i + 1}"
            self.keys(where, t, _POINT_KEYS, ("name", "body", "position"))
            name = self.string(where, "name", t["name"])
            if name in seen:
                self.fail(where, "name is used twice")
            seen.add(name)
            body = self.string(where, "body", t["body"])
            if body not in names:
                self.fail(where, f"body = {body!r} is not a body (bodies: {', '.join(names)})")
            rel = None
            if "relative_to" in t:
                rel = self.string(where, "relative_to", t["relative_to"])
                if rel not in names:
                    self.fail(where, f"relative_to = {rel!r} is not a body "
                                     f"(bodies: {', '.join(names)})")
            pos = tuple(self.numbers(where, "position", t["position"], 3))
            out.append(PointOfInterest(name, body, pos, rel))
        return out


def _digest(data: Any, csv: dict[str, str]) -> str:
    h = hashlib.sha256()
    h.update(json.dumps(data, sort_keys=True, separators=(",", ":"), ensure_ascii=False,
                        default=str).encode())
    for name in sorted(csv):
        h.update(b"\0csv\0" + name.encode() + b"\0" + csv[name].encode())
    return h.hexdigest()

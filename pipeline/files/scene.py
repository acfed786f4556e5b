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
import tomllib
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from flexbed.dynamics.bounded_cache import BoundedCache
from flexbed.dynamics.errors import SceneError
from flexbed.dynamics.integrate import MAX_OUTPUT_SAMPLES, METHODS, Settings, output_samples
from flexbed.dynamics.laws import CurveLaw, LinearLaw, PolynomialLaw
from flexbed.dynamics.rotation import A as rotation_matrix
from flexbed.dynamics.rotation import p_from_angles
from flexbed.dynamics.scene import DIRECTIONS, Base, Body, Drive, Load, Mount, Scene
from flexbed.dynamics.time_functions import SplineEnds

from flexbed.files.builtin import BUILTIN, builtin_scene_path, builtin_scene_text  # noqa: F401
from flexbed.files.bed_points import points_on_bed
from flexbed.files.bed_section import BedSection, plate_mismatch, read_bed, with_mount_points
from flexbed.files.drives import ALL_SHAPE_KEYS, ShapeReader
from flexbed.errors import InputError
from flexbed.files.destination import check_source
from flexbed.files.loads import read_loads
from flexbed.files.scene_text import keep as _keep
from flexbed.files.scene_text import scene_data, table_key
from flexbed.files.elastomer import ELASTOMER_KEYS, read_elastomer, report_fits
from flexbed.files.limits import (BODY_LIMIT_KEYS, JUDGED_ONLY_KEYS, MOUNT_LIMIT_KEYS, Limits,
                                  read_limits)
from flexbed.files.sanity import warn_far_points
from flexbed.files.table_reader import short_repr

__all__ = ["SceneFile", "SolverSection", "PointOfInterest", "load_scene", "parse_scene",
           "scene_data", "read_solver", "builtin_scene_path", "builtin_scene_text", "BUILTIN"]


_TOP = ("scene", "body", "base", "bed", "mount", "solver", "point", "clearance", "load",
        "unbalance")
_SCENE_KEYS = ("name", "description", "gravity")
_BODY_KEYS = ("name", "mass", "inertia", "position", "orientation_deg", "velocity",
              "angular_velocity") + BODY_LIMIT_KEYS
_VELOCITY_KEYS = ("velocity", "angular_velocity")
_BASE_KEYS = ("motion", "support", "drive", "force")
_MOUNT_KEYS = ("name", "body_i", "body_j", "point_i", "point_j", "axes_deg", "axes", "law",
               "k", "c", "stiffness", "damping", "spring_curve", "damper_curve")
_LAW_ENTRY_KEYS = _MOUNT_KEYS[9:]
_MOUNT_KEYS += MOUNT_LIMIT_KEYS + ELASTOMER_KEYS
_LAW_KEYS = {"linear": ("k", "c"), "polynomial": ("stiffness", "damping"),
             "curve": ("spring_curve", "damper_curve")}
_SOLVER_KEYS = ("t_end", "integrator", "dt", "rtol", "atol", "output_dt", "start", "static_tol",
                "model", "linear_tol", "static_deflection_limit", "static_rotation_limit_deg",
                "allow_unstable")
MODELS = ("nonlinear", "linear", "auto")
_POINT_KEYS = ("name", "body", "position", "relative_to")

#: entries of recently read scene files, checked, by their raw tables: a
#: study's variants share all but the entries they change, and those alone
#: are checked again (a body not the bed's, a mount without an elastomer,
#: a base without data files: what their tables alone decide); the least
#: recently used dropped first, so the entries every point shares stay
_CHECKED = BoundedCache(512)


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
    static_deflection_limit: float = 0.25
    static_rotation_limit_deg: float = 10.0
    allow_unstable: bool = False

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
    static_tol); limits : Limits (stroke, load, fragility and clearance
    limits: :mod:`flexbed.files.limits`); elastomers : tuple of (mount
    index, ElastomerTable) (:mod:`flexbed.files.elastomer`); has_bed : bool
    (the file has a ``[bed]`` table).
    """

    scene: Scene
    bed: BedSection
    solver: SolverSection
    points: tuple
    source: Path
    text: str
    digest: str
    statics_digest: str
    limits: Limits = Limits()
    elastomers: tuple = ()
    has_bed: bool = False

    @property
    def output_name(self) -> str:
        """Stem of every default output file name (``<output_name>-modes.h5``,
        ``-equilibrium.h5``, ``-results.h5``, ...): the scene file's stem,
        which no two scene files in one folder share (the built-in scene's
        is ``lee1999``). ``[scene] name`` is only a label."""
        return self.source.stem


def load_scene(path: str | Path | None = None) -> SceneFile:
    """Read and check a scene file (the built-in reference scene if path is None)."""
    if not (path is None or isinstance(path, (str, Path))) or path == "":
        raise InputError(f"flexbed.load_scene: path = {short_repr(path)} must be a scene "
                         f"file's name (str or pathlib.Path), or None for the built-in scene")
    path = builtin_scene_path() if path is None else check_source(path, "scene file")
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: cannot read the scene file ({exc.strerror or exc})") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError:
        raise InputError(f"{path.name}: not a UTF-8 text file") from None
    return parse_scene(text, path)


def read_solver(table: dict, label: str, where: str = "solver") -> SolverSection:
    """A ``[solver]`` table checked as a scene file's is; messages start
    ``label: where:`` (the API's settings use the function's name and no
    ``where``)."""
    return _Reader(label, Path.cwd()).solver(table, where)


def parse_scene(text: str, source: Path, *, data: dict | None = None) -> SceneFile:
    """Check a scene given as TOML text; ``source`` is the file it stands for
    (named in messages; curve files are read relative to its folder).
    ``data``, optional: ``text`` parsed already (``tomllib.loads(text)``,
    e.g. the data a variant's text was written from), not parsed again."""
    source = Path(source)
    if data is None:
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise InputError(f"{source.name}: not valid TOML: {exc}") from None
        except RecursionError:
            raise InputError(f"{source.name}: not readable TOML: arrays or tables nested too "
                             f"deeply") from None
    _keep(text, data)
    return _Reader(source.name, source.parent).read(data, source, text)


class _Reader(ShapeReader):
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
        bed = read_bed(data.get("bed", {}), f"{self.label}: bed", self.folder)
        at = _bed_index(bodies_raw, bed) if "bed" in data else None
        bodies = [self.body(i, b, bed) if i == at else self.checked("body", self.body, i, b)
                  for i, b in enumerate(bodies_raw)]
        names = [b.name for b in bodies]
        base_raw = data.get("base", {})
        base = (self.base(base_raw) if _reads_files(base_raw)
                else self.checked("base", self.base, base_raw))
        self.elastomers = []
        mounts = [self.mount(i, m, names) if isinstance(m, dict) and any(
                      k in m for k in ELASTOMER_KEYS)
                  else self.checked("mount", self.mount, i, m, names)
                  for i, m in enumerate(self.tables("mount", data.get("mount", [])))]
        report_fits(self.label, [(mounts[i].name, e) for i, e in self.elastomers])
        if bed.body is not None and bed.body not in names:
            self.fail("bed", f"body = {bed.body!r} is not a body (bodies: {', '.join(names)})")
        solver = self.solver(data.get("solver", {}))
        points = self.points(data.get("point", []), names)
        limits = read_limits(self, data, names, names[at] if at is not None else None,
                             _off_bed(bed))
        mounts = [m if m.stops == limits.mount(m.name).stops
                  else replace(m, stops=limits.mount(m.name).stops) for m in mounts]
        if at is not None:
            ends = [getattr(m, f"point_{k}") for m in mounts for k in "ij"
                    if getattr(m, f"body_{k}") == names[at]]
            mounts, points = points_on_bed(bed, names[at], mounts, points, self.fail)
            bed = with_mount_points(bed, ends)        # an auto mesh: nodes there
        loads = read_loads(self, data, names, names[at] if at is not None else None,
                           lambda: bed.mass_properties.centre, _off_bed(bed))
        try:
            scene = Scene(tuple(bodies), base, tuple(mounts), np.array(gravity), name,
                          loads=loads)
        except SceneError as exc:
            self.fail("", str(exc))
        warn_far_points(self.label, scene, bodies_raw[at]["name"] if at is not None else None,
                        bed)
        if bed.auto == ():
            bed = self.resolve_auto_modes(scene, bed, solver)
        digest = _digest(data, self.csv)
        at_rest = [{k: v for k, v in b.items() if k not in _VELOCITY_KEYS + BODY_LIMIT_KEYS}
                   for b in bodies_raw]
        mounts_raw = [{k: v for k, v in m.items() if k not in JUDGED_ONLY_KEYS + ELASTOMER_KEYS}
                      for m in data.get("mount", [])]
        statics = {"gravity": gravity, "body": at_rest, "mount": mounts_raw,
                   "bed": data.get("bed", {}), "static_tol": solver.static_tol}
        for key in ("load", "unbalance"):     # a constant load moves the equilibrium
            if key in data:
                statics[key] = data[key]
        return SceneFile(scene=scene, bed=bed, solver=solver, points=tuple(points),
                         source=path, text=text, digest=digest,
                         statics_digest=_digest(statics, {}), limits=limits,
                         elastomers=tuple(self.elastomers), has_bed="bed" in data)

    def checked(self, kind: str, read, *args):
        """``read(*args)``, or its result for the same arguments kept from a
        scene read before (:data:`_CHECKED`; a table by its
        :func:`~flexbed.files.scene_text.table_key`, so ``1`` and ``1.0``
        stay apart as the checks keep them). Only for readers whose result
        their arguments alone decide; a refusal is never kept, so it is
        raised again, naming this file."""
        key = (kind,) + tuple(table_key(a) if isinstance(a, (dict, list)) else a for a in args)
        if None in key:                               # not to be kept: read every time
            return read(*args)
        return _CHECKED.get(key, lambda: read(*args))

    def resolve_auto_modes(self, scene: Scene, bed: BedSection, solver) -> BedSection:
        """``[bed] modes = "auto"`` → fmax = f_cut (see :mod:`flexbed.stages.modes_auto`)."""
        from flexbed.stages.modes_auto import cutoff
        try:
            f_cut, f_in, f_sus = cutoff(scene, solver.t_end, bed.auto_factor, solver.static_tol)
        except RuntimeError as exc:
            self.fail("bed", f"modes = \"auto\" needs the static equilibrium with a rigid "
                             f"bed: {exc}")
        return replace(bed, fmax=float(f_cut), auto=(float(f_cut), f_in, f_sus))

    def body(self, i: int, t: dict, bed: BedSection | None = None) -> Body:
        """A ``[[body]]``; ``bed``: the scene's [bed] when this is the bed's body
        (its mass and inertia may then be omitted: they come from the plate)."""
        where = f"body {t['name']!r}" if isinstance(t, dict) and isinstance(t.get("name"), str) \
            else f"body {i + 1}"
        required = ("name", "position") if bed else ("name", "mass", "inertia", "position")
        self.keys(where, t, _BODY_KEYS, required)
        name = self.string(where, "name", t["name"])
        if "mass" in t:
            mass = self.number(where, "mass", t["mass"], positive=True)
        else:
            mass = bed.mass_properties.mass
        if "inertia" not in t:
            J = bed.mass_properties.inertia.tolist()
        elif isinstance(t["inertia"], list) and t["inertia"] and all(isinstance(r, list)
                                                                    for r in t["inertia"]):
            if len(t["inertia"]) != 3:
                self.fail(where, f"inertia must be 3 numbers or 3 × 3, has "
                                 f"{len(t['inertia'])} rows")
            J = [self.numbers(where, f"inertia[{r}]", row, 3) for r, row in enumerate(t["inertia"])]
        else:
            J = self.numbers(where, "inertia", t["inertia"], 3)
        if bed and bed.flexible:
            why = plate_mismatch(bed.plate, mass if "mass" in t else None,
                                 J if "inertia" in t else None)
            if why:
                self.fail(where, why)
        position = self.numbers(where, "position", t["position"], 3)
        ang = self.numbers(where, "orientation_deg", t.get("orientation_deg", [0, 0, 0]), 3)
        p = p_from_angles(*np.radians(ang))
        if bed is not None:       # the bed's position is its drawing origin's: to its CoM
            position = (np.array(position) + rotation_matrix(p) @ bed.mass_properties.centre
                        ).tolist()
        v = self.numbers(where, "velocity", t.get("velocity", [0, 0, 0]), 3)
        w = self.numbers(where, "angular_velocity", t.get("angular_velocity", [0, 0, 0]), 3)
        try:
            return Body(name, mass, np.array(J, dtype=float), np.array(position), p,
                        np.array(v), np.array(w))
        except SceneError as exc:
            self.fail("", str(exc))

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
                self.keys(w, d, ALL_SHAPE_KEYS, ("direction", "shape"))
                direction = self.string(w, "direction", d["direction"], DIRECTIONS)
                out += [cls(DIRECTIONS.index(direction), s) for s in self.terms(w, d, kind)]
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
        for key in _LAW_ENTRY_KEYS:
            if key in t and key not in _LAW_KEYS[law]:
                self.fail(where, f"key '{key}' does not apply to law = {law!r} "
                                 f"(it takes {', '.join(_LAW_KEYS[law])})")
        laws = self.laws(where, law, t)
        elastomer = read_elastomer(self, where, t, laws)
        if elastomer is not None:
            self.elastomers.append((i, elastomer))
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
                fs, fd = springs[d], dampers[d]
                try:
                    out.append(CurveLaw(fs[:2], fd[:2] if fd else None, fs[2],
                                        fd[2] if fd else SplineEnds()))
                except SceneError as exc:
                    self.fail(where, f"direction {d + 1}: {exc}")
            return tuple(out)
        except SceneError as exc:
            self.fail(where, str(exc))

    def coefficient_lists(self, where, key, value) -> list:
        if (not isinstance(value, list) or len(value) != 3
                or not all(isinstance(v, list) for v in value)):
            self.fail(where, f"{key} must be 3 lists of coefficients (one per direction)")
        out = []
        for d, row in enumerate(value):
            if len(row) > 9:
                self.fail(where, f"{key}[{d}] has degree {len(row) - 1} ({len(row)} coefficients), "
                                 f"at most 8 allowed")
            out.append(self.numbers(where, f"{key}[{d}]", row))
        return out

    def solver(self, t: dict, where: str = "solver") -> SolverSection:
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
        for key in ("static_deflection_limit", "static_rotation_limit_deg"):   # inf: no limit
            if key in t:
                v = t[key]
                args[key] = v if v == float("inf") else self.number(where, key, v, positive=True)
        if "allow_unstable" in t:
            if not isinstance(t["allow_unstable"], bool):
                self.fail(where, f"allow_unstable = {t['allow_unstable']!r} must be true or false")
            args["allow_unstable"] = t["allow_unstable"]
        section = SolverSection(**args)
        n = output_samples(section.t_end, section.output_dt)
        if n > MAX_OUTPUT_SAMPLES:
            self.fail(where, f"output_dt = {section.output_dt:g} s over t_end = "
                             f"{section.t_end:g} s gives {n:.3g} output samples; the limit is "
                             f"{MAX_OUTPUT_SAMPLES:.0e}")
        return section

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


def _bed_index(bodies: list, bed: BedSection) -> int | None:
    """Index of the bed's ``[[body]]`` table (``[bed] body``, default the
    second), None when there is none or it would be the base."""
    if bed.body is None:
        return 1 if len(bodies) > 1 else None
    for i, t in enumerate(bodies):
        if isinstance(t, dict) and t.get("name") == bed.body:
            return i if i > 0 else None
    return None


def _reads_files(base: Any) -> bool:
    """Whether a ``[base]`` table names a data file (a drive or force from
    a CSV file, whose text the scene's digest holds), or is not as the
    checks expect (then read, and refused, every time)."""
    if not isinstance(base, dict):
        return True
    for kind in ("drive", "force"):
        tables = base.get(kind, [])
        if not isinstance(tables, list) or any(not isinstance(t, dict) or "file" in t
                                               for t in tables):
            return True
    return False


def _off_bed(bed: BedSection):
    """``off_bed(point)`` for points on the bed (drawing frame), or None
    where any body-fixed point is taken (a rigid plain rectangle), as
    :func:`~flexbed.files.bed_points.points_on_bed` decides."""
    if not (bed.flexible or bed.plate.geometry is not None):
        return None
    from flexbed.fem.layout import off_bed
    return lambda point: bool(off_bed(bed.plate, np.array(point)[None, :])[0])


def _digest(data: Any, csv: dict[str, str]) -> str:
    h = hashlib.sha256()
    h.update(json.dumps(data, sort_keys=True, separators=(",", ":"), ensure_ascii=False,
                        default=str).encode())
    for name in sorted(csv):
        h.update(b"\0csv\0" + name.encode() + b"\0" + csv[name].encode())
    return h.hexdigest()

"""The ``[bed]`` table's geometry keys: ``outline``, ``[[bed.cutout]]``,
``[[bed.zone]]``, ``element_size`` and ``mesh_file``, read into a
:class:`flexbed.fem.geometry.BedGeometry` (whose own checks are reused, so
the scene file and the modes stage agree on what a valid bed is).

Every message is one line naming the file, the entry and the value.
"""

from __future__ import annotations

import math
from dataclasses import fields, replace
from pathlib import Path

from flexbed.fem.fixed_masses import FixedMass
from flexbed.fem.geometry import BedGeometry, GeometryError, Region, Zone
from flexbed.fem.layout import bed_layout, check_stiffeners
from flexbed.fem.spec import PlateSpec, PlateSpecError
from flexbed.fem.stiffener_face import face_thickness
from flexbed.fem.stiffeners import Stiffener, section_of

from flexbed.errors import InputError
from flexbed.files.table_reader import LARGEST, SMALLEST, is_number, out_of_range, short_repr

GEOMETRY_KEYS = ("outline", "cutout", "zone", "element_size", "mesh_file", "fixed_mass",
                 "stiffener")
_STIFFENER_KEYS = ("name", "start", "end", "section", "side", "offset", "height", "width", "web",
                   "flange_width", "flange", "area", "Iy", "Iz", "J", "model", "shear_area")
_MASS_KEYS = ("name", "position", "mass", "inertia")
_REGION_KEYS = ("shape", "centre", "size", "radius", "points")
#: the keys each shape of a cut-out or zone takes, all required (a centre is
#: never defaulted to the origin, a key of another shape never ignored)
_SHAPE_KEYS = {"rectangle": ("centre", "size"), "circle": ("centre", "radius"),
               "polygon": ("points",)}


def _in_range(value, where: str, key: str) -> None:
    """Every number in a (nested) value within the scene's range
    (:data:`flexbed.files.table_reader.LARGEST`), else an InputError naming
    it as ``key[i][j]``."""
    if isinstance(value, dict):
        for k, v in value.items():
            _in_range(v, where, k)
    elif isinstance(value, list):
        for i, v in enumerate(value):
            _in_range(v, where, f"{key}[{i}]")
    elif is_number(value):
        try:
            v = float(value)
        except OverflowError:
            v = math.inf if value > 0 else -math.inf
        if not math.isfinite(v) and not isinstance(value, int):
            raise InputError(f"{where}: {key} = {short_repr(value)} must be finite")
        if not math.isfinite(v) or out_of_range(v):
            raise InputError(f"{where}: {key} = {short_repr(value)} is out of range (magnitudes "
                             f"from {SMALLEST:g} to {LARGEST:g}, or 0)")


def _region(t, where: str) -> Region:
    if not isinstance(t, dict):
        raise InputError(f"{where}: must be a table {{shape = ..., ...}}")
    _in_range(t, where, "")
    for key in t:
        if key not in _REGION_KEYS + ("thickness",):
            raise InputError(f"{where}: unknown key '{key}' (known: {', '.join(_REGION_KEYS)})")
    if "shape" not in t:
        raise InputError(f"{where}: 'shape' is required (\"rectangle\", \"circle\" or "
                         f"\"polygon\")")
    keys = _SHAPE_KEYS.get(t["shape"]) if isinstance(t["shape"], str) else None
    for key in keys or ():
        if key not in t:
            raise InputError(f"{where}: '{key}' is required for a {t['shape']} (its keys: "
                             f"{', '.join(keys)})")
    for key in t:
        if keys is not None and key not in keys + ("shape", "thickness"):
            raise InputError(f"{where}: '{key}' does not apply to a {t['shape']} (its keys: "
                             f"{', '.join(keys)})")
    args = {k: t[k] for k in _REGION_KEYS if k in t}
    for k in ("centre", "size"):
        if k in args and isinstance(args[k], list):
            args[k] = tuple(args[k])
    try:
        return Region(**args)
    except (GeometryError, TypeError, ValueError) as exc:
        raise InputError(f"{where}: {exc}") from None


def _named_tables(table: dict, key: str, where: str, known: tuple, required: tuple):
    """Each ``[[bed.<key>]]`` table with the name messages give it:
    (``"<where>: <key> 'name'"`` or ``"… <key> <i>"``, table), its keys
    checked against ``known`` and ``required`` (InputError naming them)."""
    value = table.get(key, [])
    if not isinstance(value, list):
        raise InputError(f"{where}: {key} must be an array of tables [[bed.{key}]]")
    for i, t in enumerate(value):
        w = f"{where}: {key} {i + 1}"
        if not isinstance(t, dict):
            raise InputError(f"{w}: must be a table")
        if isinstance(t.get("name"), str):
            w = f"{where}: {key} {t['name']!r}"
        for k in t:
            if k not in known:
                raise InputError(f"{w}: unknown key '{k}' (known: {', '.join(known)})")
        for k in required:
            if k not in t:
                raise InputError(f"{w}: '{k}' is required")
        yield w, t


def read_fixed_masses(table: dict, where: str) -> tuple[FixedMass, ...]:
    """``[[bed.fixed_mass]]`` tables: name, position [x, y, z] (drawing frame,
    z above the mid-surface) [m], mass [kg], inertia about its centre of
    mass (3 numbers or 3 × 3, default zero) [kg m²]."""
    out = []
    for w, t in _named_tables(table, "fixed_mass", where, _MASS_KEYS,
                              ("name", "position", "mass")):
        if not isinstance(t["name"], str):
            raise InputError(f"{w}: name = {t['name']!r} must be a string")
        _in_range(t, w, "")
        try:
            out.append(FixedMass(t["name"], t["position"], t["mass"],
                                 t.get("inertia", [0.0, 0.0, 0.0])))
        except (GeometryError, TypeError, ValueError) as exc:
            raise InputError(f"{w}: {exc}") from None
    return tuple(out)


def read_stiffeners(table: dict, where: str, geometry: BedGeometry | None = None
                    ) -> tuple[Stiffener, ...]:
    """``[[bed.stiffener]]`` tables: name, start and end [x, y] (drawing frame)
    [m], section = "flat" (height, width), "T" (height, web, flange_width,
    flange), "I" (height, web, flange_width, flange) or "general" (area,
    Iy, Iz, J, offset); side = "below" (default) or "above" places flat, T
    and I sections on the plate's face (offset = ∓(t/2 + centroid height),
    t the local thickness: a zone's under the stiffener, the plate's
    elsewhere); offset [m] is the centroid's height above the mid-surface;
    model = "hinged" (the default for flat, T, I), "timoshenko" (a general
    section's default with shear_area [m²]) or "euler-bernoulli" (general
    without it) (:mod:`flexbed.fem.stiffeners`)."""
    default = {f.name: f.default for f in fields(PlateSpec)}
    thickness = table.get("thickness", default["thickness"])
    zones = geometry.zones if geometry is not None else ()
    size = None
    if zones:
        try:
            size = geometry.element_size or abs(min(
                table.get("length_x", default["length_x"]) / table.get("nx", default["nx"]),
                table.get("length_y", default["length_y"]) / table.get("ny", default["ny"])))
        except (TypeError, ZeroDivisionError):
            zones = ()                  # the plate's own checks name the bad value
    out = []
    for w, t in _named_tables(table, "stiffener", where, _STIFFENER_KEYS,
                              ("name", "start", "end", "section")):
        _in_range(t, w, "")
        kind = t["section"]
        side = t.get("side", "below")
        if side not in ("below", "above"):
            raise InputError(f"{w}: side = {side!r} must be \"below\" or \"above\"")
        try:
            sec = section_of(kind, **{k: t[k] for k in ("height", "width", "web",
                                                        "flange_width", "flange", "area", "Iy",
                                                        "Iz", "J", "shear_area") if k in t})
            model = t.get("model")
            if kind == "general":
                if "offset" not in t:
                    raise GeometryError("offset", "'offset' is required for section = "
                                                  "'general' [m]")
                offset = t["offset"]
            else:
                if "offset" in t:
                    raise GeometryError("offset", f"offset = {t['offset']!r} applies to "
                                                  f"section = 'general' only (use side)")
                offset = (thickness / 2 + sec.centroid) * (-1 if side == "below" else 1)
            st = Stiffener(t["name"], tuple(t["start"]), tuple(t["end"]), sec, offset,
                           model)
            if zones and kind != "general":
                t_face = face_thickness(st.start, st.end, zones, thickness, size)
                st = replace(st, offset=(t_face / 2 + sec.centroid) * (-1 if side == "below"
                                                                      else 1))
            out.append(st)
        except (GeometryError, TypeError, ValueError) as exc:
            raise InputError(f"{w}: {exc}") from None
    return tuple(out)


def read_geometry(table: dict, where: str, folder: Path | None) -> BedGeometry | None:
    """The geometry keys of a parsed ``[bed]`` table (None when there are none).

    Parameters
    ----------
    table : dict
        The ``[bed]`` table.
    where : str
        Message prefix, e.g. ``"lee.toml: bed"``.
    folder : Path or None
        The scene file's folder (a relative ``mesh_file`` is there).
    """
    if not any(k in table for k in GEOMETRY_KEYS if k not in ("fixed_mass", "stiffener")):
        return None
    _in_range(table.get("outline"), f"{where}", "outline")
    cut = table.get("cutout", [])
    zones = table.get("zone", [])
    for key, value in (("cutout", cut), ("zone", zones)):
        if not isinstance(value, list):
            raise InputError(f"{where}: {key} must be an array of tables [[bed.{key}]]")
    cutouts = tuple(_region(c, f"{where}: cutout {i + 1}") for i, c in enumerate(cut))
    zs = []
    for i, z in enumerate(zones):
        w = f"{where}: zone {i + 1}"
        if not isinstance(z, dict) or "thickness" not in z:
            raise InputError(f"{w}: 'thickness' is required [m]")
        _in_range(z, w, "")
        try:
            zs.append(Zone(_region({k: v for k, v in z.items() if k != "thickness"}, w),
                           z["thickness"]))
        except GeometryError as exc:
            raise InputError(f"{w}: {exc}") from None
    mesh_file = table.get("mesh_file")
    if mesh_file is not None:
        if not isinstance(mesh_file, str):
            raise InputError(f"{where}: mesh_file = {mesh_file!r} must be a string")
        path = Path(mesh_file)
        if folder is not None and not path.is_absolute():
            path = folder / path
        try:
            mesh_file = str(path.resolve())
        except (OSError, RuntimeError) as exc:        # a loop of symbolic links
            raise InputError(f"{where}: mesh_file = {table['mesh_file']!r}: cannot read it "
                             f"({getattr(exc, 'strerror', None) or exc})") from None
    try:
        return BedGeometry(outline=table.get("outline"), cutouts=cutouts, zones=tuple(zs),
                           element_size=table.get("element_size"), mesh_file=mesh_file)
    except GeometryError as exc:
        shown = str(exc).replace(mesh_file or "\0", str(table.get("mesh_file")))
        raise InputError(f"{where}: {shown}") from None


def check_bed(plate: PlateSpec, where: str, mesh_file=None) -> None:
    """Mesh the bed as the scene reads it and check it, so that a bed that
    cannot be built is refused in one line before any work: the outline,
    cut-outs and zones as geometry, the mesh's size against the solver's
    limit (estimated before meshing), the mesh as a mesh (a mesh file's
    too), fixed masses on the shell, stiffeners along cell edges
    (:mod:`flexbed.fem.mesh_checks`, :func:`flexbed.fem.layout.bed_layout`,
    cached: the stages reuse the mesh). The plain rectangle on its grid is
    not meshed here.

    Parameters
    ----------
    plate : PlateSpec
    where : str
        Message prefix, e.g. ``"lee.toml: bed"``.
    mesh_file : str, optional
        ``mesh_file`` as the scene gives it (messages show it instead of
        the resolved path).

    Raises
    ------
    InputError
        ``"<where>: <entry>: <what is wrong, with the value>"``.
    """
    if plate.is_rectangle:
        return
    try:
        bed_layout(plate)
        check_stiffeners(plate)            # on the mesh: along cell edges, end to end
    except (GeometryError, PlateSpecError) as exc:
        text = str(exc)
        resolved = plate.geometry.mesh_file if plate.geometry is not None else None
        if resolved and isinstance(mesh_file, str):
            text = text.replace(repr(resolved), repr(mesh_file)).replace(resolved, mesh_file)
        raise InputError(f"{where}: {text}") from None

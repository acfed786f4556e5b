"""The ``[bed]`` table's geometry keys: ``outline``, ``[[bed.cutout]]``,
``[[bed.zone]]``, ``element_size`` and ``mesh_file``, read into a
:class:`flexbed.fem.geometry.BedGeometry` (whose own checks are reused, so
the scene file and the modes stage agree on what a valid bed is).

Every message is one line naming the file, the entry and the value.
"""

from __future__ import annotations

from pathlib import Path

from flexbed.fem.geometry import BedGeometry, GeometryError, Region, Zone

from flexbed.errors import InputError

GEOMETRY_KEYS = ("outline", "cutout", "zone", "element_size", "mesh_file")
_REGION_KEYS = ("shape", "centre", "size", "radius", "points")


def _region(t, where: str) -> Region:
    if not isinstance(t, dict):
        raise InputError(f"{where}: must be a table {{shape = ..., ...}}")
    for key in t:
        if key not in _REGION_KEYS + ("thickness",):
            raise InputError(f"{where}: unknown key '{key}' (known: {', '.join(_REGION_KEYS)})")
    if "shape" not in t:
        raise InputError(f"{where}: 'shape' is required (\"rectangle\", \"circle\" or "
                         f"\"polygon\")")
    args = {k: t[k] for k in _REGION_KEYS if k in t}
    for k in ("centre", "size"):
        if k in args and isinstance(args[k], list):
            args[k] = tuple(args[k])
    try:
        return Region(**args)
    except (GeometryError, TypeError, ValueError) as exc:
        raise InputError(f"{where}: {exc}") from None


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
    if not any(k in table for k in GEOMETRY_KEYS):
        return None
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
        mesh_file = str(path.resolve())
    try:
        return BedGeometry(outline=table.get("outline"), cutouts=cutouts, zones=tuple(zs),
                           element_size=table.get("element_size"), mesh_file=mesh_file)
    except GeometryError as exc:
        shown = str(exc).replace(mesh_file or "\0", str(table.get("mesh_file")))
        raise InputError(f"{where}: {shown}") from None

"""The scene file's ``[bed]`` table: the plate, the modes kept, damping.

Read into a frozen :class:`BedSection`; the plate's own inputs become a
:class:`flexbed.fem.spec.PlateSpec`, whose range checks are reused here so that the
scene file and the modes stage agree on what a valid plate is.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace
from pathlib import Path
from typing import Any

import numpy as np

from flexbed.fem.layout import bed_mass_properties, elastic_mode_count
from flexbed.fem.spec import MAX_DOFS, PlateSpec, PlateSpecError

from flexbed.errors import InputError
from flexbed.files.table_reader import LARGEST, SMALLEST, short_repr, out_of_range
from flexbed.files.bed_geometry import (GEOMETRY_KEYS, check_bed, read_fixed_masses,
                                        read_geometry, read_stiffeners)

_PLATE_KEYS = tuple(f.name for f in fields(PlateSpec)
                    if f.name not in ("geometry", "masses", "stiffeners", "mesh_points"))
#: the keys that set a bed's mesh; a Mindlin bed with none of them gets
#: ``element_size = "auto"``
_MESH_KEYS = ("nx", "ny", "element_size", "mesh_file")
#: ``mesh_tolerance`` when ``element_size = "auto"`` does not give one [-]
AUTO_TOLERANCE = 0.005
_KEYS = _PLATE_KEYS + GEOMETRY_KEYS + ("body", "model", "modes", "fmax", "rayleigh",
                                       "damping_ratio", "modes_file", "static_sag", "invariants",
                                       "auto_factor", "static_correction", "correction_modes")
DEFAULT_MODES = 2
PLATE_BODY_TOL = 1e-4    # a flexible bed body's given mass and inertia against the plate's


@dataclass(frozen=True, slots=True)
class BedSection:
    """The common bed as the scene describes it.

    Parameters
    ----------
    plate : PlateSpec
        Geometry, material and mesh of the plate.
    body : str or None
        Name of the bed's body (None: the second body).
    model : str
        "rigid" or "flexible".
    modes : int or None
        Number of elastic modes kept (lowest first); None when ``fmax`` is set.
    fmax : float or None
        Keep every elastic mode below this frequency [Hz].
    auto : tuple of float or None
        ``modes = "auto"`` in the scene: (f_cut, f_input, f_suspension) [Hz]
        as :mod:`flexbed.stages.modes_auto` resolved them (then ``fmax = f_cut``);
        before resolution ``()``.
    auto_factor : float
        f_cut = auto_factor × max(f_input, f_suspension) [-].
    rayleigh : tuple of float
        (α [1/s], β [s]) of c_aa = α M_aa + β K_aa.
    damping_ratio : tuple of float or None
        Modal damping ratios (one for all, or one per kept mode) [-],
        instead of ``rayleigh``.
    modes_file : str or None
        Path of the modes file as written in the scene (relative to it).
    static_sag : bool
        Include the elastic sag in the static equilibrium.
    invariants : str
        "full" (every configuration-dependent inertia term) or
        "first_order" (inertia linear in the modal coordinates, no I5/I9).
    static_correction : bool
        Add residual vectors: the static response at the bed's mount points
        of the modes left out, up to ``correction_modes``
        (:mod:`flexbed.stages.residual_modes`).
    correction_modes : int
        The modes file's modes the static correction draws on (the modes
        stage computes at least this many when the correction is on).
    """

    plate: PlateSpec = PlateSpec()
    body: str | None = None
    model: str = "rigid"
    modes: int | None = DEFAULT_MODES
    fmax: float | None = None
    rayleigh: tuple[float, float] = (0.0, 0.0)
    damping_ratio: tuple[float, ...] | None = None
    modes_file: str | None = None
    static_sag: bool = True
    invariants: str = "full"
    auto: tuple | None = None
    auto_factor: float = 2.0
    static_correction: bool = False
    correction_modes: int = 40

    def __post_init__(self) -> None:
        if self.invariants not in ("full", "first_order"):
            raise ValueError(f"invariants = {self.invariants!r} must be \"full\" or "
                             "\"first_order\"")
        if self.model not in ("rigid", "flexible"):
            raise ValueError(f"model = {self.model!r} must be \"rigid\" or \"flexible\"")
        if self.modes is not None and (isinstance(self.modes, bool)
                                       or not isinstance(self.modes, int) or self.modes < 1):
            raise ValueError(f"modes = {self.modes!r} must be an integer >= 1")
        if self.fmax is not None and not (_is_number(self.fmax) and self.fmax > 0):
            raise ValueError(f"fmax = {self.fmax!r} must be a number > 0 [Hz]")
        if (isinstance(self.correction_modes, bool) or not isinstance(self.correction_modes, int)
                or self.correction_modes < 2):
            raise ValueError(f"correction_modes = {self.correction_modes!r} must be an integer "
                             ">= 2")
        if not (_is_number(self.auto_factor) and self.auto_factor >= 1.0):
            raise ValueError(f"auto_factor = {self.auto_factor!r} must be a number >= 1")
        if self.auto == ():
            if self.fmax is not None:
                raise ValueError("give either modes = \"auto\" or fmax, not both")
        elif (self.modes is None) == (self.fmax is None):
            raise ValueError("give either modes or fmax, not both")
        if (len(self.rayleigh) != 2 or not all(_is_number(v) for v in self.rayleigh)):
            raise ValueError(f"rayleigh = {list(self.rayleigh)!r} "
                             "must be two numbers [alpha, beta]")
        for name, v in zip(("alpha", "beta"), self.rayleigh):
            if v < 0:
                raise ValueError(f"rayleigh {name} = {v!r} must be >= 0")
        if self.damping_ratio is not None:
            if not self.damping_ratio or not all(_is_number(v) and v >= 0
                                                 for v in self.damping_ratio):
                raise ValueError(f"damping_ratio = {list(self.damping_ratio)!r} "
                                 "must be numbers >= 0")
            if any(v != 0 for v in self.rayleigh):
                raise ValueError("give either rayleigh or damping_ratio, not both")

    @property
    def mass_properties(self):
        """The plate's mass, centre of mass (drawing frame) and inertia about
        it (:func:`flexbed.fem.layout.bed_mass_properties`)."""
        return bed_mass_properties(self.plate)

    @property
    def flexible(self) -> bool:
        """True when the bed is a floating-frame flexible body."""
        return self.model == "flexible"


def _is_number_like(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and (
        isinstance(v, int) or math.isfinite(v))


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def plate_mismatch(plate: PlateSpec, mass: float | None = None, inertia=None) -> str | None:
    """Why a flexible bed body's given mass or inertia disagree with the plate's.

    The plate's are the solid plate's (:attr:`PlateSpec.mass`,
    :attr:`PlateSpec.inertia`), the values the modes file's invariants
    carry; they agree within ``PLATE_BODY_TOL`` of the given value (the
    rounding of published figures).

    Parameters
    ----------
    plate : PlateSpec
    mass : float, optional
        The given mass [kg] (None: not given).
    inertia : list, optional
        The given inertia [kg m²]: 3 numbers (the diagonal) or 3 × 3.

    Returns
    -------
    str or None
        One line with both values (the plate's to 6 significant digits)
        saying that the key can be omitted; None when they agree.
    """
    mp = bed_mass_properties(plate)
    if mass is not None and abs(mp.mass - mass) > PLATE_BODY_TOL * mass:
        how = ("density × length_x × length_y × thickness" if plate.is_rectangle
               else "the plate's outline, cut-outs and zones")
        return (f"mass = {mass!r} kg differs from the plate's {mp.mass:.6g} kg "
                f"({how}); omit mass to take the plate's")
    if inertia is not None:
        J = np.array(inertia, dtype=float)
        J = np.diag(J) if J.shape == (3,) else J
        ref = mp.inertia
        if np.abs(ref - J).max() > PLATE_BODY_TOL * np.abs(J).max():
            shown = (", ".join(f"{v:.6g}" for v in np.diag(ref)) if plate.is_rectangle
                     else "; ".join(", ".join(f"{v:.6g}" for v in row) for row in ref))
            return (f"inertia = {inertia!r} kg m^2 differs from the plate's [{shown}] kg m^2 "
                    f"(the solid plate about its centre); omit inertia to take the plate's")
    return None


def _auto_mesh(table: dict, plate_args: dict, where: str) -> dict:
    """``element_size = "auto"`` (given, or the default of a Mindlin bed with
    none of nx, ny, element_size, mesh_file): ``mesh_tolerance`` set in
    ``plate_args`` (default :data:`AUTO_TOLERANCE`); the table returned
    without ``element_size`` for the geometry reader."""
    asked = table.get("element_size") == "auto"
    default = (table.get("theory") == "mindlin"
               and not any(k in table for k in _MESH_KEYS))
    if not (asked or default):
        if "mesh_tolerance" in table:
            given = ", ".join(f"{k} = {short_repr(table[k])}" for k in _MESH_KEYS if k in table)
            raise InputError(f"{where}: mesh_tolerance = {short_repr(table['mesh_tolerance'])} "
                             f"applies to element_size = \"auto\" only (the mesh is given: "
                             f"{given or 'theory = ' + repr(table.get('theory', 'kirchhoff'))})")
        return table
    if asked:
        if "mesh_file" in table:
            raise InputError(f"{where}: element_size = \"auto\" cannot be used with "
                             f"mesh_file = {short_repr(table['mesh_file'])} (the file is the "
                             f"mesh); give one of them")
        for key in ("nx", "ny"):
            if key in table:
                raise InputError(f"{where}: {key} = {short_repr(table[key])} is not used with "
                                 f"element_size = \"auto\" (the mesh is chosen); remove it")
    plate_args["mesh_tolerance"] = table.get("mesh_tolerance", AUTO_TOLERANCE)
    return {k: v for k, v in table.items() if k != "element_size"}


def with_mount_points(bed: BedSection, points) -> BedSection:
    """An auto-meshed bed with nodes at these points (the mounts' ends on
    the bed, drawing frame (P, 2 or 3) [m]); any other bed as it is."""
    if not bed.plate.auto_mesh:
        return bed
    pts = [(float(p[0]), float(p[1])) for p in points]
    if not pts:
        return bed
    plate = replace(bed.plate, mesh_points=tuple(pts))
    return replace(bed, plate=plate)


def read_bed(table: dict, where: str, folder: Path | None = None) -> BedSection:
    """Build a :class:`BedSection` from a parsed ``[bed]`` table.

    Parameters
    ----------
    table : dict
        The table as ``tomllib`` parsed it.
    where : str
        Prefix for messages, e.g. ``"lee.toml: bed"``.
    folder : Path, optional
        The scene file's folder (for a relative ``mesh_file``).

    Raises
    ------
    InputError
        An unknown key or a value out of range, in one line naming the key.
    """
    if not isinstance(table, dict):
        raise InputError(f"{where}: must be a table")
    for key in table:
        if key not in _KEYS:
            raise InputError(f"{where}: unknown key '{key}' (known: {', '.join(_KEYS)})")
    for key, value in table.items():
        for v in (value if isinstance(value, list) else [value]):
            if _is_number_like(v):
                try:
                    bad = out_of_range(float(v))
                except OverflowError:
                    bad = True
                if bad:
                    raise InputError(f"{where}: {key} = {short_repr(v)} is out of range "
                                     f"(magnitudes from {SMALLEST:g} to {LARGEST:g}, or 0)")
    plate_args = {k: table[k] for k in _PLATE_KEYS if k in table}
    table = _auto_mesh(table, plate_args, where)
    geometry = read_geometry(table, where, folder)
    if geometry is not None:
        plate_args["geometry"] = geometry
    masses = read_fixed_masses(table, where)
    if masses:
        plate_args["masses"] = masses
    stiffeners = read_stiffeners(table, where, geometry)
    if stiffeners:
        plate_args["stiffeners"] = stiffeners
    try:
        plate = PlateSpec(**plate_args)
    except PlateSpecError as exc:
        raise InputError(f"{where}: {exc}") from None
    except TypeError as exc:
        raise InputError(f"{where}: {exc}") from None
    check_bed(plate, where, table.get("mesh_file"))   # geometry, mesh, masses, stiffeners
    args: dict[str, Any] = {"plate": plate}
    for key in ("body", "model", "modes_file", "invariants"):
        if key in table:
            if not isinstance(table[key], str):
                raise InputError(f"{where}: {key} = {table[key]!r} must be a string")
            args[key] = table[key]
    for key in ("static_sag", "static_correction"):
        if key in table:
            if not isinstance(table[key], bool):
                raise InputError(f"{where}: {key} = {table[key]!r} must be true or false")
            args[key] = table[key]
    if "correction_modes" in table:
        args["correction_modes"] = table["correction_modes"]
    if table.get("modes") == "auto":
        args["modes"] = None
        args["auto"] = ()
        if "fmax" in table:
            args["fmax"] = table["fmax"]
    elif "fmax" in table:
        args["fmax"] = table["fmax"]
        args["modes"] = table.get("modes")
    elif "modes" in table:
        args["modes"] = table["modes"]
    if "auto_factor" in table:
        args["auto_factor"] = table["auto_factor"]
    if "rayleigh" in table:
        value = table["rayleigh"]
        args["rayleigh"] = tuple(value) if isinstance(value, list) else (value,)
    if "damping_ratio" in table:
        value = table["damping_ratio"]
        args["damping_ratio"] = tuple(value) if isinstance(value, list) else (value,)
    try:
        bed = BedSection(**args)
    except ValueError as exc:
        raise InputError(f"{where}: {exc}") from None
    if bed.modes is not None:
        check_mode_count(bed.plate, bed.modes, f"{where}: modes = {bed.modes}")
    if bed.static_correction:
        check_mode_count(bed.plate, bed.correction_modes,
                         f"{where}: correction_modes = {bed.correction_modes}")
    return bed


def check_mode_count(plate: PlateSpec, n: int, what: str) -> None:
    """Refuse ``n`` elastic modes of a bed whose FE model has fewer
    (:func:`flexbed.fem.layout.elastic_mode_count`, counted on the mesh
    before any assembly; an auto mesh has at most ``MAX_DOFS`` degrees of
    freedom).

    Parameters
    ----------
    plate : PlateSpec
    n : int
        The elastic modes asked for.
    what : str
        The message's start, naming the file, the entry and its value
        (``"lee.toml: bed: modes = 500"``, ``"--modes 500"``).

    Raises
    ------
    InputError
        ``"<what>: the 10 x 10 plate has only 481 elastic modes"``.
    """
    have = elastic_mode_count(plate)
    if have is None:
        if n > MAX_DOFS:
            raise InputError(f"{what}: element_size = \"auto\" meshes the bed "
                             f"with at most {MAX_DOFS:,} degrees of freedom")
    elif n > have:
        mesh = f"the {plate.nx} x {plate.ny} plate" if plate.geometry is None else "the bed's mesh"
        raise InputError(f"{what}: {mesh} has only {have} elastic modes")

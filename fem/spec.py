"""The plate's inputs: geometry, material, mesh — and their hash.

A :class:`PlateSpec` is everything the modes stage computes from; two specs
with the same :meth:`PlateSpec.digest` give the same modes file.
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import asdict, dataclass

from .fixed_masses import FixedMass
from .stiffeners import Section, Stiffener
from .geometry import BedGeometry, GeometryError, Region, Zone


#: the most degrees of freedom a plate mesh may have (4 per node: w, its two
#: slopes and the twist): 250 x 250 elements, whose banded factor takes
#: about 4 GiB; a mesh past it is refused before anything is allocated
MAX_DOFS = 250_000
#: the most memory the banded factor of the stiffness may take [bytes]
MAX_BAND_BYTES = 4 * 2 ** 30


def mesh_size(nx: int, ny: int) -> tuple[int, int]:
    """(degrees of freedom, bytes of the banded factor) of an nx x ny mesh:
    4 unknowns per node, a band about 8 x the nodes across the short side
    (the reverse Cuthill-McKee ordering of :mod:`fem.banded`)."""
    dofs = 4 * (nx + 1) * (ny + 1)
    band = 8 * (min(nx, ny) + 1)
    return dofs, 8 * dofs * (band + 1)


class PlateSpecError(ValueError):
    """A plate input out of its range; ``entry`` names the key."""

    def __init__(self, entry: str, message: str):
        super().__init__(message)
        self.entry = entry


def _short(n: int) -> str:
    return str(n) if n < 10 ** 12 else f"<an integer of {int(n.bit_length() * 0.30103) + 1} digits>"


def _gib(n: int) -> str:
    return f"{n / 2 ** 30:.3g}" if n < 10 ** 300 else "> 1e290"


def _positive(entry: str, value: float) -> None:
    if isinstance(value, bool) or not (isinstance(value, (int, float))
                                       and math.isfinite(value) and value > 0):
        raise PlateSpecError(entry, f"{entry} = {value!r} must be a finite number > 0")


THEORIES = ("kirchhoff", "mindlin")
#: the largest ``mesh_tolerance``: 50 % [-]
MAX_MESH_TOLERANCE = 0.5


@dataclass(frozen=True, slots=True)
class PlateSpec:
    """Rectangular Kirchhoff plate, free on all edges, centred on the origin.

    Parameters
    ----------
    length_x : float
        Side a along x [m].
    length_y : float
        Side b along y [m].
    thickness : float
        Thickness t [m]; the mid-surface is the plane z = 0.
    young : float
        Young's modulus E [Pa].
    poisson : float
        Poisson's ratio ν, -1 < ν < 0.5 [-].
    density : float
        Density ρ [kg/m³].
    nx, ny : int
        Elements along x and y (the mesh has (nx+1)(ny+1) nodes).
    rotary_inertia : bool
        Include the rotary inertia ρt³/12 ∫∇w·∇v in the mass matrix. With
        it, the discrete rigid rotations about x and y carry exactly the
        solid plate's moments of inertia, so the elastic modes are
        orthogonal to the solid's rigid motions. (The Mindlin shell always
        has it.)
    theory : str
        "kirchhoff" (thin plate, bending only, Bogner–Fox–Schmit elements)
        or "mindlin" (Reissner–Mindlin flat shell with membrane, MITC4
        elements, :mod:`flexbed.fem.shell`).
    geometry : BedGeometry or None
        Outline, cut-outs, thickness zones, element size or a mesh file
        (:mod:`flexbed.fem.geometry`; Mindlin only). None: the length_x ×
        length_y rectangle on the nx × ny grid.

    Examples
    --------
    >>> PlateSpec().mass
    2995.2
    """

    length_x: float = 0.8
    length_y: float = 4.8
    thickness: float = 0.1
    young: float = 2.1e11
    poisson: float = 0.3
    density: float = 7800.0
    nx: int = 10
    ny: int = 10
    rotary_inertia: bool = True
    theory: str = "kirchhoff"
    geometry: BedGeometry | None = None
    masses: tuple[FixedMass, ...] = ()
    stiffeners: tuple[Stiffener, ...] = ()
    mesh_tolerance: float | None = None
    mesh_points: tuple[tuple[float, float], ...] = ()

    def __post_init__(self) -> None:
        for entry in ("length_x", "length_y", "thickness", "young", "density"):
            _positive(entry, getattr(self, entry))
            object.__setattr__(self, entry, float(getattr(self, entry)))
        nu = self.poisson
        if isinstance(nu, bool) or not (isinstance(nu, (int, float))
                                        and math.isfinite(nu) and -1.0 < nu < 0.5):
            raise PlateSpecError("poisson", f"poisson = {nu!r} must satisfy -1 < poisson < 0.5")
        object.__setattr__(self, "poisson", float(nu))
        for entry in ("nx", "ny"):
            n = getattr(self, entry)
            if isinstance(n, bool) or not isinstance(n, int) or n < 1:
                raise PlateSpecError(entry, f"{entry} = {n!r} must be an integer >= 1")
        dofs, band_bytes = mesh_size(self.nx, self.ny)
        if dofs > MAX_DOFS or band_bytes > MAX_BAND_BYTES:
            shown = f"{dofs:,}" if dofs < 10 ** 15 else _short(dofs)
            raise PlateSpecError("nx", f"nx = {_short(self.nx)}, ny = {_short(self.ny)} give "
                                       f"{shown} degrees of freedom (banded factor "
                                       f"{_gib(band_bytes)} GiB); the limits are "
                                       f"{MAX_DOFS:,} and {MAX_BAND_BYTES / 2 ** 30:g} GiB")
        if not isinstance(self.rotary_inertia, bool):
            raise PlateSpecError("rotary_inertia",
                                 f"rotary_inertia = {self.rotary_inertia!r} must be true or false")
        if self.theory not in THEORIES:
            raise PlateSpecError("theory", f"theory = {self.theory!r} must be one of "
                                           + ", ".join(f'"{v}"' for v in THEORIES))
        if self.geometry is not None and self.geometry.is_plain:
            object.__setattr__(self, "geometry", None)
        object.__setattr__(self, "masses", tuple(self.masses))
        if not all(isinstance(m, FixedMass) for m in self.masses):
            raise PlateSpecError("masses", "masses must be FixedMass items")
        names = [m.name for m in self.masses]
        if len(set(names)) != len(names):
            raise PlateSpecError("fixed_mass", f"fixed mass names {names!r} must be unique")
        object.__setattr__(self, "stiffeners", tuple(self.stiffeners))
        names = [st.name for st in self.stiffeners]
        if len(set(names)) != len(names):
            raise PlateSpecError("stiffener", f"stiffener names {names!r} must be unique")
        if self.stiffeners and self.theory != "mindlin":
            raise PlateSpecError("theory", "stiffener needs theory = \"mindlin\" (its "
                                           "eccentric coupling needs the membrane)")
        if self.masses and self.theory != "mindlin":
            raise PlateSpecError("theory", "fixed_mass needs theory = \"mindlin\" (the "
                                           "Kirchhoff plate has no in-plane inertia)")
        self._check_auto()
        if self.geometry is not None and self.theory != "mindlin":
            raise PlateSpecError("theory", "outline, cutout, zone, element_size and mesh_file "
                                           "need theory = \"mindlin\" (the Kirchhoff plate is "
                                           "a rectangle on a grid)")

    def _check_auto(self) -> None:
        """``mesh_tolerance`` (element_size = "auto") and ``mesh_points``."""
        tol = self.mesh_tolerance
        if tol is not None:
            if isinstance(tol, bool) or not (isinstance(tol, (int, float)) and math.isfinite(tol)
                                             and 0.0 < tol <= MAX_MESH_TOLERANCE):
                raise PlateSpecError("mesh_tolerance", f"mesh_tolerance = {tol!r} must be a "
                                                       f"fraction > 0 and <= "
                                                       f"{MAX_MESH_TOLERANCE:g} (50 %)")
            object.__setattr__(self, "mesh_tolerance", float(tol))
            if self.theory != "mindlin":
                raise PlateSpecError("element_size", "element_size = \"auto\" needs theory = "
                                                     "\"mindlin\" (the Kirchhoff plate is a "
                                                     "rectangle on its nx x ny grid)")
            g = self.geometry
            if g is not None and (g.mesh_file is not None or g.mesh_digest is not None):
                raise PlateSpecError("element_size", f"element_size = \"auto\" cannot be used "
                                                     f"with mesh_file = {g.mesh_file!r} (the "
                                                     f"file is the mesh); give one of them")
            if g is not None and g.element_size is not None:
                raise PlateSpecError("element_size", f"element_size = {g.element_size!r} and "
                                                     f"\"auto\": give one of them")
        try:
            pts = tuple((float(x), float(y)) for x, y in self.mesh_points)
        except (TypeError, ValueError):
            raise PlateSpecError("mesh_points", f"mesh_points = {self.mesh_points!r} must be "
                                                f"[x, y] points") from None
        if not all(math.isfinite(v) for p in pts for v in p):
            raise PlateSpecError("mesh_points", f"mesh_points = {pts!r} must be finite")
        object.__setattr__(self, "mesh_points", tuple(sorted(set(pts))))
        if pts and self.theory != "mindlin":
            raise PlateSpecError("mesh_points", "mesh_points need theory = \"mindlin\"")

    @classmethod
    def from_dict(cls, d: dict) -> "PlateSpec":
        """Inverse of :meth:`as_dict` (``geometry`` as a nested dict)."""
        d = dict(d)
        g = d.get("geometry")
        if isinstance(g, dict):
            def region(r):
                r = dict(r)
                if r.get("points") is not None:
                    r["points"] = tuple(tuple(p) for p in r["points"])
                for k in ("centre", "size"):
                    if r.get(k) is not None:
                        r[k] = tuple(r[k])
                return Region(**r)
            try:
                d["geometry"] = BedGeometry(
                    outline=g.get("outline"), cutouts=tuple(region(r) for r in g["cutouts"]),
                    zones=tuple(Zone(region(z["region"]), z["thickness"]) for z in g["zones"]),
                    element_size=g.get("element_size"), mesh_digest=g.get("mesh_digest"))
            except (GeometryError, KeyError, TypeError) as exc:
                raise PlateSpecError("geometry", f"geometry: {exc}") from None
        if "masses" in d:
            try:
                d["masses"] = tuple(FixedMass(m["name"], tuple(m["position"]), m["mass"],
                                              tuple(tuple(r) for r in m["inertia"]))
                                    for m in d["masses"])
            except (GeometryError, KeyError, TypeError) as exc:
                raise PlateSpecError("masses", f"masses: {exc}") from None
        if "stiffeners" in d:
            try:
                d["stiffeners"] = tuple(
                    Stiffener(st["name"], tuple(st["start"]), tuple(st["end"]),
                              Section(**st["section"]), st["offset"],
                              st.get("model", "euler-bernoulli"))
                    for st in d["stiffeners"])
            except (GeometryError, KeyError, TypeError) as exc:
                raise PlateSpecError("stiffeners", f"stiffeners: {exc}") from None
        if "mesh_points" in d:
            d["mesh_points"] = tuple(tuple(p) for p in d["mesh_points"])
        return cls(**d)

    @property
    def mass(self) -> float:
        """Mass of the solid plate, ρabt [kg]."""
        return self.density * self.length_x * self.length_y * self.thickness

    @property
    def inertia(self) -> tuple[float, float, float]:
        """Principal moments of inertia of the solid plate about its centre,
        (Jxx, Jyy, Jzz) [kg·m²]."""
        m, a, b, t = self.mass, self.length_x, self.length_y, self.thickness
        return (m * (b * b + t * t) / 12.0, m * (a * a + t * t) / 12.0,
                m * (a * a + b * b) / 12.0)

    @property
    def rigidity(self) -> float:
        """Bending rigidity D = E t³ / (12 (1 - ν²)) [N·m]."""
        return self.young * self.thickness ** 3 / (12.0 * (1.0 - self.poisson ** 2))

    def as_dict(self) -> dict:
        """The inputs as a plain dictionary (JSON-serialisable). ``theory``
        appears only when it is not the default "kirchhoff", so a Kirchhoff
        plate keeps the digest (and modes files) it had before the key
        existed."""
        d = asdict(self)
        if d["theory"] == "kirchhoff":
            del d["theory"]
        if not d["masses"]:
            del d["masses"]
        if not d["stiffeners"]:
            del d["stiffeners"]
        for st in d.get("stiffeners", ()):      # as before the keys existed
            if st["model"] == "euler-bernoulli":
                del st["model"]
                del st["section"]["shear_area"]
        if d["mesh_tolerance"] is None:
            del d["mesh_tolerance"]
        if not d["mesh_points"]:
            del d["mesh_points"]
        else:
            d["mesh_points"] = [list(p) for p in d["mesh_points"]]
        if d["geometry"] is None:
            del d["geometry"]
        else:                      # the mesh file counts by its contents, not its path
            del d["geometry"]["mesh_file"]
        return d

    @property
    def is_rectangle(self) -> bool:
        """True for the plain length_x × length_y plate on its grid."""
        return (self.geometry is None and not self.masses and not self.stiffeners
                and self.mesh_tolerance is None and not self.mesh_points)

    @property
    def auto_mesh(self) -> bool:
        """True when the mesh is chosen for ``mesh_tolerance``."""
        return self.mesh_tolerance is not None

    def digest(self) -> str:
        """SHA-256 of the canonical JSON of the inputs (hex)."""
        text = json.dumps(self.as_dict(), sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()

"""The scene: bodies, base motion, mounts and gravity as frozen dataclasses.

Everything is validated once, in ``__post_init__``; a broken rule raises
:class:`~flexbed.dynamics.errors.SceneError` with a message naming the entry and the
value. NumPy arrays inside are read-only copies. Units are SI.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .body_loads import check_loads
from .errors import SceneError
from .flexible import FlexibleBody
from .laws import BumpStop, CurveLaw, LinearLaw, PolynomialLaw
from .maxwell_terms import check_maxwell
from .time_functions import SHAPES as _SHAPES

__all__ = ["Body", "Drive", "Load", "Base", "Mount", "Scene", "DIRECTIONS"]

DIRECTIONS = ("x", "y", "z")
_LAWS = (LinearLaw, PolynomialLaw, CurveLaw)


def _vector(where: str, name: str, value, shape) -> np.ndarray:
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise SceneError(f"{where}: {name} = {value!r} must be numbers of shape {shape}") from None
    if a.shape != shape:
        raise SceneError(f"{where}: {name} has shape {a.shape}, expected {shape}")
    finite = np.isfinite(a)
    if not finite.all():
        idx = tuple(int(i) for i in np.argwhere(~finite)[0])
        sub = "".join(f"[{i}]" for i in idx)
        raise SceneError(f"{where}: {name}{sub} = {float(a[idx])!r} must be finite")
    a.setflags(write=False)
    return a


def _name(where: str, value) -> str:
    if not isinstance(value, str) or not value.strip():
        raise SceneError(f"{where}: name = {value!r} must be a non-empty string")
    if any(ord(c) < 32 or ord(c) == 127 for c in value):
        raise SceneError(f"{where}: name = {value!r} holds a control character (a line break, "
                         f"a tab, …); names are one line of text")
    return value


@dataclass(frozen=True, slots=True)
class Body:
    """A rigid body.

    Parameters
    ----------
    name : str
        Unique name.
    mass : float
        Mass [kg], > 0.
    inertia : array_like, shape (3, 3) or (3,)
        Inertia tensor about the centre of mass in body axes [kg m²],
        symmetric positive definite; (3,) is the diagonal.
    position : array_like, shape (3,)
        Initial position of the centre of mass (the body-frame origin) [m].
    orientation : array_like, shape (4,)
        Initial Euler parameters (scalar first); normalised here.
    velocity : array_like, shape (3,)
        Initial velocity of the centre of mass (the body-frame origin) in
        the inertial frame [m/s]. The base: only when it is free.
    angular_velocity : array_like, shape (3,)
        Initial angular velocity in the body frame [rad/s] (ω̄, as the
        state holds it). Zero for the base (its orientation is locked).
    """

    name: str
    mass: float
    inertia: np.ndarray
    position: np.ndarray
    orientation: np.ndarray = field(default_factory=lambda: np.array([1.0, 0.0, 0.0, 0.0]))
    velocity: np.ndarray = field(default_factory=lambda: np.zeros(3))
    angular_velocity: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self):
        where = f"body {self.name!r}"
        _name(where, self.name)
        try:
            m = float(self.mass)
        except (TypeError, ValueError):
            raise SceneError(f"{where}: mass = {self.mass!r} must be a number") from None
        if not (math.isfinite(m) and m > 0.0):
            raise SceneError(f"{where}: mass = {m!r} must be > 0")
        object.__setattr__(self, "mass", m)
        try:
            J = np.array(self.inertia, dtype=float)
        except (TypeError, ValueError):
            raise SceneError(f"{where}: inertia = {self.inertia!r} "
                             "must be 3 or 3 × 3 numbers") from None
        if J.shape == (3,):
            J = np.diag(J)
        J = _vector(where, "inertia", J, (3, 3))
        scale = float(np.max(np.abs(J)))
        if np.max(np.abs(J - J.T)) > 1e-9 * scale:
            i, j = np.unravel_index(int(np.argmax(np.abs(J - J.T))), (3, 3))
            raise SceneError(f"{where}: inertia is not symmetric: "
                             f"[{i}][{j}] = {float(J[i, j])!r} but [{j}][{i}] = {float(J[j, i])!r}")
        eig = np.linalg.eigvalsh(0.5 * (J + J.T))
        if not eig[0] > 1e-12 * max(scale, 1e-300):
            raise SceneError(f"{where}: inertia is not positive definite "
                             f"(eigenvalues {', '.join(f'{e:.6g}' for e in eig)})")
        Js = np.array(0.5 * (J + J.T))
        Js.setflags(write=False)
        object.__setattr__(self, "inertia", Js)
        object.__setattr__(self, "position", _vector(where, "position", self.position, (3,)))
        p = _vector(where, "orientation", self.orientation, (4,))
        norm = float(np.linalg.norm(p))
        if norm < 1e-12:
            raise SceneError(f"{where}: orientation = {p.tolist()} is not a rotation")
        p = p / norm
        p.setflags(write=False)
        object.__setattr__(self, "orientation", p)
        object.__setattr__(self, "velocity", _vector(where, "velocity", self.velocity, (3,)))
        object.__setattr__(self, "angular_velocity",
                           _vector(where, "angular_velocity", self.angular_velocity, (3,)))


def _check_input(direction, shape, what: str) -> None:
    """SceneError unless ``direction`` is an axis (0, 1, 2) and ``shape`` a
    time shape; ``what``: "drive" or "load", for the message."""
    if direction not in (0, 1, 2):
        raise SceneError(f"direction = {direction!r} must be 0, 1 or 2 (x, y, z)")
    if not isinstance(shape, _SHAPES):
        raise SceneError(f"shape = {shape!r} is not a {what} shape")


@dataclass(frozen=True, slots=True)
class Drive:
    """Prescribed translational acceleration of the base along one inertial axis.

    direction : int (0, 1, 2 = X, Y, Z); shape : one of
    :data:`flexbed.dynamics.time_functions.SHAPES`, values in m/s².
    """

    direction: int
    shape: object

    def __post_init__(self):
        _check_input(self.direction, self.shape, "drive")


@dataclass(frozen=True, slots=True)
class Load:
    """External force on the base's centre of mass along one inertial axis [N]."""

    direction: int
    shape: object

    def __post_init__(self):
        _check_input(self.direction, self.shape, "load")


@dataclass(frozen=True, slots=True)
class Base:
    """How body 1 (the base) moves. Its orientation is always locked.

    motion : "fixed" | "driven" | "free"
    drives : tuple of Drive — ``driven`` only; they add up.
    loads : tuple of Load — ``free`` only; they add up.
    support : "static" or array_like (3,) — ``free`` only: constant force [N];
        "static" is minus the whole system's weight.
    """

    motion: str = "fixed"
    drives: tuple = ()
    loads: tuple = ()
    support: object = "none"

    def __post_init__(self):
        if self.motion not in ("fixed", "driven", "free"):
            raise SceneError(f"base: motion = {self.motion!r} must be 'fixed', 'driven' or 'free'")
        object.__setattr__(self, "drives", tuple(self.drives))
        object.__setattr__(self, "loads", tuple(self.loads))
        for i, d in enumerate(self.drives):
            if not isinstance(d, Drive):
                raise SceneError(f"base: drive[{i}] = {d!r} is not a Drive")
        for i, d in enumerate(self.loads):
            if not isinstance(d, Load):
                raise SceneError(f"base: force[{i}] = {d!r} is not a Load")
        if self.drives and self.motion != "driven":
            raise SceneError(f"base: {len(self.drives)} drive(s) given but motion = "
                             f"{self.motion!r} (drives need motion = 'driven')")
        if self.loads and self.motion != "free":
            raise SceneError(f"base: {len(self.loads)} force(s) given but motion = "
                             f"{self.motion!r} (forces act only on a free base)")
        if isinstance(self.support, str):
            if self.support not in ("static", "none"):
                raise SceneError(f"base: support = {self.support!r} must be 'static' or 3 numbers")
            if self.support == "static" and self.motion != "free":
                raise SceneError("base: support = 'static' needs motion = 'free', "
                                 f"not {self.motion!r}")
        else:
            s = _vector("base", "support", self.support, (3,))
            if self.motion != "free" and np.any(s != 0):
                raise SceneError(f"base: support = {s.tolist()} needs motion = 'free', "
                                 f"not {self.motion!r}")
            object.__setattr__(self, "support", s)


@dataclass(frozen=True, slots=True)
class Mount:
    """A three-direction mount between two bodies (paper eq. 1–6).

    Parameters
    ----------
    name : str
    body_i, body_j : str
        Names of the reference body i and of body j.
    point_i, point_j : array_like, shape (3,)
        P_i in body i's frame and P_j in body j's frame [m].
    axes : array_like, shape (3, 3)
        Rows u1, u2, u3 in body i's frame: orthonormal, right-handed (1e-9).
    laws : tuple of 3 laws
        One per direction: LinearLaw, PolynomialLaw or CurveLaw.
    stops : tuple of 3 BumpStop or None, optional
        A bump stop (snubber) per direction, or None (default: none).
    """

    name: str
    body_i: str
    body_j: str
    point_i: np.ndarray
    point_j: np.ndarray
    axes: np.ndarray
    laws: tuple
    stops: tuple = (None, None, None)

    def __post_init__(self):
        where = f"mount {self.name!r}"
        _name(where, self.name)
        for key in ("body_i", "body_j"):
            v = getattr(self, key)
            if not isinstance(v, str) or not v:
                raise SceneError(f"{where}: {key} = {v!r} must be a body name")
        if self.body_i == self.body_j:
            raise SceneError(f"{where}: body_i and body_j are both {self.body_i!r}")
        object.__setattr__(self, "point_i", _vector(where, "point_i", self.point_i, (3,)))
        object.__setattr__(self, "point_j", _vector(where, "point_j", self.point_j, (3,)))
        U = _vector(where, "axes", self.axes, (3, 3))
        err = float(np.max(np.abs(U @ U.T - np.eye(3))))
        if err > 1e-9:
            raise SceneError(f"{where}: axes are not orthonormal "
                             f"(max |U Uᵀ − I| = {err:.3g}, tolerance 1e-9)")
        det = float(np.linalg.det(U))
        if det < 0:
            raise SceneError(f"{where}: axes are left-handed (det = {det:.6g}); "
                             f"u3 must be u1 × u2")
        object.__setattr__(self, "axes", U)
        laws = tuple(self.laws)
        if len(laws) != 3:
            raise SceneError(f"{where}: {len(laws)} laws given, need one per direction (3)")
        for k, law in enumerate(laws):
            if not isinstance(law, _LAWS):
                raise SceneError(f"{where}: law[{k}] = {law!r} is not a mount law")
        object.__setattr__(self, "laws", laws)
        stops = tuple(self.stops)
        if len(stops) != 3 or not all(s is None or isinstance(s, BumpStop) for s in stops):
            raise SceneError(f"{where}: stops = {stops!r} must be 3 BumpStop or None")
        object.__setattr__(self, "stops", stops)


@dataclass(frozen=True, slots=True)
class Scene:
    """The whole mount system.

    Parameters
    ----------
    bodies : tuple of Body
        Body 1 (index 0) is the base; the others are free rigid bodies.
    base : Base
        How the base moves.
    mounts : tuple of Mount
    gravity : array_like, shape (3,)
        Gravity vector in the inertial frame [m/s²].
    name : str
    flexible : tuple of (str, FlexibleBody)
        Bodies modelled as flexible (floating frame), by name. Their mass
        and inertia come from the FlexibleBody and must agree with the
        body's table within 1e-4 (rounding of published values).
    loads : tuple of BodyLoad
        External forces and moments on bodies other than the base
        (:mod:`flexbed.dynamics.body_loads`); they add up.
    maxwell : tuple of MaxwellSeries
        Generalised Maxwell terms of elastomer mounts, one internal state
        per term (:mod:`flexbed.dynamics.maxwell_terms`); time runs only.
    """

    bodies: tuple
    base: Base = field(default_factory=Base)
    mounts: tuple = ()
    gravity: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, -9.81]))
    name: str = "scene"
    flexible: tuple = ()
    loads: tuple = ()
    maxwell: tuple = ()

    def __post_init__(self):
        bodies = tuple(self.bodies)
        if not bodies:
            raise SceneError("scene has no bodies (body 1, the base, is required)")
        for i, b in enumerate(bodies):
            if not isinstance(b, Body):
                raise SceneError(f"body[{i}] = {b!r} is not a Body")
        names = [b.name for b in bodies]
        for i, n in enumerate(names):
            if n in names[:i]:
                raise SceneError(f"body {n!r}: name is used twice (bodies {names.index(n) + 1} "
                                 f"and {i + 1})")
        if not isinstance(self.base, Base):
            raise SceneError(f"base = {self.base!r} is not a Base")
        base = bodies[0]
        if np.any(base.velocity != 0.0) and self.base.motion != "free":
            raise SceneError(f"body {base.name!r}: velocity = {base.velocity.tolist()} needs "
                             f"base motion = 'free' (a {self.base.motion} base moves as its "
                             f"motion prescribes, from rest)")
        if np.any(base.angular_velocity != 0.0):
            raise SceneError(f"body {base.name!r}: angular_velocity = "
                             f"{base.angular_velocity.tolist()} must be zero: the base's "
                             f"orientation is locked")
        for b in bodies[1:]:        # the base's orientation is locked: its inertia plays no part
            J = np.linalg.eigvalsh(b.inertia)
            if J[0] + J[1] < J[2] * (1.0 - 1e-9):
                raise SceneError(f"body {b.name!r}: inertia has principal moments "
                                 f"{J[0]:.6g}, {J[1]:.6g}, {J[2]:.6g} kg m^2, which break the "
                                 f"triangle inequality J1 + J2 >= J3 ({J[0] + J[1]:.6g} < "
                                 f"{J[2]:.6g}): no body has them")
        mounts = tuple(self.mounts)
        mnames = []
        for i, m in enumerate(mounts):
            if not isinstance(m, Mount):
                raise SceneError(f"mount[{i}] = {m!r} is not a Mount")
            if m.name in mnames:
                raise SceneError(f"mount {m.name!r}: name is used twice")
            mnames.append(m.name)
            for key in ("body_i", "body_j"):
                if getattr(m, key) not in names:
                    raise SceneError(f"mount {m.name!r}: {key} = {getattr(m, key)!r} is not a body "
                                     f"(bodies: {', '.join(names)})")
        flexible = tuple(self.flexible)
        for entry in flexible:
            name, fb = entry
            if name not in names:
                raise SceneError(f"flexible body {name!r} is not a body "
                                 f"(bodies: {', '.join(names)})")
            if name == names[0]:
                raise SceneError(f"body {name!r}: the base cannot be flexible")
            if not isinstance(fb, FlexibleBody):
                raise SceneError(f"body {name!r}: {fb!r} is not a FlexibleBody")
            body = bodies[names.index(name)]
            if abs(fb.mass - body.mass) > 1e-4 * body.mass:
                raise SceneError(f"body {name!r}: mass = {body.mass!r} kg differs from the "
                                 f"flexible model's {fb.mass:.6g} kg")
            J = body.inertia
            if np.abs(fb.inertia - J).max() > 1e-4 * np.abs(J).max():
                raise SceneError(f"body {name!r}: inertia {np.diag(J).tolist()} differs from "
                                 f"the flexible model's "
                                 f"[{', '.join(f'{v:.6g}' for v in np.diag(fb.inertia))}] kg m^2")
            for m in mounts:
                for key, point in (("body_i", m.point_i), ("body_j", m.point_j)):
                    if getattr(m, key) == name:
                        fb.point_index(point)   # raises if no shapes for that point
        if len({n for n, _ in flexible}) != len(flexible):
            raise SceneError("a body is listed as flexible twice")
        object.__setattr__(self, "loads", check_loads(self.loads, names, dict(flexible)))
        object.__setattr__(self, "maxwell", check_maxwell(self.maxwell, mnames))
        object.__setattr__(self, "flexible", flexible)
        object.__setattr__(self, "bodies", bodies)
        object.__setattr__(self, "mounts", mounts)
        object.__setattr__(self, "gravity", _vector("scene", "gravity", self.gravity, (3,)))

    def body_index(self, name: str) -> int:
        """0-based index of the body called ``name``."""
        for i, b in enumerate(self.bodies):
            if b.name == name:
                return i
        raise SceneError(f"{name!r} is not a body")

    @property
    def total_mass(self) -> float:
        return float(sum(b.mass for b in self.bodies))

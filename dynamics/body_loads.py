"""External loads on any body: forces and moments at a body point, and the
running machinery that makes them (rotating unbalance, harmonic orders).

A :class:`BodyLoad` is one component of a force [N] or a moment [N m] at a
point ū of a body (body frame [m]; on a flexible body the point moves with
the modes, so a force there projects onto them by the mode shapes at the
point, as a mount end's does), along an axis of the inertial frame or of
the body's frame, with a time shape of
:data:`flexbed.dynamics.time_functions.SHAPES`. The compiled right-hand side
adds them to the bodies' generalized forces (:mod:`flexbed.dynamics.kernel`,
section 4b), so statics (a constant load at t = 0 enters the equilibrium),
every integrator and the linearisation see them.

Running machinery (Den Hartog, *Mechanical Vibrations*, §3.3; ISO 21940-11
for the unbalance m·e):

- a rotating unbalance m·e [kg m] spinning at Ω = 2π f about a body axis
  gives the rotating force ``m e Ω² (cos(Ωt + φ) e₁ + sin(Ωt + φ) e₂)`` in
  the plane normal to the axis (e₁, e₂, axis right-handed): two body-frame
  sinusoids in quadrature (:func:`unbalance`);
- over a run-up from f₀ to f₁ in time T the speed rises linearly, the
  angle is ``θ = 2π (f₀ u + ½ (f₁ − f₀) u²/T)``, u = t − start, and the
  force ``m e (2π f(u))² (cos θ, sin θ)``, sampled as curve data (a cubic
  spline through 64 samples per revolution at the top speed: relative
  interpolation error below 1e-6), then the steady sinusoids at f₁,
  phase-continuous;
- a harmonic order k of a running speed f is a sinusoid at k·f
  (:func:`harmonic`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .errors import SceneError
from .time_functions import SHAPES, Curve, Sinusoid

__all__ = ["BodyLoad", "FRAMES", "QUANTITIES", "unbalance", "harmonic", "check_loads",
           "RUNUP_SAMPLES_PER_REV"]

FRAMES = ("inertial", "body")
QUANTITIES = ("force", "moment")
#: samples per revolution (at the top speed) of a run-up's force curve
RUNUP_SAMPLES_PER_REV = 64


@dataclass(frozen=True, slots=True)
class BodyLoad:
    """One component of an external force or moment on a body.

    Parameters
    ----------
    body : str
        The body's name (not the base: its loads are ``Base.loads``).
    point : array_like, shape (3,)
        Point of application in the body frame [m] (for a moment: the point
        whose rotation it works on; on a rigid body it plays no part).
    direction : int
        0, 1, 2: x, y, z of ``frame``.
    shape : one of :data:`flexbed.dynamics.time_functions.SHAPES`
        Values in N (force) or N m (moment).
    frame : str
        "inertial" (the axis stays fixed in space) or "body" (it turns with
        the body).
    quantity : str
        "force" or "moment".
    name : str
        A label for messages and outputs.
    """

    body: str
    point: np.ndarray
    direction: int
    shape: object
    frame: str = "inertial"
    quantity: str = "force"
    name: str = "load"

    def __post_init__(self):
        where = f"load {self.name!r}"
        if not isinstance(self.body, str) or not self.body:
            raise SceneError(f"{where}: body = {self.body!r} must be a body name")
        try:
            p = np.array(self.point, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise SceneError(f"{where}: point = {self.point!r} must be 3 numbers") from None
        if p.shape != (3,) or not np.all(np.isfinite(p)):
            raise SceneError(f"{where}: point = {self.point!r} must be 3 finite numbers [m]")
        p.setflags(write=False)
        object.__setattr__(self, "point", p)
        if self.direction not in (0, 1, 2):
            raise SceneError(f"{where}: direction = {self.direction!r} must be 0, 1 or 2")
        if not isinstance(self.shape, SHAPES):
            raise SceneError(f"{where}: shape = {self.shape!r} is not a load shape")
        if self.frame not in FRAMES:
            raise SceneError(f"{where}: frame = {self.frame!r} must be 'inertial' or 'body'")
        if self.quantity not in QUANTITIES:
            raise SceneError(f"{where}: quantity = {self.quantity!r} must be 'force' or "
                             f"'moment'")


def check_loads(loads: tuple, names: list, flexible: dict) -> tuple:
    """The scene's loads checked against its bodies (``Scene`` calls this).

    names : the bodies' names, the base first; flexible : name →
    FlexibleBody. Raises SceneError naming the load for a load on the
    base, on a body that does not exist, a moment on a flexible body, or a
    point of a flexible body without mode shapes.
    """
    loads = tuple(loads)
    for i, ld in enumerate(loads):
        if not isinstance(ld, BodyLoad):
            raise SceneError(f"load[{i}] = {ld!r} is not a BodyLoad")
        where = f"load {ld.name!r}"
        if ld.body not in names:
            raise SceneError(f"{where}: body = {ld.body!r} is not a body "
                             f"(bodies: {', '.join(names)})")
        if ld.body == names[0]:
            raise SceneError(f"{where}: body = {ld.body!r} is the base; loads on the base are "
                             f"[[base.force]] entries of a free base")
        fb = flexible.get(ld.body)
        if fb is not None:
            if ld.quantity == "moment":
                raise SceneError(f"{where}: a moment on the flexible body {ld.body!r} is not "
                                 f"supported (its modes' rotations at the point are not "
                                 f"kept); give it as a couple of forces")
            try:
                fb.point_index(ld.point)
            except SceneError:
                raise SceneError(f"{where}: point = {ld.point.tolist()} m: the flexible body "
                                 f"{ld.body!r} has no mode shapes there") from None
    return loads


def _speed(where: str, f) -> float:
    try:
        f = float(f)
    except (TypeError, ValueError):
        raise SceneError(f"{where}: speed = {f!r} must be a number [Hz]") from None
    if not (math.isfinite(f) and f > 0.0):
        raise SceneError(f"{where}: speed = {f!r} Hz must be > 0 (a running speed)")
    return f


def _plane(axis: int) -> tuple[int, int]:
    """The body axes e₁, e₂ with (e₁, e₂, axis) right-handed."""
    return {0: (1, 2), 1: (2, 0), 2: (0, 1)}[axis]


def unbalance(name: str, body: str, point, axis: int, me: float, speed, phase: float = 0.0,
              start: float = 0.0, duration: float = math.inf,
              runup: float | None = None) -> tuple:
    """The body-frame loads of a rotating unbalance.

    Parameters
    ----------
    name, body : str
    point : array_like (3,)
        The rotor's point on the body's axis [m], body frame.
    axis : int
        Spin axis: body x, y or z (0, 1, 2).
    me : float
        Unbalance m·e [kg m], > 0.
    speed : float or (float, float)
        Running speed f [Hz] > 0, or (f₀, f₁) for a run-up (f₀ ≥ 0, f₁ > 0).
    phase : float
        Angle of the unbalance at ``start`` [rad], measured from e₁.
    start, duration : float
        When it runs [s]; a run-up's steady part runs from start + runup on.
    runup : float, optional
        The run-up's time T [s] (needs two speeds).

    Returns
    -------
    tuple of BodyLoad
        Along e₁ and e₂: their sum is ``m e Ω² (cos(Ωu + φ), sin(Ωu + φ))``.
    """
    where = f"unbalance {name!r}"
    try:
        me = float(me)
    except (TypeError, ValueError):
        raise SceneError(f"{where}: mass_radius = {me!r} must be a number [kg m]") from None
    if not (math.isfinite(me) and me > 0.0):
        raise SceneError(f"{where}: mass_radius = {me!r} kg m must be > 0")
    e1, e2 = _plane(axis)
    if runup is None:
        if not np.isscalar(speed):
            raise SceneError(f"{where}: speed = {speed!r}: two speeds need a runup time")
        f = _speed(where, speed)
        F = me * (2.0 * math.pi * f) ** 2
        groups = ((Sinusoid(F, f, phase + math.pi / 2, start, duration),),
                  (Sinusoid(F, f, phase, start, duration),))
    else:
        groups = _runup(where, me, speed, phase, start, runup)
    return tuple(BodyLoad(body, point, d, s, "body", "force", f"{name} {'xyz'[d]}")
                 for d, group in zip((e1, e2), groups) for s in group)


def _runup(where: str, me: float, speed, phase: float, start: float, T: float) -> tuple:
    """Two groups of shapes (along e₁, e₂): the run-up as curve data, then
    the steady sinusoids at the top speed."""
    try:
        f0, f1 = (float(v) for v in speed)
    except (TypeError, ValueError):
        raise SceneError(f"{where}: speed = {speed!r} must be two speeds [Hz] for a "
                         f"run-up") from None
    if not (math.isfinite(f0) and f0 >= 0.0):
        raise SceneError(f"{where}: speed[0] = {f0!r} Hz must be >= 0")
    _speed(where, f1)
    if not (math.isfinite(T) and T > 0.0):
        raise SceneError(f"{where}: runup = {T!r} s must be > 0")
    fmax = max(f0, f1)
    n = max(int(math.ceil(RUNUP_SAMPLES_PER_REV * fmax * T)), 8)
    u = np.linspace(0.0, T, n + 1)
    f = f0 + (f1 - f0) * u / T
    theta = 2.0 * math.pi * (f0 * u + 0.5 * (f1 - f0) * u * u / T) + phase
    F = me * (2.0 * math.pi * f) ** 2
    t = start + u
    c1 = Curve(t, F * np.cos(theta))
    c2 = Curve(t, F * np.sin(theta))
    # the curves hold their last value after T: the steady sinusoids take over minus it
    Ft = me * (2.0 * math.pi * f1) ** 2
    th = float(theta[-1])
    s1 = Sinusoid(Ft, f1, th + math.pi / 2, start + T)
    s2 = Sinusoid(Ft, f1, th, start + T)
    return ((c1, s1, _cancel(t[-1], float(F[-1] * math.cos(th)))),
            (c2, s2, _cancel(t[-1], float(F[-1] * math.sin(th)))))


def _cancel(t_end: float, value: float) -> Curve:
    """A curve of −value from t_end on (cancels a curve's held last value)."""
    dt = 1.0
    return Curve(t_end + dt * np.arange(4), np.full(4, -value))


def harmonic(name: str, body: str, point, direction: int, amplitude: float, speed, order,
             phase: float = 0.0, start: float = 0.0, duration: float = math.inf,
             frame: str = "body", quantity: str = "force") -> BodyLoad:
    """Harmonic order k of a running speed f: a sinusoid at k·f [Hz] of the
    given amplitude [N or N m] and phase [rad]."""
    where = f"harmonic {name!r}"
    f = _speed(where, speed)
    try:
        k = float(order)
    except (TypeError, ValueError):
        raise SceneError(f"{where}: order = {order!r} must be a number") from None
    if not (math.isfinite(k) and k > 0.0):
        raise SceneError(f"{where}: order = {k!r} must be > 0")
    return BodyLoad(body, point, direction, Sinusoid(amplitude, k * f, phase, start, duration),
                    frame, quantity, name)

"""Shapes of base drives and loads as functions of time (paper Fig. 4).

Each shape is a frozen dataclass of its parameters. ``compile()`` returns a
:class:`TimeFunction` that gives the value ``f(t)`` and its exact first and
second integrals from rest (for a drive: acceleration, velocity,
displacement), plus the breakpoints where the function or a derivative
jumps, which the integrators step onto.

``max_step`` [s] is the longest step an adaptive integrator may take while
the shape is active (between its first and last breakpoint), so that it
cannot step over the input while the system is still at rest: a quarter
period for a sinusoid, 20 sample spacings for curve data; pulses need none
(each piece lies between breakpoints).

Before ``start`` every shape is zero. After its end a pulse is zero, a
sinusoid with a duration is zero, and curve data hold their last value.
The sawtooth drops from its peak to zero instantaneously: its end is a
breakpoint where the value jumps (its integrals stay continuous). So do the
square pulse (at both ends) and the initial-peak sawtooth (at its start).
Shock pulses as specifications state them (half-sine, haversine, with
compensation) are sums of these shapes: :mod:`flexbed.dynamics.pulses`.

Curve data are cubic splines whose end conditions (:class:`SplineEnds`)
are "not-a-knot" (the default), "natural" or "clamped".
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .errors import SceneError
from .piecewise import END_CONDITIONS, PiecewisePolynomial, spline_with_tails

__all__ = ["Sinusoid", "Triangle", "Trapezoid", "Sawtooth", "Square", "InitialPeakSawtooth",
           "Curve", "SplineEnds", "TimeFunction", "MIN_CURVE_POINTS", "END_CONDITIONS",
           "SHAPES", "summed", "jumps"]

MIN_CURVE_POINTS = 4
CURVE_SAMPLES_PER_STEP = 20     # adaptive steps span at most this many sample spacings


def _finite(name: str, value: float) -> float:
    value = float(value)
    if not math.isfinite(value):
        raise SceneError(f"{name} = {value!r} must be finite")
    return value


def _positive(name: str, value: float) -> float:
    value = _finite(name, value)
    if not value > 0.0:
        raise SceneError(f"{name} = {value!r} must be > 0")
    return value


def _non_negative(name: str, value: float) -> float:
    value = _finite(name, value)
    if value < 0.0:
        raise SceneError(f"{name} = {value!r} must be >= 0")
    return value


class TimeFunction:
    """Compiled shape: ``value``, ``first`` and ``second`` integrals, breakpoints.

    ``value(t, seg_end=None)``, ``first(t, seg_end=None)``,
    ``second(t, seg_end=None)`` take a scalar time [s] and are cheap (pure
    Python). They are right-continuous at breakpoints, except at ``seg_end``
    (the end of the segment an integrator is stepping through), where they
    give the limit from the left: from inside the segment.
    ``values(t)`` etc. take arrays.
    """

    __slots__ = ("value", "first", "second", "breakpoints", "values", "firsts", "seconds",
                 "support", "max_step")

    def __init__(self, value, first, second, breakpoints, values, firsts, seconds,
                 support=(0.0, math.inf), max_step=math.inf):
        self.support = (float(support[0]), float(support[1]))
        self.max_step = float(max_step)
        self.value = value
        self.first = first
        self.second = second
        self.breakpoints = tuple(float(b) for b in breakpoints)
        self.values = values
        self.firsts = firsts
        self.seconds = seconds

    @classmethod
    def from_piecewise(cls, f: PiecewisePolynomial, breakpoints,
                       max_step=math.inf) -> "TimeFunction":
        f1 = f.antiderivative()
        f2 = f1.antiderivative()
        return cls(f, f1, f2, breakpoints, f.evaluate, f1.evaluate, f2.evaluate,
                   support=(breakpoints[0], breakpoints[-1]), max_step=max_step)


@dataclass(frozen=True, slots=True)
class Sinusoid:
    """a(t) = amplitude · sin(2π·frequency·(t − start) + phase) on [start, start + duration].

    amplitude : float [unit of the quantity]; frequency : float > 0 [Hz];
    phase : float [rad]; start : float >= 0 [s]; duration : float > 0 [s] or inf.
    """

    amplitude: float
    frequency: float
    phase: float = 0.0
    start: float = 0.0
    duration: float = math.inf

    def __post_init__(self):
        _finite("amplitude", self.amplitude)
        _positive("frequency", self.frequency)
        _finite("phase", self.phase)
        _non_negative("start", self.start)
        d = float(self.duration)
        if not (d > 0.0):
            raise SceneError(f"duration = {d!r} must be > 0")

    @property
    def end(self) -> float:
        return self.start + self.duration

    def compile(self) -> TimeFunction:
        A, w, ph, s, T = (float(self.amplitude), 2 * math.pi * float(self.frequency),
                          float(self.phase), float(self.start), float(self.duration))
        end = s + T
        cph, sph = math.cos(ph), math.sin(ph)

        def v_in(u):          # first integral on the window, u = t - s
            return A / w * (cph - math.cos(w * u + ph))

        def d_in(u):
            return A / w * cph * u - A / (w * w) * (math.sin(w * u + ph) - sph)

        v_end = v_in(T) if math.isfinite(T) else 0.0
        d_end = d_in(T) if math.isfinite(T) else 0.0

        def inside(t, seg_end):
            # right-continuous window [s, end), left limit at a segment's end
            if seg_end is not None and t >= seg_end:
                return s < t <= end
            return s <= t < end

        def value(t, seg_end=None):
            if not inside(t, seg_end):
                return 0.0
            return A * math.sin(w * (t - s) + ph)

        def first(t, seg_end=None):
            if t <= s:
                return 0.0
            if t >= end:
                return v_end
            return v_in(t - s)

        def second(t, seg_end=None):
            if t <= s:
                return 0.0
            if t >= end:
                return d_end + v_end * (t - end)
            return d_in(t - s)

        def values(t):        # the three, vectorised, right-continuous as above
            t = np.asarray(t, dtype=float)
            return np.where((t >= s) & (t < end), A * np.sin(w * (t - s) + ph), 0.0)

        def firsts(t):
            t = np.asarray(t, dtype=float)
            u = np.clip(t, s, end) - s
            return np.where(t <= s, 0.0, A / w * (cph - np.cos(w * u + ph)))

        def seconds(t):
            t = np.asarray(t, dtype=float)
            u = np.clip(t, s, end) - s
            inside = A / w * cph * u - A / (w * w) * (np.sin(w * u + ph) - sph)
            after = v_end * (t - end) if math.isfinite(end) else 0.0
            return np.where(t <= s, 0.0, np.where(t >= end, d_end + after, inside))

        bps = [s] + ([end] if math.isfinite(end) else [])
        return TimeFunction(value, first, second, bps, values, firsts, seconds,
                            support=(s, end), max_step=0.25 / float(self.frequency))

    def sample_times(self, dt: float) -> np.ndarray:
        if not math.isfinite(self.duration):
            raise SceneError("sample needs a sinusoid with a finite duration")
        return _grid(self.start, self.end, dt)


#: the most samples ``sample`` may make of one shape (as many as the
#: longest output a run may have, :data:`integrate.MAX_OUTPUT_SAMPLES`)
MAX_SAMPLES = 10_000_000


def _grid(a: float, b: float, dt: float) -> np.ndarray:
    dt = _positive("sample", dt)
    count = (b - a) / dt + 1.0
    if not count <= MAX_SAMPLES:
        raise SceneError(f"sample = {dt:g} s over {b - a:g} s gives {count:.3g} samples; "
                         f"the limit is {MAX_SAMPLES:.0e} (a larger sample)")
    n = int(math.floor((b - a) / dt + 1e-9))
    t = a + dt * np.arange(n + 1)
    if b - t[-1] > 1e-9 * dt:
        t = np.append(t, b)
    else:
        t[-1] = b
    return t


def _pulse(peak: float, start: float, rise: float, flat: float, fall: float) -> TimeFunction:
    s1, s2, s3 = start + rise, start + rise + flat, start + rise + flat + fall
    breaks = [start, s1] + ([s2] if flat > 0 else []) + [s3]
    rows = [[0.0, 0.0], [0.0, peak / rise]]
    if flat > 0:
        rows.append([peak, 0.0])
    rows += [[peak, -peak / fall], [0.0, 0.0]]
    return TimeFunction.from_piecewise(PiecewisePolynomial(breaks, rows), breaks)


@dataclass(frozen=True, slots=True)
class Triangle:
    """Triangular pulse: 0 at start, ``peak`` after ``rise``, 0 again after ``fall`` [s]."""

    peak: float
    rise: float
    fall: float
    start: float = 0.0

    def __post_init__(self):
        _finite("peak", self.peak)
        _positive("rise", self.rise)
        _positive("fall", self.fall)
        _non_negative("start", self.start)

    @property
    def end(self) -> float:
        return self.start + self.rise + self.fall

    def compile(self) -> TimeFunction:
        return _pulse(float(self.peak), float(self.start), float(self.rise), 0.0, float(self.fall))

    def sample_times(self, dt: float) -> np.ndarray:
        return _grid(self.start, self.end, dt)


@dataclass(frozen=True, slots=True)
class Trapezoid:
    """Trapezoidal pulse: ramp up over ``rise``, hold ``peak`` for ``flat``,
    ramp down over ``fall``."""

    peak: float
    rise: float
    flat: float
    fall: float
    start: float = 0.0

    def __post_init__(self):
        _finite("peak", self.peak)
        _positive("rise", self.rise)
        _non_negative("flat", self.flat)
        _positive("fall", self.fall)
        _non_negative("start", self.start)

    @property
    def end(self) -> float:
        return self.start + self.rise + self.flat + self.fall

    def compile(self) -> TimeFunction:
        return _pulse(float(self.peak), float(self.start), float(self.rise),
                      float(self.flat), float(self.fall))

    def sample_times(self, dt: float) -> np.ndarray:
        return _grid(self.start, self.end, dt)


@dataclass(frozen=True, slots=True)
class Sawtooth:
    """Terminal-peak sawtooth (shock standards): 0 at ``start``, rising
    linearly to ``peak`` after ``rise`` [s], then dropping to 0 at once.

    The drop at ``start + rise`` is a breakpoint: the integrators stop on it
    and see the peak from the left, zero from the right. Velocity and
    displacement are the exact integrals: peak·rise/2 and
    peak·rise²/6 at the drop.
    """

    peak: float
    rise: float
    start: float = 0.0

    def __post_init__(self):
        _finite("peak", self.peak)
        _positive("rise", self.rise)
        _non_negative("start", self.start)

    @property
    def end(self) -> float:
        return self.start + self.rise

    def compile(self) -> TimeFunction:
        peak, s, rise = float(self.peak), float(self.start), float(self.rise)
        breaks = [s, s + rise]
        rows = [[0.0, 0.0], [0.0, peak / rise], [0.0, 0.0]]
        return TimeFunction.from_piecewise(PiecewisePolynomial(breaks, rows), breaks)

    def sample_times(self, dt: float) -> np.ndarray:
        raise SceneError("sample does not apply to shape = 'sawtooth': a cubic spline through "
                         "samples of its instantaneous drop overshoots (by 5 % of the peak "
                         "however fine the samples); the sawtooth is used exactly, the "
                         "integrators stop at the drop")


@dataclass(frozen=True, slots=True)
class Square:
    """Rectangular pulse: ``peak`` on [start, start + duration), 0 elsewhere.

    Both ends are breakpoints where the value jumps; velocity
    peak·(t − start) and displacement peak·(t − start)²/2 on the pulse are
    the exact integrals.
    """

    peak: float
    duration: float
    start: float = 0.0

    def __post_init__(self):
        _finite("peak", self.peak)
        _positive("duration", self.duration)
        _non_negative("start", self.start)

    @property
    def end(self) -> float:
        return self.start + self.duration

    def compile(self) -> TimeFunction:
        s, d = float(self.start), float(self.duration)
        breaks = [s, s + d]
        rows = [[0.0], [float(self.peak)], [0.0]]
        return TimeFunction.from_piecewise(PiecewisePolynomial(breaks, rows), breaks)

    def sample_times(self, dt: float) -> np.ndarray:
        raise SceneError("sample does not apply to shape = 'square' (its ends are jumps, "
                         "used exactly)")


@dataclass(frozen=True, slots=True)
class InitialPeakSawtooth:
    """Initial-peak sawtooth: a jump to ``peak`` at ``start``, then a linear
    decay to 0 at ``start + duration`` [s].

    The jump at ``start`` is a breakpoint (the integrators see 0 before it
    and the peak after); velocity and displacement are the exact integrals:
    peak·duration/2 and peak·duration²/3 at the end.
    """

    peak: float
    duration: float
    start: float = 0.0

    def __post_init__(self):
        _finite("peak", self.peak)
        _positive("duration", self.duration)
        _non_negative("start", self.start)

    @property
    def end(self) -> float:
        return self.start + self.duration

    def compile(self) -> TimeFunction:
        p, s, d = float(self.peak), float(self.start), float(self.duration)
        breaks = [s, s + d]
        rows = [[0.0, 0.0], [p, -p / d], [0.0, 0.0]]
        return TimeFunction.from_piecewise(PiecewisePolynomial(breaks, rows), breaks)

    def sample_times(self, dt: float) -> np.ndarray:
        raise SceneError("sample does not apply to shape = 'initial-peak-sawtooth' (its "
                         "start is a jump, used exactly)")


@dataclass(frozen=True, slots=True)
class SplineEnds:
    """End conditions of a cubic spline through curve data.

    condition : {"not-a-knot", "natural", "clamped"}
        "not-a-knot": third derivative continuous at the second and the
        last-but-one sample (a cubic's samples give back that cubic);
        "natural": zero second derivative at both ends; "clamped": the
        first derivative at both ends is ``slopes``.
    slopes : (float, float)
        dy/dx at the first and the last sample for "clamped" [unit of the
        value per unit of the abscissa]; (0, 0) otherwise.
    """

    condition: str = "not-a-knot"
    slopes: tuple = (0.0, 0.0)

    def __post_init__(self):
        if self.condition not in END_CONDITIONS:
            raise SceneError(f"end_condition = {self.condition!r} must be one of "
                             f"{', '.join(map(repr, END_CONDITIONS))}")
        try:
            slopes = tuple(float(v) for v in self.slopes)
        except (TypeError, ValueError):
            raise SceneError(f"end_slopes = {self.slopes!r} must be two numbers") from None
        if len(slopes) != 2:
            raise SceneError(f"end_slopes = {list(slopes)!r} must be two numbers "
                             f"(at the first and at the last sample)")
        for i, v in enumerate(slopes):
            _finite(f"end_slopes[{i}]", v)
        if self.condition != "clamped" and any(v != 0.0 for v in slopes):
            raise SceneError(f"end_slopes = {list(slopes)!r} apply to end_condition = "
                             f"'clamped', not {self.condition!r}")
        object.__setattr__(self, "slopes", slopes)

    def spline(self, x, y, *, left: str, right: str) -> PiecewisePolynomial:
        """The spline through (x, y) with these ends and the given tails
        (see :func:`~flexbed.dynamics.piecewise.spline_with_tails`)."""
        return spline_with_tails(x, y, left=left, right=right, end=self.condition,
                                 slopes=self.slopes)


@dataclass(frozen=True, slots=True)
class Curve:
    """Curve data: samples (time [s], value), a cubic spline through them.

    Zero before the first sample, the last value held after the last one.
    At least 4 samples, times strictly increasing, all finite. ``ends``:
    the spline's end conditions (default not-a-knot); with "clamped" the
    slopes are [unit of the value per s].
    """

    time: np.ndarray
    value: np.ndarray
    ends: SplineEnds = SplineEnds()

    def __post_init__(self):
        t = _curve_array("time", self.time)
        v = _curve_array("value", self.value)
        if t.size != v.size:
            raise SceneError(f"time has {t.size} samples but value has {v.size}")
        _check_increasing("time", t)
        if t[0] < 0.0:
            raise SceneError(f"time[0] = {float(t[0])!r} must be >= 0")
        object.__setattr__(self, "time", t)
        object.__setattr__(self, "value", v)
        if not isinstance(self.ends, SplineEnds):
            raise SceneError(f"ends = {self.ends!r} is not a SplineEnds")

    @property
    def start(self) -> float:
        return float(self.time[0])

    @property
    def end(self) -> float:
        return float(self.time[-1])

    def compile(self) -> TimeFunction:
        f = self.ends.spline(self.time, self.value, left="zero", right="hold")
        shortest = float(np.min(np.diff(self.time)))
        return TimeFunction.from_piecewise(f, [self.time[0], self.time[-1]],
                                           max_step=CURVE_SAMPLES_PER_STEP * shortest)

    def sample_times(self, dt: float) -> np.ndarray:
        return _grid(self.start, self.end, dt)


def _curve_array(name: str, data) -> np.ndarray:
    try:
        a = np.array(data, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise SceneError(f"{name} must be a list of numbers") from None
    if a.size < MIN_CURVE_POINTS:
        raise SceneError(f"{name} has {a.size} points, needs at least {MIN_CURVE_POINTS}")
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        raise SceneError(f"{name}[{bad[0]}] = {float(a[bad[0]])!r} must be finite")
    a.setflags(write=False)
    return a


def _check_increasing(name: str, a: np.ndarray) -> None:
    bad = np.flatnonzero(np.diff(a) <= 0)
    if bad.size:
        i = int(bad[0]) + 1
        raise SceneError(f"{name} must be strictly increasing: {name}[{i}] = {float(a[i])!r} "
                         f"after {name}[{i - 1}] = {float(a[i - 1])!r}")


def sampled(shape, dt: float) -> Curve:
    """Shape sampled every dt [s] over its support, as curve data."""
    t = shape.sample_times(dt)
    f = shape.compile()
    return Curve(t, np.array([f.value(float(x)) for x in t]))


#: the shapes a drive or a load may have (each one row of the compiled
#: right-hand side's input tables: a windowed sinusoid or a piecewise
#: polynomial); sums of them: :mod:`flexbed.dynamics.pulses`
SHAPES = (Sinusoid, Triangle, Trapezoid, Sawtooth, Square, InitialPeakSawtooth, Curve)


def summed(functions) -> TimeFunction:
    """The sum of compiled shapes as one :class:`TimeFunction` (values and
    integrals added in the given order, breakpoints merged, the support
    their hull, the shortest ``max_step``)."""
    fs = tuple(functions)
    if len(fs) == 1:
        return fs[0]

    def add(name):
        parts = [getattr(f, name) for f in fs]

        def total(t, seg_end=None):
            acc = 0.0
            for g in parts:
                acc += g(t, seg_end)
            return acc
        return total

    def add_arrays(name):
        parts = [getattr(f, name) for f in fs]

        def total(t):
            acc = np.zeros(np.shape(t))
            for g in parts:
                acc = acc + g(t)
            return acc
        return total

    bps = sorted({b for f in fs for b in f.breakpoints})
    return TimeFunction(add("value"), add("first"), add("second"), bps, add_arrays("values"),
                        add_arrays("firsts"), add_arrays("seconds"),
                        support=(min(f.support[0] for f in fs), max(f.support[1] for f in fs)),
                        max_step=min(f.max_step for f in fs))


def jumps(f: TimeFunction) -> list[tuple[float, float]]:
    """Where a compiled shape's value jumps: [(time [s], right − left limit)]
    at its breakpoints, exact zeros left out."""
    out = []
    for b in f.breakpoints:
        d = f.value(b) - f.value(b, b)
        if d != 0.0:
            out.append((b, d))
    return out

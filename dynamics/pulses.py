"""Shock pulses as specifications state them: a form, a peak and a duration.

A :class:`ShockPulse` is a sum of the elementary shapes of
:mod:`flexbed.dynamics.time_functions` (``terms()``), each of which the
compiled right-hand side evaluates exactly with its integrals and whose
corners the integrators step onto:

=========================  =======================================================
form                       a(τ), τ = t − t₀ on [0, D]
=========================  =======================================================
``half-sine``              P sin(πτ/D)                     (a windowed sinusoid)
``haversine``              P sin²(πτ/D) = P/2 − P/2 cos(2πτ/D)  (square + sinusoid)
``terminal-peak-sawtooth`` P τ/D, then a drop to 0          (sawtooth)
``initial-peak-sawtooth``  a jump to P, then P (1 − τ/D)    (piecewise linear)
``trapezoid``              rise, dwell at P, fall; D = rise + dwell + fall
``square``                 P                                (jumps at both ends)
=========================  =======================================================

Compensation (a shaker's test synthesis, the pre- and post-pulses that
MIL-STD-810 Method 516 draws beside its half-sine and sawtooth pulses): a
main pulse alone leaves the base moving at its velocity change
ΔV = ∫a dt. A pre-pulse of duration d₁ before it and a post-pulse of
duration d₂ after it, both of the opposite sign and of amplitude
``ratio``·|P|, half-sines (``"half-sine"``) or rectangles
(``"rectangular"``), bring the base back to rest where it started. With A
the main pulse's area, c its centroid from its start, κ the compensating
shape's area per unit of amplitude and duration (2/π, 1) and
S = A/(ratio·P·κ) = d₁ + d₂, the velocity (∫a = 0) and the displacement
after the end (−∫t·a dt = 0) vanish when

    d₂ = S (c + S/2) / (S + D),   d₁ = S − d₂.

``start`` is where the whole sequence begins (the pre-pulse's start; the
main pulse's start without compensation). Velocity and displacement are
exact integrals, so the compensated base ends at rest to round-off.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from .errors import SceneError
from .time_functions import (InitialPeakSawtooth, Sawtooth, Sinusoid, Square, TimeFunction,
                             Trapezoid, summed)

__all__ = ["ShockPulse", "FORMS", "COMPENSATIONS", "STANDARD_GRAVITY", "compensation_durations",
           "compensated"]

#: standard gravity g_n [m/s²] (CGPM 1901, ISO 80000-3): the g of "30 g"
STANDARD_GRAVITY = 9.80665

FORMS = ("half-sine", "haversine", "terminal-peak-sawtooth", "initial-peak-sawtooth",
         "trapezoid", "square")
COMPENSATIONS = ("none", "half-sine", "rectangular")
#: a compensating pulse's area per unit amplitude and duration
_AREA_FACTOR = {"half-sine": 2.0 / math.pi, "rectangular": 1.0}


def _number(name, value, *, positive=False, non_negative=False) -> float:
    v = float(value)
    if not math.isfinite(v):
        raise SceneError(f"{name} = {v!r} must be finite")
    if positive and not v > 0.0:
        raise SceneError(f"{name} = {v!r} must be > 0")
    if non_negative and v < 0.0:
        raise SceneError(f"{name} = {v!r} must be >= 0")
    return v


def _main_terms(form: str, peak: float, duration: float, start: float, rise: float,
                fall: float) -> tuple:
    """The elementary shapes of one uncompensated pulse starting at ``start``."""
    if form == "half-sine":
        return (Sinusoid(peak, 0.5 / duration, 0.0, start, duration),)
    if form == "haversine":
        return (Square(0.5 * peak, duration, start),
                Sinusoid(0.5 * peak, 1.0 / duration, -0.5 * math.pi, start, duration))
    if form == "terminal-peak-sawtooth":
        return (Sawtooth(peak, duration, start),)
    if form == "initial-peak-sawtooth":
        return (InitialPeakSawtooth(peak, duration, start),)
    if form == "trapezoid":
        return (Trapezoid(peak, rise, duration - rise - fall, fall, start),)
    return (Square(peak, duration, start),)


def compensation_durations(main: TimeFunction, start: float, end: float, amplitude: float,
                           kind: str) -> tuple[float, float]:
    """(d₁, d₂) [s]: the pre- and post-pulse durations that bring the base
    back to rest (see the module docstring).

    Parameters
    ----------
    main : TimeFunction
        The main pulse, compiled (its exact first and second integrals give
        its area and first moment).
    start, end : float
        The main pulse's start and end [s].
    amplitude : float
        The compensating pulses' signed amplitude [m/s²], of the sign
        opposite to the main pulse's area.
    kind : {"half-sine", "rectangular"}
    """
    D = end - start
    area = main.first(end)                                   # ΔV of the main pulse
    # first moment about the main pulse's start: ∫τ a dτ = D·A − x(end)
    moment = D * area - (main.second(end) - main.second(start))
    S = -area / (amplitude * _AREA_FACTOR[kind])
    if not (S > 0.0 and math.isfinite(S)):
        raise SceneError("compensation: the pulse has no velocity change to compensate")
    c = moment / area
    d2 = S * (c + 0.5 * S) / (S + D)
    return S - d2, d2


def compensated(main_terms: tuple, main_start: float, main_end: float, kind: str,
                ratio: float, peak: float) -> tuple:
    """``main_terms`` preceded and followed by compensating pulses of
    ``kind`` and amplitude −ratio·peak, the sequence starting at
    ``main_start`` (the main pulse moves later by the pre-pulse)."""
    amplitude = -ratio * peak
    d1, d2 = compensation_durations(summed(t.compile() for t in main_terms), main_start,
                                    main_end, amplitude, kind)
    shifted = tuple(replace(t, start=t.start + d1) for t in main_terms)
    pre_at, post_at = main_start, main_end + d1
    if kind == "half-sine":
        pre = Sinusoid(amplitude, 0.5 / d1, 0.0, pre_at, d1)
        post = Sinusoid(amplitude, 0.5 / d2, 0.0, post_at, d2)
    else:
        pre = Square(amplitude, d1, pre_at)
        post = Square(amplitude, d2, post_at)
    return (pre,) + shifted + (post,)


@dataclass(frozen=True, slots=True)
class ShockPulse:
    """A shock pulse by form, peak and duration, optionally compensated.

    Attributes
    ----------
    form : str
        One of :data:`FORMS`.
    peak : float
        Peak of the main pulse [m/s²] (a load: [N]), not 0.
    duration : float
        The main pulse's duration D [s], > 0.
    start : float
        When the sequence begins [s], ≥ 0.
    rise, fall : float
        ``trapezoid`` only: ramp times [s], > 0, rise + fall ≤ duration.
    compensation : str
        One of :data:`COMPENSATIONS`.
    ratio : float
        The compensating pulses' amplitude as a fraction of |peak|,
        0 < ratio ≤ 1 (with compensation only).
    """

    form: str
    peak: float
    duration: float
    start: float = 0.0
    rise: float = 0.0
    fall: float = 0.0
    compensation: str = "none"
    ratio: float = 0.0

    def __post_init__(self):
        if self.form not in FORMS:
            raise SceneError(f"shape = {self.form!r} is not a shock pulse "
                             f"({', '.join(map(repr, FORMS))})")
        if _number("peak", self.peak) == 0.0:
            raise SceneError("peak = 0.0: a pulse of zero peak moves nothing; remove it")
        D = _number("duration", self.duration, positive=True)
        _number("start", self.start, non_negative=True)
        if self.form == "trapezoid":
            r = _number("rise", self.rise, positive=True)
            f = _number("fall", self.fall, positive=True)
            if r + f > D * (1.0 + 1e-12):
                raise SceneError(f"rise + fall = {r + f!r} s is longer than duration = {D!r} s")
        elif self.rise or self.fall:
            raise SceneError(f"rise and fall apply to form 'trapezoid', not {self.form!r}")
        if self.compensation not in COMPENSATIONS:
            raise SceneError(f"compensation = {self.compensation!r} must be one of "
                             f"{', '.join(map(repr, COMPENSATIONS))}")
        ratio = _number("compensation_ratio", self.ratio)
        if self.compensation == "none":
            if ratio != 0.0:
                raise SceneError(f"compensation_ratio = {ratio!r} needs a compensation")
        elif not 0.0 < ratio <= 1.0:
            raise SceneError(f"compensation_ratio = {ratio!r} must be in (0, 1] (the "
                             f"compensating pulses' amplitude over the peak)")

    def main_terms(self) -> tuple:
        """The main pulse's elementary shapes, uncompensated, from ``start``."""
        return _main_terms(self.form, float(self.peak), float(self.duration), float(self.start),
                           float(self.rise), float(self.fall))

    def terms(self) -> tuple:
        """The elementary shapes whose sum is the pulse (pre-pulse, main
        pulse, post-pulse)."""
        main = self.main_terms()
        if self.compensation == "none":
            return main
        s = float(self.start)
        return compensated(main, s, s + float(self.duration), self.compensation,
                           float(self.ratio), float(self.peak))

    @property
    def end(self) -> float:
        """When the last term ends [s]."""
        return max(t.end for t in self.terms())

    def compile(self) -> TimeFunction:
        """The sum of the terms, compiled (value and exact integrals)."""
        return summed(t.compile() for t in self.terms())

"""The frequency-domain numbers a study keeps per point (analyses ``modal``
and ``frf``: :func:`flexbed.modal`, :func:`flexbed.frf` of the point's
scene), checked against the scene before anything runs.

Kinds:

- ``natural_frequency`` (modal): mode ``mode`` (1-based, default 1 — the
  first mounted-system mode, by increasing natural frequency) of the
  mounted system about its static equilibrium, base held;
  ``quantity = "frequency"`` (default) its natural frequency ωₙ/2π [Hz],
  ``"damped_frequency"`` [Hz] or ``"damping_ratio"`` ζ [1].
- ``effective_mass_fraction`` (modal): the share of the moving mass that
  undamped mode ``mode`` (default 1) carries for a base translation along
  ``axis`` = x | y | z (required) [1]; ``cumulative = true``: modes 1 to
  ``mode`` together.
- ``transmissibility`` (frf): |T| [1] at ``frequency`` [Hz] — the
  amplitude of a point's acceleration along ``direction`` (x | y | z,
  default the input's axis) per unit base acceleration along ``input``
  (``"base x" | "base y" | "base z"``, default ``"base z"``); the point as
  for ``peak_displacement`` (``point = NAME`` or ``body`` + ``position``),
  absolute (inertial) unless ``relative_to`` names a body (then in that
  body's frame, relative to it).
- ``peak_transmissibility`` (frf): the largest |T| over ``band = [f_min,
  f_max]`` [Hz] on ``flexbed frf``'s adaptive grid (resonances refined to
  0.1 % of their half-power bandwidth), or with ``quantity = "frequency"``
  the frequency [Hz] where it is; same point, input, direction keys.

A mode index beyond the mounted system's coordinates (six per moving body
and the bed's elastic modes) is refused before anything runs; a mode the
point's scene lacks at run time (its motions overdamped) fails that point.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from flexbed.analyses.frf import BAND_LIMITS
from flexbed.errors import InputError, NumericalError
from flexbed.files.scene import SceneFile
from flexbed.files.table_reader import is_finite_number, short_repr
from flexbed.study.metric_keys import OneColumn, _options, resolve_point
from flexbed.study.spec import MetricTable

__all__ = ["NaturalFrequency", "EffectiveMassFraction", "Transmissibility",
           "PeakTransmissibility", "FREQUENCY_KINDS", "coordinate_count"]

_AXES = "xyz"
_MODAL_QUANTITIES = {"frequency": "Hz", "damped_frequency": "Hz", "damping_ratio": "1"}


def coordinate_count(scene: SceneFile) -> int | None:
    """Coordinates of the mounted system (base held): six per moving body,
    plus the flexible bed's elastic modes (None when set by ``fmax``)."""
    n = 6 * (len(scene.scene.bodies) - 1)
    if scene.bed.flexible:
        if scene.bed.modes is None:
            return None
        n += int(scene.bed.modes)
    return n


def _mode(scene: SceneFile, opts: dict, where: str) -> int:
    k = opts.get("mode", 1)
    if isinstance(k, bool) or not isinstance(k, int) or k < 1:
        raise InputError(f"{where}: mode = {k!r} must be an integer >= 1 (1: the lowest)")
    n = coordinate_count(scene)
    if n is not None and k > n:
        raise InputError(f"{where}: mode = {k!r}: the mounted system has {n} coordinates, "
                         f"so at most {n} modes")
    return k


def _number(value, where: str, key: str) -> float:
    if (isinstance(value, bool) or not isinstance(value, (int, float))
            or not is_finite_number(value) or value <= 0):
        raise InputError(f"{where}: {key} = {short_repr(value)} must be a number > 0 [Hz]")
    lo, hi = BAND_LIMITS
    if not lo <= value <= hi:
        raise InputError(f"{where}: {key} = {short_repr(value)} Hz: a response is computed within "
                         f"{lo:g} – {hi:g} Hz")
    return float(value)


@dataclass(frozen=True)
class NaturalFrequency(OneColumn):
    """A mounted-system mode's natural frequency, damped frequency or
    damping ratio."""

    kind: str
    column: str
    mode: int
    quantity: str
    analysis = "modal"

    @classmethod
    def build(cls, table: MetricTable, scene: SceneFile, where: str) -> "NaturalFrequency":
        opts = _options(table, ("mode", "quantity"), where)
        k = _mode(scene, opts, where)
        q = opts.get("quantity", "frequency")
        if q not in _MODAL_QUANTITIES:
            raise InputError(f"{where}: quantity = {q!r} must be one of "
                             f"{', '.join(_MODAL_QUANTITIES)}")
        default = f"{table.kind}.mode{k}" + ("" if q == "frequency" else f".{q}")
        return cls(table.kind, opts.get("name") or default, k, q)

    unit = property(lambda self: _MODAL_QUANTITIES[self.quantity])

    def values(self, outcomes: dict) -> tuple:
        m = outcomes["modal"]
        if self.mode > m.frequency.size:
            raise NumericalError(f"modal: mode {self.mode}: the mounted system has "
                                 f"{m.frequency.size} modes (and {m.overdamped_rates.size} "
                                 f"real roots: overdamped motions)")
        return (float(getattr(m, self.quantity)[self.mode - 1]),)


@dataclass(frozen=True)
class EffectiveMassFraction(OneColumn):
    """The share of the moving mass an undamped mode carries along an axis."""

    kind: str
    column: str
    mode: int
    axis: int
    cumulative: bool
    analysis = "modal"

    @classmethod
    def build(cls, table: MetricTable, scene: SceneFile, where: str) -> "EffectiveMassFraction":
        opts = _options(table, ("mode", "axis", "cumulative"), where)
        k = _mode(scene, opts, where)
        axis = opts.get("axis")
        if axis not in tuple(_AXES):
            raise InputError(f"{where}: axis = {axis!r} must be x, y or z (the base "
                             f"translation)")
        cum = opts.get("cumulative", False)
        if not isinstance(cum, bool):
            raise InputError(f"{where}: cumulative = {cum!r} must be true or false")
        default = f"{table.kind}.{axis}." + (f"modes1-{k}" if cum else f"mode{k}")
        return cls(table.kind, opts.get("name") or default, k, _AXES.index(axis), cum)

    unit = "1"

    def values(self, outcomes: dict) -> tuple:
        m = outcomes["modal"]
        if self.mode > m.effective_mass.shape[0]:
            raise NumericalError(f"modal: mode {self.mode}: the mounted system has "
                                 f"{m.effective_mass.shape[0]} undamped modes")
        if self.cumulative:
            return (float(m.cumulative_mass[self.mode - 1, self.axis]),)
        return (float(m.effective_mass[self.mode - 1, self.axis] / m.moving_mass),)


def _response_options(table: MetricTable, scene: SceneFile, where: str, extra: tuple) -> tuple:
    opts = _options(table, ("point", "body", "position", "relative_to", "input",
                            "direction") + extra, where)
    body, pos, rel, label = resolve_point(scene, opts, where, point_relative=False)
    inp = opts.get("input", "base z")
    words = inp.split() if isinstance(inp, str) else []
    if len(words) != 2 or words[0] != "base" or words[1] not in _AXES:
        raise InputError(f"{where}: input = {inp!r} must be \"base x\", \"base y\" or "
                         f"\"base z\" (a unit base acceleration)")
    direction = opts.get("direction", words[1])
    if direction not in tuple(_AXES):
        raise InputError(f"{where}: direction = {direction!r} must be x, y or z")
    point = (label, body, list(pos)) + ((rel,) if rel else ())
    output = f"{label}@{rel} a{direction}" if rel else f"{label} a{direction}"
    stem = (f"{table.kind}.{label}" + (f"@{rel}" if rel else "") + f".{direction}"
            + ("" if words[1] == direction else f".base_{words[1]}"))
    return opts, f"base {words[1]}", point, output, stem


@dataclass(frozen=True)
class Transmissibility(OneColumn):
    """|T| of a point at one frequency."""

    kind: str
    column: str
    input: str
    point: tuple
    output: str
    frequency: float
    analysis = "frf"

    @classmethod
    def build(cls, table: MetricTable, scene: SceneFile, where: str) -> "Transmissibility":
        opts, inp, point, output, stem = _response_options(table, scene, where, ("frequency",))
        if "frequency" not in opts:
            raise InputError(f"{where}: give frequency = F [Hz]")
        f = _number(opts["frequency"], where, "frequency")
        return cls(table.kind, opts.get("name") or f"{stem}.{f:g}Hz", inp, point, output, f)

    unit = "1"

    def values(self, outcomes: dict) -> tuple:
        t = outcomes["frf"].response(self.input, self.point, frequencies=[self.frequency])
        return (float(t.magnitude[0, t.column(self.output)]),)


@dataclass(frozen=True)
class PeakTransmissibility(OneColumn):
    """The largest |T| of a point over a band, or its frequency."""

    kind: str
    column: str
    input: str
    point: tuple
    output: str
    band: tuple
    quantity: str
    analysis = "frf"

    @classmethod
    def build(cls, table: MetricTable, scene: SceneFile, where: str) -> "PeakTransmissibility":
        opts, inp, point, output, stem = _response_options(table, scene, where,
                                                           ("band", "quantity"))
        band = opts.get("band")
        if not isinstance(band, list) or len(band) != 2:
            raise InputError(f"{where}: band = {band!r} must be [f_min, f_max] [Hz]")
        lo, hi = (_number(b, where, "band") for b in band)
        if not lo < hi:
            raise InputError(f"{where}: band = {band!r} must have f_min < f_max")
        q = opts.get("quantity", "magnitude")
        if q not in ("magnitude", "frequency"):
            raise InputError(f"{where}: quantity = {q!r} must be magnitude or frequency")
        default = f"{stem}.{lo:g}-{hi:g}Hz" + ("" if q == "magnitude" else ".frequency")
        return cls(table.kind, opts.get("name") or default, inp, point, output, (lo, hi), q)

    unit = property(lambda self: "1" if self.quantity == "magnitude" else "Hz")

    def values(self, outcomes: dict) -> tuple:
        t = outcomes["frf"].response(self.input, self.point, band=self.band)
        mag = t.magnitude[:, t.column(self.output)]
        k = int(np.argmax(mag))
        return (float(mag[k] if self.quantity == "magnitude" else t.frequency[k]),)


#: the kinds this module adds to :data:`flexbed.study.metrics.KINDS`
FREQUENCY_KINDS = {"natural_frequency": NaturalFrequency,
                   "effective_mass_fraction": EffectiveMassFraction,
                   "transmissibility": Transmissibility,
                   "peak_transmissibility": PeakTransmissibility}

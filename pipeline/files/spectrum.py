"""Design spectrum files: a TOML file of shock design spectra per axis, read
and checked into :class:`~flexbed.dynamics.design_spectrum.DesignSpectrum`.

::

    name = "deck, 5 % damping"      # optional
    damping = 0.05                  # the damping ratio the spectra are for [1]
    units = "g"                     # of every acceleration: "g" or "m/s^2" (also "m/s2")

    [z]                             # tripartite breakpoints
    displacement = 0.05             # relative displacement level [m]
    velocity = 2.0                  # pseudo-velocity level [m/s]
    acceleration = 100.0            # acceleration level [units]
    band = [5.0, 2000.0]            # [Hz]

    [y]                             # or a table, log-log interpolated
    frequency = [5.0, 20.0, 100.0, 2000.0]       # [Hz], strictly increasing
    acceleration = [5.0, 40.0, 60.0, 60.0]       # [units], > 0

Axes ``x``, ``y``, ``z``; at least one. A response-spectrum analysis asked
for a damping ratio other than ``damping`` is refused (a spectrum holds for
the damping it was given for). Every error is one line naming the file, the
entry and the value (:class:`~flexbed.errors.InputError`, exit 2).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from flexbed.dynamics.design_spectrum import DesignSpectrum, tripartite
from flexbed.dynamics.pulses import STANDARD_GRAVITY
from flexbed.errors import InputError
from flexbed.files.destination import check_source
from flexbed.files.table_reader import TableReader

__all__ = ["SpectrumFile", "read_spectrum", "parse_spectrum", "AXES", "SPECTRUM_UNITS"]

AXES = ("x", "y", "z")
#: the file's ``units`` and the factor to m/s²
SPECTRUM_UNITS = {"g": STANDARD_GRAVITY, "m/s^2": 1.0, "m/s2": 1.0}
_TOP = ("name", "damping", "units") + AXES
_TABLE = ("frequency", "acceleration")
_TRIPARTITE = ("displacement", "velocity", "acceleration", "band")


@dataclass(frozen=True)
class SpectrumFile:
    """A design spectrum file.

    source : Path; name : str; damping : ζ [1]; units : "g" or "m/s^2";
    axes : {axis index 0|1|2: DesignSpectrum} (accelerations in m/s²);
    text : the file's text.
    """

    source: Path
    name: str
    damping: float
    units: str
    axes: dict
    text: str

    @property
    def scale(self) -> float:
        """From m/s² to the file's units: divide by this."""
        return SPECTRUM_UNITS[self.units]


def read_spectrum(path: str | Path) -> SpectrumFile:
    """Read and check a design spectrum file (InputError on any fault)."""
    p = check_source(path, "spectrum file")
    try:
        text = p.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        reason = getattr(exc, "strerror", None) or str(exc)
        raise InputError(f"{p}: cannot read the spectrum file ({reason})") from None
    return parse_spectrum(text, p)


def parse_spectrum(text: str, source: Path) -> SpectrumFile:
    """Check the TOML text of a design spectrum file (see the module docstring)."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{source.name}: not valid TOML ({exc})") from None
    r = TableReader(source.name, source.parent)
    r.keys("", data, _TOP, ("damping", "units"))
    damping = r.number("", "damping", data["damping"], non_negative=True)
    if not damping < 1.0:
        r.fail("", f"damping = {damping!r} must be in [0, 1) (a damping ratio, e.g. 0.05)")
    units = r.string("", "units", data["units"], tuple(SPECTRUM_UNITS))
    scale = SPECTRUM_UNITS[units]
    axes = {}
    for k, axis in enumerate(AXES):
        if axis in data:
            axes[k] = _axis(r, axis, data[axis], scale, damping, units)
    if not axes:
        r.fail("", "no spectrum: give a table [x], [y] or [z]")
    name = r.string("", "name", data.get("name", source.stem)) if "name" in data else source.stem
    return SpectrumFile(source, name, damping, "m/s^2" if units == "m/s2" else units, axes, text)


def _axis(r: TableReader, axis: str, t, scale: float, damping: float,
          units: str) -> DesignSpectrum:
    where = f"[{axis}]"
    if not isinstance(t, dict):
        r.fail(where, f"must be a table, got {t!r}")
    if "frequency" in t:
        r.keys(where, t, _TABLE, _TABLE)
        f = np.array(r.numbers(where, "frequency", t["frequency"]), dtype=float)
        a = np.array(r.numbers(where, "acceleration", t["acceleration"]), dtype=float)
        if f.size != a.size or f.size < 2:
            r.fail(where, f"frequency has {f.size} values and acceleration {a.size}: give "
                          f"the same number, at least 2")
        _check_positive(r, where, "frequency", f, "Hz")
        bad = np.flatnonzero(np.diff(f) <= 0.0)
        if bad.size:
            i = int(bad[0])
            r.fail(where, f"frequency[{i + 1}] = {float(f[i + 1])!r} Hz is not above "
                          f"frequency[{i}] = {float(f[i])!r} Hz: frequencies must increase")
        _check_positive(r, where, "acceleration", a, units)
        return DesignSpectrum(f, a * scale, damping)
    r.keys(where, t, _TRIPARTITE, _TRIPARTITE)
    levels = {}
    for key, unit in (("displacement", "m"), ("velocity", "m/s"), ("acceleration", units)):
        v = r.number(where, key, t[key])
        if not v > 0.0:
            r.fail(where, f"{key} = {v!r} {unit} must be > 0")
        levels[key] = v
    band = r.numbers(where, "band", t["band"], 2)
    if not 0.0 < band[0] < band[1]:
        r.fail(where, f"band = {band!r} Hz must satisfy 0 < f_min < f_max")
    d, v, a = levels["displacement"], levels["velocity"], levels["acceleration"] * scale
    f_dv, f_va = v / (2.0 * math.pi * d), a / (2.0 * math.pi * v)
    if not f_dv < f_va:
        r.fail(where, f"the velocity level {v!r} m/s is never reached: its corner with the "
                      f"displacement level, {f_dv:.4g} Hz, is not below its corner with the "
                      f"acceleration level, {f_va:.4g} Hz (lower the velocity or raise the "
                      f"others)")
    return tripartite(d, v, a, band[0], band[1], damping)


def _check_positive(r: TableReader, where: str, key: str, a: np.ndarray, unit: str) -> None:
    bad = np.flatnonzero(~(a > 0.0))
    if bad.size:
        i = int(bad[0])
        r.fail(where, f"{key}[{i}] = {float(a[i])!r} {unit} must be > 0 (a spectrum level)")


def check_damping(spectrum: SpectrumFile, damping) -> float:
    """The damping ratio of an analysis: ``damping`` (None: the spectrum's)
    must be the spectrum's (to 1e-9), else InputError."""
    if damping is None:
        return spectrum.damping
    if not abs(float(damping) - spectrum.damping) <= 1e-9 * max(1.0, spectrum.damping):
        raise InputError(f"{spectrum.source.name}: damping = {damping!r} asked, but the "
                         f"spectrum is given for damping = {spectrum.damping!r}: give a "
                         f"spectrum for that damping")
    return spectrum.damping

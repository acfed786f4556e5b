"""The scene file's drives and loads and its curve data: ``[[base.drive]]``
and ``[[base.force]]`` entries as time shapes (sinusoid, triangle,
trapezoid, sawtooth, the shock pulses of :mod:`flexbed.dynamics.pulses`
with or without compensation, curve data inline or from a CSV file; the
functions themselves: :mod:`flexbed.dynamics.time_functions`) and the
mount laws' curve tables, with the splines' end conditions.

One table may give several elementary shapes (a haversine is a square plus
a sinusoid; a compensated pulse has a pre- and a post-pulse):
:meth:`ShapeReader.terms` returns them all, and the scene holds one drive
(load) per term. A drive's ``units = "g"`` multiplies its accelerations by
standard gravity (:data:`~flexbed.dynamics.pulses.STANDARD_GRAVITY`); the
scene file's text, recorded in every output made from it, keeps the key.

:class:`ShapeReader` adds these readers to :class:`TableReader`; the
scene file's reader (:mod:`flexbed.files.scene`) builds on it.
"""

from __future__ import annotations

import io
import math
import warnings

import numpy as np

from flexbed.dynamics.errors import SceneError
from flexbed.dynamics.pulses import COMPENSATIONS, STANDARD_GRAVITY, ShockPulse, compensated
from flexbed.dynamics.time_functions import (END_CONDITIONS, Curve, Sawtooth, Sinusoid, SplineEnds,
                                     Trapezoid, Triangle, sampled)

from flexbed.files.table_reader import TableReader

__all__ = ["ShapeReader", "SHAPE_KEYS", "ALL_SHAPE_KEYS", "END_KEYS", "UNITS", "PULSES",
           "COMPENSATION_KEYS"]

END_KEYS = ("end_condition", "end_slopes")
COMPENSATION_KEYS = ("compensation", "compensation_ratio")
#: a drive's ``units`` and the factor to m/s²
UNITS = {"m/s2": 1.0, "g": STANDARD_GRAVITY}
#: the shock pulses given by peak and duration (:class:`~flexbed.dynamics.pulses.ShockPulse`)
PULSES = ("half-sine", "haversine", "terminal-peak-sawtooth", "initial-peak-sawtooth", "square")
_PULSE_KEYS = ("peak", "duration", "start") + COMPENSATION_KEYS
SHAPE_KEYS = {
    "sinusoid": ("amplitude", "frequency", "phase_deg", "start", "duration"),
    "triangle": ("peak", "start", "rise", "fall") + COMPENSATION_KEYS,
    "trapezoid": ("peak", "start", "rise", "flat", "fall") + COMPENSATION_KEYS,
    "sawtooth": ("peak", "start", "rise") + COMPENSATION_KEYS,
    **{kind: _PULSE_KEYS for kind in PULSES},
    "curve": ("time", "value", "file") + END_KEYS,
}
ALL_SHAPE_KEYS = ("direction", "shape", "sample", "units") + tuple(
    sorted({k for v in SHAPE_KEYS.values() for k in v}))


class ShapeReader(TableReader):
    """Readers of time shapes and curve tables (see the module docstring)."""

    def terms(self, where: str, t: dict, role: str = "drive") -> tuple:
        """The elementary shapes of a drive's or a force's table, whose sum
        is the input it describes (keys other than ``direction`` checked
        here); ``role``: "drive" (accelerations, ``units`` allowed) or
        "force" [N]."""
        kind = self.string(where, "shape", t["shape"], tuple(SHAPE_KEYS))
        allowed = ("direction", "shape", "sample") + (("units",) if role == "drive" else ()) \
            + SHAPE_KEYS[kind]
        for key in t:
            if key == "units" and role != "drive":
                self.fail(where, f"units = {t[key]!r}: a force is in N; 'units' applies to "
                                 f"[[base.drive]] only")
            if key not in allowed:
                self.fail(where, f"key '{key}' does not apply to shape = {kind!r} "
                                 f"(known: {', '.join(allowed)})")
        scale = UNITS[self.string(where, "units", t.get("units", "m/s2"), tuple(UNITS))]
        try:
            if kind in PULSES:
                return self._pulse(where, kind, t, scale)
            shape = self._shape(where, kind, t, scale)
            if "sample" in t:
                if kind == "curve":
                    self.fail(where, "sample applies to sinusoid, triangle and trapezoid "
                                     "(curve data are already samples)")
                if "compensation" in t:
                    self.fail(where, "sample does not apply to a compensated pulse")
                shape = sampled(shape, self.number(where, "sample", t["sample"], positive=True))
            if t.get("compensation", "none") != "none" or "compensation_ratio" in t:
                how, ratio = self._compensation(where, t)
                return compensated((shape,), shape.start, shape.end, how, ratio, shape.peak)
            return (shape,)
        except SceneError as exc:
            self.fail(where, str(exc))

    def shape(self, where: str, t: dict, role: str = "drive"):
        """The one elementary shape of a table (an error for one that needs
        several: a haversine, a compensated pulse)."""
        terms = self.terms(where, t, role)
        if len(terms) != 1:
            self.fail(where, f"shape = {t['shape']!r} is a sum of {len(terms)} shapes here")
        return terms[0]

    def _compensation(self, where: str, t: dict) -> tuple[str, float]:
        how = self.string(where, "compensation", t.get("compensation", "none"), COMPENSATIONS)
        if how == "none":
            self.fail(where, f"compensation_ratio = {t['compensation_ratio']!r} needs "
                             f"compensation = 'half-sine' or 'rectangular'")
        if "compensation_ratio" not in t:
            self.fail(where, f"compensation = {how!r} needs compensation_ratio (the pre- and "
                             f"post-pulses' amplitude over the peak, in (0, 1])")
        ratio = self.number(where, "compensation_ratio", t["compensation_ratio"])
        if not 0.0 < ratio <= 1.0:
            self.fail(where, f"compensation_ratio = {ratio!r} must be in (0, 1]")
        return how, ratio

    def _pulse(self, where: str, kind: str, t: dict, scale: float) -> tuple:
        """A shock pulse's terms (:class:`~flexbed.dynamics.pulses.ShockPulse`)."""
        for key in ("peak", "duration"):
            if key not in t:
                self.fail(where, f"'{key}' is required for shape = {kind!r}")
        if "sample" in t:
            self.fail(where, f"sample does not apply to shape = {kind!r} (used exactly)")
        peak = self.number(where, "peak", t["peak"])
        if peak == 0.0:
            self.fail(where, "peak = 0.0: a pulse of zero peak moves nothing; remove the entry")
        duration = self.number(where, "duration", t["duration"], positive=True)
        start = self.number(where, "start", t.get("start", 0.0), non_negative=True)
        how, ratio = "none", 0.0
        if t.get("compensation", "none") != "none" or "compensation_ratio" in t:
            how, ratio = self._compensation(where, t)
        return ShockPulse(kind, peak * scale, duration, start, compensation=how,
                          ratio=ratio).terms()

    def _shape(self, where: str, kind: str, t: dict, scale: float):
        """One elementary shape of the sinusoid, triangle, trapezoid,
        sawtooth or curve tables, values times ``scale``."""
        if kind == "sinusoid":
            for key in ("amplitude", "frequency"):
                if key not in t:
                    self.fail(where, f"'{key}' is required for shape = 'sinusoid'")
            dur = t.get("duration", math.inf)
            return Sinusoid(
                self.number(where, "amplitude", t["amplitude"]) * scale,
                self.number(where, "frequency", t["frequency"], positive=True),
                math.radians(self.number(where, "phase_deg", t.get("phase_deg", 0.0))),
                self.number(where, "start", t.get("start", 0.0), non_negative=True),
                dur if dur == math.inf else self.number(where, "duration", dur, positive=True))
        if kind in ("triangle", "trapezoid", "sawtooth"):
            need = ("peak", "rise") + {"triangle": ("fall",), "trapezoid": ("flat", "fall"),
                                       "sawtooth": ()}[kind]
            for key in need:
                if key not in t:
                    self.fail(where, f"'{key}' is required for shape = {kind!r}")
            peak = self.number(where, "peak", t["peak"]) * scale
            start = self.number(where, "start", t.get("start", 0.0), non_negative=True)
            rise = self.number(where, "rise", t["rise"], positive=True)
            if kind == "sawtooth":
                return Sawtooth(peak, rise, start)
            if kind == "triangle":
                return Triangle(peak, rise, self.number(where, "fall", t["fall"], positive=True),
                                start)
            flat = self.number(where, "flat", t["flat"], non_negative=True)
            fall = self.number(where, "fall", t["fall"], positive=True)
            return Trapezoid(peak, rise, flat, fall, start)
        if "file" in t:
            if "time" in t or "value" in t:
                self.fail(where, "give either 'file' or 'time'/'value', not both")
            times, values = self.csv_file(where, self.string(where, "file", t["file"]))
        else:
            for key in ("time", "value"):
                if key not in t:
                    self.fail(where, f"'{key}' is required for shape = 'curve' "
                                     f"(or give 'file')")
            times = self.numbers(where, "time", t["time"])
            values = self.numbers(where, "value", t["value"])
        ends = self.ends(where, t)
        if scale != 1.0:
            ends = SplineEnds(ends.condition, tuple(v * scale for v in ends.slopes))
        return Curve(np.array(times), np.array(values) * scale, ends)

    def ends(self, where: str, t: dict) -> SplineEnds:
        """``end_condition`` and ``end_slopes`` of a curve's table."""
        cond = self.string(where, "end_condition", t.get("end_condition", "not-a-knot"),
                           END_CONDITIONS)
        if "end_slopes" in t and cond != "clamped":
            self.fail(where, f"end_slopes = {t['end_slopes']!r} applies to end_condition = "
                             f"'clamped' only (end_condition is {cond!r})")
        slopes = self.numbers(where, "end_slopes", t.get("end_slopes", [0.0, 0.0]), 2)
        try:
            return SplineEnds(cond, tuple(slopes))
        except SceneError as exc:
            self.fail(where, str(exc))

    def csv_file(self, where: str, name: str):
        """(times, values) of a two-column CSV file beside the scene file."""
        p = (self.folder / name)
        try:
            if p.exists() and not p.is_file():
                self.fail(where, f"file = {name!r}: not a regular file (a folder, a FIFO or "
                                 f"a device)")
            text = p.read_text(encoding="utf-8")
        except OSError as exc:
            self.fail(where, f"file = {name!r}: cannot read it ({exc.strerror or exc})")
        except UnicodeDecodeError as exc:
            line = p.read_bytes()[:exc.start].count(b"\n") + 1
            self.fail(where, f"file = {name!r}: line {line}: not UTF-8 text (byte "
                             f"0x{exc.object[exc.start]:02x})")
        self.csv[name] = text
        fast = _two_columns(text)
        if fast is not None:
            return fast
        times, values = [], []
        for lineno, line in enumerate(text.splitlines(), 1):
            s = line.strip()
            if not s or s.startswith("#"):
                continue
            cells = [c.strip() for c in s.split(",")]
            try:
                nums = [float(c) for c in cells]
            except ValueError:
                if not times:      # a header line
                    continue
                self.fail(where, f"file = {name!r}: line {lineno}: {s!r} is not two numbers")
            if len(nums) != 2:
                self.fail(where, f"file = {name!r}: line {lineno}: {len(nums)} columns, "
                                 f"expected 2 (time, value)")
            times.append(nums[0])
            values.append(nums[1])
        if not times:
            self.fail(where, f"file = {name!r}: no line of two numbers (time, value)")
        return times, values

    def curve_tables(self, where, key, value, xkey) -> list:
        """A mount law's 3 curve tables (one per direction):
        [(x, force, SplineEnds)]."""
        if (not isinstance(value, list) or len(value) != 3
                or not all(isinstance(v, dict) for v in value)):
            self.fail(where, f"{key} must be 3 tables {{{xkey} = [...], force = [...]}} "
                             f"(one per direction)")
        out = []
        for d, tab in enumerate(value):
            w = f"{where}: {key}[{d}]"
            self.keys(w, tab, (xkey, "force") + END_KEYS, (xkey, "force"))
            x = self.numbers(w, xkey, tab[xkey])
            f = self.numbers(w, "force", tab["force"])
            out.append((np.array(x), np.array(f), self.ends(w, tab)))
        return out


def _two_columns(text: str):
    """(times, values) of a CSV text parsed in compiled code, or None when
    the text needs the line-by-line reader: a header other than the lines
    before the first data line, a comment or an odd line among the data, a
    line break other than ``\\n`` or ``\\r\\n``, a number NumPy's parser
    does not take (``1_000``) — the line-by-line reader then parses it or
    names the line at fault. Both parsers round correctly, so the values are
    the same either way.

    Returns
    -------
    (times, values) : two (n,) float arrays, or None
    """
    start = 0
    while start < len(text):                  # the lines before the first data line
        end = text.find("\n", start)
        end = len(text) if end < 0 else end
        line = text[start:end].strip()
        if line and not line.startswith("#"):
            try:
                [float(c) for c in line.split(",")]
                break
            except ValueError:
                pass
        start = end + 1
    data = text[start:]
    if not data.strip() or "#" in data or data.count("\r") != data.count("\r\n"):
        return None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            table = np.loadtxt(io.StringIO(data), delimiter=",", comments=None, ndmin=2,
                               dtype=float, encoding=None)
    except (ValueError, UserWarning):
        return None
    if table.ndim != 2 or table.shape[1] != 2:
        return None
    return table[:, 0].copy(), table[:, 1].copy()

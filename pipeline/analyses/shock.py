"""Shock response spectra of a finished run: the absolute acceleration of a
point of interest (:mod:`flexbed.analyses.points`) along X, Y, Z, through
:func:`flexbed.dynamics.shock_spectrum.shock_spectrum`; for a driven base,
the base's acceleration (the input) beside it.

Jumps of the base's acceleration (a sawtooth's drop, a square pulse's
ends) are read from the run's scene (its drives, or its forces over the
base's mass) and handed to the filter, which adds their exact step
responses (:func:`flexbed.dynamics.shock_spectrum.shock_spectrum`): the
record holds the value after a jump at the sample on it, and joined by a
straight line to the sample before it would lose peak·Δt/2 of impulse.
They apply to the input and to points on the base; every other body's
acceleration is continuous (its forces are functions of positions and
velocities).

Record length: an oscillator's largest residual response comes within
half its period after the input ends, so a record shorter than the input's
end (its last breakpoint) plus one period of the lowest oscillator, 1/fmin,
is warned about (``Spectra.warnings``).

File layout (HDF5, schema ``flexbed.srs`` 1.1): ``frequency`` (n,) [Hz];
for each point NAME (and ``input`` for a driven base)
``NAME/positive``, ``NAME/negative``, ``NAME/maximax`` (n, 3) [m/s²], the
same in g as ``NAME/positive_g``, ``NAME/negative_g``, ``NAME/maximax_g``
(g = 9.80665 m/s²), and ``NAME/pseudo_velocity`` (n, 3) [m/s], columns X,
Y, Z, the group's attributes ``body`` and ``position`` (body frame [m]);
root attributes ``q``, ``per_octave``, ``sample_interval`` [s],
``results``, ``standard_gravity`` [m/s²], ``drive_units`` (the units the
scene's drives were given in, one per drive table, comma-separated),
``jumps`` (the jumps of the base's acceleration taken exactly, as text),
``warnings``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from flexbed.dynamics.pulses import STANDARD_GRAVITY
from flexbed.dynamics.scene import DIRECTIONS
from flexbed.dynamics.shock_spectrum import ShockSpectrum, frequency_grid, shock_spectrum
from flexbed.dynamics.time_functions import jumps as shape_jumps
from flexbed.errors import InputError
from flexbed.analyses.points import Point, Run

__all__ = ["PointSpectrum", "Spectra", "spectra", "spectrum_csv", "spectra_datasets",
           "base_jumps", "record_warning", "INPUT", "SCHEMA", "VERSION", "G"]

SCHEMA, VERSION = "flexbed.srs", "1.1"
G = STANDARD_GRAVITY                 # [m/s²]: spectra in g are divided by it
INPUT = "input"                      # the name of the base's own spectrum
#: highest frequency allowed, as a fraction of the sampling rate (a sampled
#: peak then misses the continuous one by at most 1 − cos(π/4) = 29 %)
FMAX_SHARE = 0.25
#: default highest frequency, as a fraction of the sampling rate (≤ 5 %)
FMAX_DEFAULT_SHARE = 0.1


@dataclass(frozen=True)
class PointSpectrum:
    """The SRS of one point along X, Y, Z (n frequencies).

    name, body : str; position : (3,) body frame [m];
    positive, negative, maximax : (n, 3) [m/s²] (``in_g(key)``: in g);
    pseudo_velocity : (n, 3) [m/s].
    """

    name: str
    body: str
    position: np.ndarray
    positive: np.ndarray
    negative: np.ndarray
    maximax: np.ndarray
    pseudo_velocity: np.ndarray

    @classmethod
    def of(cls, name: str, body: str, position, axes: list[ShockSpectrum]) -> "PointSpectrum":
        cols = {k: np.column_stack([getattr(s, k) for s in axes])
                for k in ("positive", "negative", "maximax", "pseudo_velocity")}
        return cls(name, body, np.asarray(position, dtype=float), **cols)

    def in_g(self, key: str) -> np.ndarray:
        """``positive``, ``negative`` or ``maximax`` in g (n, 3)."""
        return getattr(self, key) / G


@dataclass(frozen=True)
class Spectra:
    """Spectra of the points asked for, and of a driven base's input.

    frequency : (n,) [Hz]; q : quality factor; per_octave : int;
    sample_interval : [s]; points : tuple of PointSpectrum;
    input : PointSpectrum or None (the base's acceleration, driven base only);
    jumps : tuple of (time [s], (3,) jump [m/s²]) of the base's acceleration
    taken exactly; drive_units : tuple of str, per drive table;
    warnings : tuple of str (a record too short for the lowest frequency).
    """

    frequency: np.ndarray
    q: float
    per_octave: int
    sample_interval: float
    points: tuple
    input: PointSpectrum | None
    jumps: tuple = ()
    drive_units: tuple = ()
    warnings: tuple = ()


def _uniform(t: np.ndarray, where: Path) -> tuple[float, int]:
    """The sample interval [s] and how many samples are uniformly spaced
    (a shorter last interval, at t_end, is dropped)."""
    if t.size < 3:
        raise InputError(f"{where}: {t.size} samples are too few for a shock spectrum")
    dt = float(t[1] - t[0])
    n = t.size
    if abs((t[-1] - t[-2]) - dt) > 1e-6 * dt:
        n -= 1
    if np.max(np.abs(np.diff(t[:n]) - dt)) > 1e-6 * dt:
        raise InputError(f"{where}: the samples are not uniformly spaced; a shock spectrum "
                         f"needs a constant output_dt")
    return dt, n


#: the finest grid asked for: 1/1000 octave is 0.07 % apart, far below any
#: oscillator's bandwidth at the Q in use
MAX_PER_OCTAVE = 1000
#: the most oscillators of one spectrum (each a pass over the record)
MAX_FREQUENCIES = 20_000
#: the smallest quality factor: Q = 1/(2ζ) > 0.5, oscillators below critical
#: damping (the ramp-invariant filter is that of a ringing oscillator)
Q_MIN = 0.5


def spectra(run: Run, points: list[Point], *, q: float = 10.0, fmin: float = 1.0,
            fmax: float | None = None, per_octave: int = 12) -> Spectra:
    """SRS of each point's absolute acceleration (and of a driven base's).

    Parameters
    ----------
    run : Run
        A results file opened for post-processing.
    points : list of Point
    q : quality factor Q = 1/(2ζ) [1], > 0
    fmin, fmax : band [Hz]; ``fmax`` defaults to a tenth of the sampling rate
        and may not exceed a quarter of it
    per_octave : frequencies per octave (logarithmic grid)
    """
    dt, n = _uniform(run.t, run.path)
    fs = 1.0 / dt
    if fmax is None:
        fmax = FMAX_DEFAULT_SHARE * fs
    if not (q > Q_MIN and math.isfinite(q)):
        raise InputError(f"--q {q!r}: the quality factor must be a number above {Q_MIN:g} "
                         f"(damping ratio below 1: the oscillators ring)")
    if not (fmin > 0 and math.isfinite(fmin)):
        raise InputError(f"--fmin {fmin!r}: must be a positive frequency [Hz]")
    from flexbed.analyses.frf import BAND_LIMITS      # one band rule for every spectrum
    if fmin < BAND_LIMITS[0]:
        raise InputError(f"--fmin {fmin!r}: below {BAND_LIMITS[0]:g} Hz, the lowest frequency "
                         f"a response is computed at")
    if not (math.isfinite(fmax) and fmax >= fmin):
        raise InputError(f"--fmax {fmax!r}: must be a frequency at or above fmin = {fmin:g} Hz")
    if fmax > FMAX_SHARE * fs * (1 + 1e-12):
        raise InputError(f"--fmax {fmax:g} Hz: above a quarter of {run.path}'s sampling rate "
                         f"({fs:g} Hz); at most {FMAX_SHARE * fs:g} Hz")
    if not 1 <= per_octave <= MAX_PER_OCTAVE:
        raise InputError(f"--per-octave {per_octave!r}: from 1 to {MAX_PER_OCTAVE}")
    count = per_octave * (math.log2(fmax) - math.log2(fmin)) + 1
    if count > MAX_FREQUENCIES:
        raise InputError(f"--fmin {fmin:g} Hz to --fmax {fmax:g} Hz at {per_octave} per octave "
                         f"is {count:.3g} frequencies; the limit is {MAX_FREQUENCIES:,}")
    f = frequency_grid(fmin, fmax, per_octave)
    found, ends, units = base_jumps(run)
    t = run.t[:n]
    steps = []                                  # (sample, offset, (3,) jump) in the record
    for tj, J in found:
        k = int(np.searchsorted(t, tj, side="left"))    # the first sample at or after it
        if k < n:
            steps.append((k, float(t[k] - tj), J))

    def axes(acc, on_base):
        return [shock_spectrum(acc[:n, i], dt, f, q,
                               [(k, off, J[i]) for k, off, J in steps] if on_base else ())
                for i in range(3)]

    out = [PointSpectrum.of(p.name, p.body, p.position,
                            axes(run.absolute(p).acceleration, p.body == run.names[0]))
           for p in points]
    base = None
    if run.base_motion == "driven":
        base = PointSpectrum.of(INPUT, run.names[0], np.zeros(3), axes(run.rdd[:, 0], True))
    warn = record_warning(run, float(f[0]), ends, n)
    return Spectra(f, float(q), int(per_octave), dt, tuple(out), base,
                   tuple((tj, J) for tj, J in found), units, (warn,) if warn else ())


def base_jumps(run: Run) -> tuple[list, float, tuple]:
    """The jumps of the base's acceleration, from the run's scene.

    Returns
    -------
    jumps : list of (time [s], (3,) jump after minus before [m/s²]), by time
        (a driven base's drives; a free base's forces over its mass)
    end : float
        The inputs' last breakpoint [s] (0 with none; inf for an input
        that never ends: a sinusoid without a duration)
    units : tuple of str
        The units each drive table was given in.
    """
    from flexbed.files.drives import ShapeReader

    base = run.scene_data.get("base", {})
    kind = {"driven": "drive", "free": "force"}.get(run.base_motion)
    tables = base.get(kind, []) if kind and isinstance(base, dict) else []
    units = tuple(str(t.get("units", "m/s2")) for t in tables) if kind == "drive" else ()
    scale = 1.0
    if kind == "force":
        bodies = run.scene_data.get("body", [])
        scale = 1.0 / float(bodies[0]["mass"]) if bodies else 0.0
    source = Path(run.scene_source) if run.scene_source else run.path
    reader = ShapeReader(str(run.path), source.parent)
    found: dict[float, np.ndarray] = {}
    size: dict[float, float] = {}              # Σ|jump| of the terms, for round-off
    end = 0.0
    for i, table in enumerate(tables):
        try:
            terms = reader.terms(f"base.{kind} {i + 1}", table, kind)
            axis = DIRECTIONS.index(table["direction"])
        except (InputError, KeyError, ValueError, TypeError):
            continue                # e.g. a curve's CSV file no longer beside the scene
        for term in terms:
            fn = term.compile()
            end = max(end, fn.support[1])
            scale_of_term = _magnitude(term)
            for tj, d in shape_jumps(fn):
                if abs(d) <= 1e-12 * scale_of_term:        # sin(π) ≠ 0 at a window's end
                    continue
                found.setdefault(tj, np.zeros(3))[axis] += d * scale
                size[tj] = size.get(tj, 0.0) + abs(d * scale)
    # terms whose jumps cancel (a haversine's square and sinusoid) leave round-off
    kept = [(tj, J) for tj, J in sorted(found.items())
            if np.abs(J).max() > 1e-12 * size[tj]]
    return kept, end, units


def _magnitude(term) -> float:
    """The largest value a shape's parameters give (amplitude, peak or
    curve values), for telling round-off from a jump."""
    for key in ("amplitude", "peak"):
        if hasattr(term, key):
            return abs(float(getattr(term, key)))
    return float(np.max(np.abs(term.value)))


def record_warning(run: Run, fmin: float, input_end: float, n: int) -> str:
    """A warning when the record ends before the input's end plus one
    period of the lowest oscillator (its residual peak comes within half a
    period after the input ends), else ""."""
    t0, t1 = float(run.t[0]), float(run.t[n - 1])
    end = input_end if math.isfinite(input_end) else t0
    need = max(end, t0) + 1.0 / fmin
    if t1 >= need * (1 - 1e-12):
        return ""
    room = t1 - max(end, t0)
    hint = (f"; or --fmin {1.0 / room:.3g} Hz" if room > 0 else "")
    return (f"{run.path}: the record ends at {t1:g} s, before the input's end "
            f"({end:g} s) plus one period of the lowest oscillator ({fmin:g} Hz: "
            f"{1.0 / fmin:g} s), {need:g} s; the residual response of the lowest frequencies "
            f"may be cut short: a longer t_end{hint}")


def _all(s: Spectra) -> list[PointSpectrum]:
    return list(s.points) + ([s.input] if s.input is not None else [])


def spectrum_csv(s: Spectra, p: PointSpectrum) -> str:
    """One point's spectra as CSV: frequency, then positive, negative,
    maximax [m/s²] and pseudo-velocity [m/s] along X, Y, Z, then positive,
    negative and maximax in g."""
    cols = ["frequency_Hz"] + [f"{k}_{c}_{u}" for k, u in
                               (("positive", "m/s2"), ("negative", "m/s2"),
                                ("maximax", "m/s2"), ("pseudo_velocity", "m/s"),
                                ("positive", "g"), ("negative", "g"), ("maximax", "g"))
                               for c in "xyz"]
    data = np.column_stack([s.frequency, p.positive, p.negative, p.maximax, p.pseudo_velocity,
                            p.in_g("positive"), p.in_g("negative"), p.in_g("maximax")])
    return "\n".join([",".join(cols)] + [",".join(f"{v:.10g}" for v in row)
                                         for row in data]) + "\n"


def spectra_datasets(s: Spectra, results: str) -> tuple[dict, dict]:
    """Datasets and attributes of the spectra file (module docstring)."""
    from flexbed.files.store import Dataset

    ds = {"frequency": Dataset(s.frequency, "Hz", "natural frequencies of the oscillators")}
    attrs = {"": {"q": s.q, "per_octave": s.per_octave, "sample_interval": s.sample_interval,
                  "results": results, "standard_gravity": G,
                  "drive_units": ", ".join(s.drive_units),
                  "jumps": "; ".join(f"t = {tj:.9g} s: " + ", ".join(f"{v:.6g}" for v in J)
                                     + " m/s^2" for tj, J in s.jumps),
                  "warnings": "\n".join(s.warnings)}}
    for p in _all(s):
        g = p.name
        what = "the base's acceleration (input)" if p is s.input else f"point {p.name}"
        for key, unit, text in (("positive", "m/s^2", "largest positive absolute acceleration"),
                                ("negative", "m/s^2", "largest negative absolute acceleration "
                                                      "(magnitude)"),
                                ("maximax", "m/s^2", "maximax absolute acceleration"),
                                ("pseudo_velocity", "m/s", "pseudo-velocity ω·max|z|")):
            ds[f"{g}/{key}"] = Dataset(getattr(p, key), unit,
                                       f"{text}, columns X, Y, Z, of {what}")
            if unit == "m/s^2":
                ds[f"{g}/{key}_g"] = Dataset(p.in_g(key), "g",
                                             f"{text} in g (9.80665 m/s^2), columns X, Y, Z, "
                                             f"of {what}")
        attrs[g] = {"body": p.body, "position": p.position}
    return ds, attrs


def summary(s: Spectra) -> str:
    """The peak maximax per point and axis, with its frequency, as a table."""
    lines = [f"shock response spectra, Q = {s.q:g}, {s.frequency[0]:g}-{s.frequency[-1]:g} Hz, "
             f"{s.per_octave} per octave ({s.frequency.size} frequencies):",
             "| point | body | axis | peak maximax [m/s²] | [g] | at [Hz] "
             "| peak positive [g] | peak negative [g] | peak pseudo-velocity [m/s] |",
             "|---|---|---|---|---|---|---|---|---|"]
    for p in _all(s):
        for i, c in enumerate("xyz"):
            k = int(np.argmax(p.maximax[:, i]))
            lines.append(f"| {p.name} | {p.body} | {c} | {p.maximax[k, i]:.5g} | "
                         f"{p.maximax[k, i] / G:.4g} | {s.frequency[k]:.4g} | "
                         f"{p.positive[:, i].max() / G:.4g} | {p.negative[:, i].max() / G:.4g} | "
                         f"{p.pseudo_velocity[:, i].max():.5g} |")
    return "\n".join(lines)

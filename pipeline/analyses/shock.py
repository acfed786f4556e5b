"""Shock response spectra of a finished run: the absolute acceleration of a
point of interest (:mod:`flexbed.analyses.points`) along X, Y, Z, through
:func:`flexbed.dynamics.shock_spectrum.shock_spectrum`; for a driven base,
the base's acceleration (the input) beside it.

File layout (HDF5, schema ``flexbed.srs`` 1.0): ``frequency`` (n,) [Hz];
for each point NAME (and ``input`` for a driven base)
``NAME/positive``, ``NAME/negative``, ``NAME/maximax`` (n, 3) [m/s²] and
``NAME/pseudo_velocity`` (n, 3) [m/s], columns X, Y, Z, the group's
attributes ``body`` and ``position`` (body frame [m]); root attributes
``q``, ``per_octave``, ``sample_interval`` [s], ``results``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from flexbed.dynamics.shock_spectrum import ShockSpectrum, frequency_grid, shock_spectrum
from flexbed.errors import InputError
from flexbed.analyses.points import Point, Run

__all__ = ["PointSpectrum", "Spectra", "spectra", "spectrum_csv", "spectra_datasets",
           "INPUT", "SCHEMA", "VERSION"]

SCHEMA, VERSION = "flexbed.srs", "1.0"
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
    positive, negative, maximax : (n, 3) [m/s²]; pseudo_velocity : (n, 3) [m/s].
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


@dataclass(frozen=True)
class Spectra:
    """Spectra of the points asked for, and of a driven base's input.

    frequency : (n,) [Hz]; q : quality factor; per_octave : int;
    sample_interval : [s]; points : tuple of PointSpectrum;
    input : PointSpectrum or None (the base's acceleration, driven base only).
    """

    frequency: np.ndarray
    q: float
    per_octave: int
    sample_interval: float
    points: tuple
    input: PointSpectrum | None


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
    if not (q > 0 and math.isfinite(q)):
        raise InputError(f"--q {q!r}: the quality factor must be a positive number")
    if not (fmin > 0 and math.isfinite(fmin)):
        raise InputError(f"--fmin {fmin!r}: must be a positive frequency [Hz]")
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

    def axes(acc):
        return [shock_spectrum(acc[:n, i], dt, f, q) for i in range(3)]

    out = [PointSpectrum.of(p.name, p.body, p.position, axes(run.absolute(p).acceleration))
           for p in points]
    base = None
    if run.base_motion == "driven":
        base = PointSpectrum.of(INPUT, run.names[0], np.zeros(3), axes(run.rdd[:, 0]))
    return Spectra(f, float(q), int(per_octave), dt, tuple(out), base)


def _all(s: Spectra) -> list[PointSpectrum]:
    return list(s.points) + ([s.input] if s.input is not None else [])


def spectrum_csv(s: Spectra, p: PointSpectrum) -> str:
    """One point's spectra as CSV: frequency, then positive, negative,
    maximax [m/s²] and pseudo-velocity [m/s] along X, Y, Z."""
    cols = ["frequency_Hz"] + [f"{k}_{c}_{u}" for k, u in
                               (("positive", "m/s2"), ("negative", "m/s2"),
                                ("maximax", "m/s2"), ("pseudo_velocity", "m/s"))
                               for c in "xyz"]
    data = np.column_stack([s.frequency, p.positive, p.negative, p.maximax, p.pseudo_velocity])
    return "\n".join([",".join(cols)] + [",".join(f"{v:.10g}" for v in row)
                                         for row in data]) + "\n"


def spectra_datasets(s: Spectra, results: str) -> tuple[dict, dict]:
    """Datasets and attributes of the spectra file (module docstring)."""
    from flexbed.files.store import Dataset

    ds = {"frequency": Dataset(s.frequency, "Hz", "natural frequencies of the oscillators")}
    attrs = {"": {"q": s.q, "per_octave": s.per_octave, "sample_interval": s.sample_interval,
                  "results": results}}
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
        attrs[g] = {"body": p.body, "position": p.position}
    return ds, attrs


def summary(s: Spectra) -> str:
    """The peak maximax per point and axis, with its frequency, as a table."""
    lines = [f"shock response spectra, Q = {s.q:g}, {s.frequency[0]:g}-{s.frequency[-1]:g} Hz, "
             f"{s.per_octave} per octave ({s.frequency.size} frequencies):",
             "| point | body | axis | peak maximax [m/s²] | at [Hz] | peak pseudo-velocity [m/s] |",
             "|---|---|---|---|---|---|"]
    for p in _all(s):
        for i, c in enumerate("xyz"):
            k = int(np.argmax(p.maximax[:, i]))
            lines.append(f"| {p.name} | {p.body} | {c} | {p.maximax[k, i]:.5g} | "
                         f"{s.frequency[k]:.4g} | {p.pseudo_velocity[:, i].max():.5g} |")
    return "\n".join(lines)

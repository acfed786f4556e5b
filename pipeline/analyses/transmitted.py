"""The force the mounts put into the base (issue 25, part 2): per mount and
summed, as time histories and spectra in N and dB re 1 N, narrow-band and
in third-octave bands, and the insertion loss between two designs.

Transmitted force: for each mount with one end on the base (body 1), the
inertial force on that end (``mounts/force_i`` or ``mounts/force_j`` of
the results file), and their sum. With the base held, the momentum of the
other bodies gives the same sum: ``Σ F = Σ m_b (g − r̈_b) + Σ loads``
(rigid bodies), which the tests check.

Spectra (of the dynamic part: the mean over the analysed window, the
static weight carried, is removed), from samples on the run's uniform
output grid at and after ``start``:

- narrow-band: one-sided RMS per line [N] of a Hann-windowed FFT of the
  whole window (n samples, resolution Δf = 1/(n Δt)), amplitude-corrected
  (a steady tone at a line reads its RMS, A/√2);
- mean square per line [N²] (energy-corrected: the lines' sum is the
  window's mean square, Parseval), summed into third-octave bands of IEC
  61260-1 (base 10: exact mid-band f_m = 1000 · 10^(x/10) Hz, edges
  f_m · 10^(±1/20), labelled by the nominal centres); a band narrower than
  4 Δf is left out (too few lines);
- levels L = 20 log10(F_rms / 1 N) dB re 1 N.

Insertion loss of design B against design A (the reference: rigid bed, or
machinery mounted directly): IL = L_A − L_B per band [dB], positive when B
transmits less.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from flexbed.errors import InputError

__all__ = ["TransmittedForce", "Spectrum", "Bands", "transmitted_force", "spectrum",
           "third_octaves", "insertion_loss", "db", "NOMINAL_THIRD_OCTAVES"]

#: IEC 61260-1 nominal mid-band frequencies of one decade (× 10^k)
NOMINAL_THIRD_OCTAVES = (1.0, 1.25, 1.6, 2.0, 2.5, 3.15, 4.0, 5.0, 6.3, 8.0)
_MIN_LINES = 4


@dataclass(frozen=True)
class TransmittedForce:
    """The mounts' forces into the base.

    time : (k,) [s]; mounts : names of the mounts with an end on the base;
    per_mount : (k, Mb, 3) [N] inertial force each puts into the base;
    total : (k, 3) [N] their sum.
    """

    time: np.ndarray
    mounts: tuple
    per_mount: np.ndarray
    total: np.ndarray


@dataclass(frozen=True)
class Spectrum:
    """Narrow-band spectrum of a force, one column per component.

    frequency : (n,) [Hz]; rms : (n, c) [N] amplitude-corrected RMS per
    line; mean_square : (n, c) [N²] energy-corrected per line; window :
    name; samples : n samples analysed from ``start`` [s]; resolution Δf
    [Hz].
    """

    frequency: np.ndarray
    rms: np.ndarray
    mean_square: np.ndarray
    window: str
    samples: int
    start: float
    resolution: float


@dataclass(frozen=True)
class Bands:
    """Third-octave bands: nominal and exact centres, lower and upper edges
    (nb,) [Hz], RMS per band (nb, c) [N]."""

    nominal: np.ndarray
    centre: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    rms: np.ndarray


def db(x) -> np.ndarray:
    """20 log10(x / 1 N) [dB re 1 N] (−inf for 0)."""
    with np.errstate(divide="ignore"):
        return 20.0 * np.log10(np.asarray(x, dtype=float))


def transmitted_force(contents) -> TransmittedForce:
    """The mounts' forces into the base from a results file's contents
    (:func:`flexbed.files.results.read_results`)."""
    names = [str(n) for n in np.atleast_1d(contents.get("mounts/names"))]
    body_i = [str(n) for n in np.atleast_1d(contents.get("mounts/body_i"))]
    body_j = [str(n) for n in np.atleast_1d(contents.get("mounts/body_j"))]
    base = str(np.atleast_1d(contents.get("bodies/names"))[0])
    Fi = np.asarray(contents.get("mounts/force_i"), dtype=float)
    Fj = np.asarray(contents.get("mounts/force_j"), dtype=float)
    t = np.asarray(contents.get("time"), dtype=float)
    cols, used = [], []
    for m, name in enumerate(names):
        if body_i[m] == base:
            cols.append(Fi[:, m])
            used.append(name)
        elif body_j[m] == base:
            cols.append(Fj[:, m])
            used.append(name)
    if not cols:
        raise InputError(f"no mount has an end on the base {base!r}: nothing is transmitted "
                         f"to it")
    per = np.stack(cols, axis=1)
    return TransmittedForce(t, tuple(used), per, per.sum(axis=1))


def spectrum(t: np.ndarray, x: np.ndarray, start: float = 0.0) -> Spectrum:
    """Hann-windowed narrow-band spectrum of the samples at t ≥ start.

    Parameters
    ----------
    t : (k,) array [s]
        Uniform sample times (a run's output grid).
    x : (k,) or (k, c) array [N]
    start : float
        First time analysed [s] (skip the transient).
    """
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    if x.ndim == 1:
        x = x[:, None]
    keep = t >= start - 1e-12
    t, x = t[keep], x[keep]
    n = t.size
    if n < 16:
        raise InputError(f"--from {start:g} s leaves {n} samples; a spectrum needs at least 16")
    dt = np.diff(t)
    h = float(np.median(dt))
    if np.max(np.abs(dt - h)) > 1e-6 * h:
        raise InputError("the samples are not uniformly spaced in time (a spectrum needs the "
                         "run's uniform output grid)")
    w = np.hanning(n + 1)[:-1]               # periodic Hann
    X = np.fft.rfft((x - x.mean(axis=0)) * w[:, None], axis=0)
    f = np.fft.rfftfreq(n, h)
    one_sided = np.full(f.size, 2.0)
    one_sided[0] = 1.0
    if n % 2 == 0:
        one_sided[-1] = 1.0
    amp = np.abs(X) * (one_sided / w.sum())[:, None]             # tone peak amplitude
    rms = amp / np.where(one_sided == 2.0, math.sqrt(2.0), 1.0)[:, None]
    ms = np.abs(X) ** 2 * (one_sided / (n * np.sum(w ** 2)))[:, None]
    return Spectrum(f, rms, ms, "hann", n, float(t[0]), 1.0 / (n * h))


def third_octaves(sp: Spectrum, fmin: float = 1.0, fmax: float | None = None) -> Bands:
    """The spectrum's mean square summed in IEC 61260-1 third-octave bands
    between fmin and fmax [Hz] (default: the spectrum's top line); bands
    narrower than 4 lines are left out."""
    fmax = float(sp.frequency[-1]) if fmax is None else fmax
    x = np.arange(math.floor(10 * math.log10(fmin / 1000.0)),
                  math.ceil(10 * math.log10(fmax / 1000.0)) + 1)
    centre = 1000.0 * 10.0 ** (x / 10.0)
    lower, upper = centre * 10 ** (-1 / 20), centre * 10 ** (1 / 20)
    ok = (upper - lower >= _MIN_LINES * sp.resolution) & (lower >= fmin * 10 ** (-1 / 20)) \
        & (upper <= fmax * 10 ** (1 / 20))
    rows = []
    for lo, hi in zip(lower[ok], upper[ok]):
        sel = (sp.frequency >= lo) & (sp.frequency < hi)
        rows.append(np.sqrt(sp.mean_square[sel].sum(axis=0)))
    nominal = np.array([_nominal(v) for v in x[ok]])
    rms = np.array(rows).reshape(-1, sp.rms.shape[1])
    return Bands(nominal, centre[ok], lower[ok], upper[ok], rms)


def _nominal(x: int) -> float:
    """The nominal mid-band frequency of band x (f_m = 1000 · 10^(x/10))."""
    decade, k = divmod(int(x) + 30, 10)
    return round(NOMINAL_THIRD_OCTAVES[k] * 10.0 ** decade, 6)


def insertion_loss(reference: Bands, candidate: Bands) -> np.ndarray:
    """IL = L_ref − L_candidate per band and column [dB] (the same bands)."""
    if reference.centre.shape != candidate.centre.shape or not np.allclose(
            reference.centre, candidate.centre):
        raise InputError("insertion loss: the two runs' third-octave bands differ (give both "
                         "runs the same output_dt and analysed length)")
    return db(reference.rms) - db(candidate.rms)

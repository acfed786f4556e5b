"""A base acceleration synthesised to match a design spectrum: a sum of
wavelets iterated until its shock response spectrum is the target's.

Method (after D. O. Smallwood & A. R. Nord, "Matching shock spectra with
sums of decaying sinusoids compensated for velocity effects", Shock and
Vibration Bulletin 43, 1973, and the wavelet form of NASA-HDBK-7005 §5.4):
one wavelet per check frequency f_k,

    w_k(t) = A_k sin(2π f_k (t − τ_k)/N_k) sin(2π f_k (t − τ_k)),   τ_k ≤ t ≤ τ_k + N_k/(2 f_k),

zero elsewhere, N_k odd ≥ 3 (half-cycles of the carrier under a half-sine
window). With N_k odd each wavelet has zero net velocity and zero net
displacement: ∫ w dt = ½[sin((b−a)T)/(b−a) − sin((b+a)T)/(b+a)] with
(b ∓ a)T = π(N_k ∓ 1), both sines 0, and ∫ (T − t) w dt vanishes because
cos π(N_k ∓ 1) = 1 (T = N_k/(2f_k), a = 2πf_k/N_k, b = 2πf_k).
Delays τ_k and signs are drawn from a seeded generator (repeatable); each
iteration scales A_k by target/achieved at f_k (the maximax absolute
acceleration SRS, Smallwood's filter, :mod:`flexbed.dynamics.shock_spectrum`).

The record is then used as curve data, a cubic spline through the samples
(:class:`~flexbed.dynamics.time_functions.Curve`), whose integrals are not
exactly the wavelets'. A closed-form correction makes the spline's own end
velocity and displacement zero: the spline's integrals are linear in the
samples, so c₁ sin(πt/T) + c₂ sin(2πt/T) (T the record's length, far below
the band) taken off the samples with (c₁, c₂) from a 2 × 2 solve zeroes
both to round-off. The correction is applied in every iteration, so the
SRS iterated on is the corrected record's.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.signal import lfilter

from .design_spectrum import DesignSpectrum
from .shock_spectrum import acceleration_coefficients, frequency_grid
from .time_functions import Curve

__all__ = ["Synthesis", "synthesise", "check_frequencies", "end_motion", "maximax"]


@dataclass(frozen=True)
class Synthesis:
    """A synthesised base acceleration and how well it matches.

    time : (k,) [s], from 0, uniform; acceleration : (k,) [m/s²];
    frequency : (p,) check frequencies [Hz]; target : (p,) [m/s²];
    achieved : (p,) maximax SRS of the record [m/s²] at the target's damping;
    error_db : (p,) 20 log10(achieved/target) [dB];
    wavelet_frequency, wavelet_amplitude [m/s²], wavelet_delay [s] : (p,);
    wavelet_half_cycles : (p,) int; iterations : int; converged : bool
    (every |error| ≤ tolerance_db); tolerance_db : float;
    end_velocity [m/s], end_displacement [m] : of the record as curve data;
    damping : ζ [1]; seed : int.
    """

    time: np.ndarray
    acceleration: np.ndarray
    frequency: np.ndarray
    target: np.ndarray
    achieved: np.ndarray
    error_db: np.ndarray
    wavelet_frequency: np.ndarray
    wavelet_amplitude: np.ndarray
    wavelet_delay: np.ndarray
    wavelet_half_cycles: np.ndarray
    iterations: int
    converged: bool
    tolerance_db: float
    end_velocity: float
    end_displacement: float
    damping: float
    seed: int

    @property
    def dt(self) -> float:
        return float(self.time[1] - self.time[0])


def check_frequencies(spectrum: DesignSpectrum, f_lo: float, f_hi: float,
                      per_octave: int) -> np.ndarray:
    """The log grid of ``per_octave`` points an octave on [f_lo, f_hi] [Hz]
    with the spectrum's breakpoints inside it."""
    grid = frequency_grid(f_lo, f_hi, per_octave)
    inside = spectrum.frequency[(spectrum.frequency > f_lo) & (spectrum.frequency < f_hi)]
    f = np.unique(np.concatenate([grid, inside]))
    keep = np.concatenate([[True], np.diff(np.log(f)) > 1e-3 * math.log(2.0)])
    return f[keep]


def maximax(u: np.ndarray, dt: float, frequency: np.ndarray, zeta: float) -> np.ndarray:
    """Maximax absolute acceleration SRS [m/s²] of ``u`` (k,) [m/s²] at
    ``frequency`` (p,) [Hz] (Smallwood's filter, oscillators at rest)."""
    b, a = acceleration_coefficients(2.0 * np.pi * frequency, zeta, dt)
    return np.array([np.abs(lfilter(b[i], a[i], u)).max() for i in range(frequency.size)])


def end_motion(time: np.ndarray, acceleration: np.ndarray) -> tuple[float, float]:
    """(velocity [m/s], displacement [m]) at the last sample of the curve
    data (time, acceleration) read as a drive (the spline's exact integrals)."""
    f = Curve(time, acceleration).compile()
    t = float(time[-1])
    return float(f.first(t)), float(f.second(t))


def _wavelets(t: np.ndarray, f: np.ndarray, n: np.ndarray, delay: np.ndarray) -> list:
    """Each wavelet's unit-amplitude samples as (first index, values)."""
    dt = t[1] - t[0]
    out = []
    for fk, nk, tk in zip(f, n, delay):
        i0 = int(math.ceil(tk / dt - 1e-9))
        i1 = int(math.floor((tk + nk / (2.0 * fk)) / dt + 1e-9))
        s = t[i0:i1 + 1] - tk
        w = 2.0 * math.pi * fk
        out.append((i0, np.sin(w * s / nk) * np.sin(w * s)))
    return out


def _sum(size: int, amp: np.ndarray, waves: list) -> np.ndarray:
    u = np.zeros(size)
    for a_k, (i0, w) in zip(amp, waves):
        u[i0:i0 + w.size] += a_k * w
    return u


def _iterate(t, waves, f, target, zeta, sign, goal_db, max_iterations):
    """The amplitudes' iteration for one draw of delays and signs: the
    best (worst |error| [dB], amplitudes, iteration) reached."""
    dt = t[1] - t[0]
    amp = sign * target / 4.0
    best = (math.inf, amp, 0)
    for it in range(1, max_iterations + 1):
        got = maximax(_sum(t.size, amp, waves), dt, f, zeta)
        worst = float(np.abs(20.0 * np.log10(got / target)).max())
        if worst < best[0]:
            best = (worst, amp, it)
        if worst <= goal_db:
            break
        # each amplitude scaled by target/achieved, the step shrinking as it
        # goes (the wavelets' spectra overlap: a full step oscillates)
        amp = amp * (target / got) ** (1.0 / (1.0 + it / 15.0))
    return best


def synthesise(spectrum: DesignSpectrum, f_lo: float, f_hi: float, *, per_octave: int = 6,
               tolerance_db: float = 1.5, goal_db: float = 1.0, seed: int = 0,
               attempts: int = 8, max_iterations: int = 30, samples_per_cycle: int = 20,
               wavelet_duration: float = 0.1, min_half_cycles: int = 11,
               max_delay: float = 0.1) -> Synthesis:
    """A base acceleration whose SRS matches ``spectrum`` on [f_lo, f_hi].

    Parameters
    ----------
    spectrum : the target (its damping is the SRS's)
    f_lo, f_hi : the band [Hz], 0 < f_lo < f_hi
    per_octave : check frequencies (one wavelet each) per octave
    tolerance_db : the match required at every check frequency [dB]
    goal_db : an attempt stops once every |error| is below this [dB] (a
        margin inside the tolerance for other ways of computing the SRS)
    seed : the generator of delays and signs (the same seed, the same record)
    attempts : draws of delays and signs at most, each iterated
        ``max_iterations`` times; the first to reach ``goal_db`` is kept,
        else the best
    samples_per_cycle : samples per period of f_hi (20: a sampled peak
        within 1.2 % of the continuous one)
    wavelet_duration, min_half_cycles : N_k is the smallest odd number
        ≥ max(min_half_cycles, 2 f_k · wavelet_duration) (narrow-band
        wavelets: their spectra overlap less)
    max_delay : delays τ_k drawn uniformly in [0, max_delay] [s]

    Returns
    -------
    Synthesis (``converged`` False when no attempt reached ``tolerance_db``).
    """
    zeta = spectrum.damping
    f = check_frequencies(spectrum, f_lo, f_hi, per_octave)
    target = spectrum(f)
    n = np.maximum(min_half_cycles,
                   2 * np.ceil((2.0 * f * wavelet_duration - 1.0) / 2.0) + 1).astype(int)
    dt = 1.0 / (samples_per_cycle * f_hi)
    length = max_delay + float(np.max(n / (2.0 * f))) + 1.0 / f_lo     # a period of residual
    t = dt * np.arange(int(math.ceil(length / dt)) + 1)
    T = t[-1]
    g = np.vstack([np.sin(np.pi * t / T), np.sin(2.0 * np.pi * t / T)])
    g[:, -1] = 0.0
    G = np.array([end_motion(t, gi) for gi in g]).T                  # (2, 2): rows v, d
    rng = np.random.default_rng(seed)
    best = None
    for _ in range(attempts):
        delay = rng.uniform(0.0, max_delay, f.size)
        sign = rng.choice([-1.0, 1.0], f.size)
        waves = _wavelets(t, f, n, delay)
        worst, amp, it = _iterate(t, waves, f, target, zeta, sign, goal_db, max_iterations)
        if best is None or worst < best[0]:
            best = (worst, amp, it, delay, waves)
        if worst <= goal_db:
            break
    _, amp, it, delay, waves = best
    u = _sum(t.size, amp, waves)
    u -= np.linalg.solve(G, np.array(end_motion(t, u))) @ g
    got = maximax(u, dt, f, zeta)
    err = 20.0 * np.log10(got / target)
    worst = float(np.abs(err).max())
    v_end, d_end = end_motion(t, u)
    return Synthesis(time=t, acceleration=u, frequency=f, target=target, achieved=got,
                     error_db=err, wavelet_frequency=f, wavelet_amplitude=amp,
                     wavelet_delay=delay, wavelet_half_cycles=n, iterations=it,
                     converged=worst <= tolerance_db, tolerance_db=tolerance_db,
                     end_velocity=v_end, end_displacement=d_end, damping=zeta, seed=seed)

"""Stationary random response of the mounted system to base accelerations
given as power spectral densities.

With ``H_d(f)`` (k, o) the outputs' frequency responses to a unit base
acceleration along axis d (:func:`flexbed.dynamics.frequency.frf.responses`)
and ``S(f)`` (k, 3, 3) the base accelerations' one-sided cross-spectral
density matrix [(m/s²)²/Hz], Hermitian, the outputs' one-sided PSDs are
[1, §6.2]

    S_y(f) = Σ_d Σ_e H_d(f) S_de(f) conj(H_e(f)),

their mean squares ``σ² = ∫ S_y df`` (zero mean: the responses about the
static equilibrium). The grid has, around each mode, points at
``fₙ (1 + ζ tan θ)`` for θ evenly spaced (the substitution that makes a
mode's Lorentzian peak ``1/(1 + s²)`` flat in θ, so its half-power band,
s = ±1 or θ = ±45°, is evenly covered), then, in the tails, points growing
geometrically away from fₙ. The integral is Simpson's rule for uneven
steps, and the error stated its difference from the trapezoidal rule (a
bound: the lower-order rule's error).

Miles' equation [2], generalised to any output dominated by one mode:
``σ² ≈ π ζ fₙ S_y(fₙ)``, exact for a lightly damped single-degree-of-freedom
isolator's absolute acceleration and relative displacement under white
noise (for the acceleration, ``S_y(fₙ) = (1 + 4ζ²)/(4ζ²) W`` gives
``σ² = π fₙ (1 + 4ζ²) W / (4ζ)``, the closed form; with Q = 1/(2ζ) and the
input's W it is the textbook ``√(π/2 fₙ Q W)``).

[1] J. S. Bendat, A. G. Piersol, *Random Data*, 4th ed., Wiley 2010.
[2] J. W. Miles, "On structural fatigue under random loading", J.
    Aeronautical Sciences 21 (1954) 753–762.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .modal import Modes

__all__ = ["loglog_interpolate", "random_grid", "response_psd", "mean_square", "miles",
           "Miles", "HALF_POWER_SHARE"]

#: a mode's core: s = tan θ with θ in steps of 45°/CORE_STEPS (the
#: half-power points s = ±1 among them) up to ±CORE_LIMIT steps (63°: s = ±1.96)
CORE_STEPS = 10
CORE_LIMIT = 14
#: beyond the core, s grows geometrically by this ratio …
TAIL_RATIO = 1.08
#: … until the points are this many times as far apart as the base grid's
TAIL_REACH = 10.0
#: an output is single-mode dominated when the half-power band of one mode
#: holds at least this share of its mean square (an isolated lightly damped
#: mode holds (2/π) atan(1) = 0.5 there)
HALF_POWER_SHARE = 0.4


def loglog_interpolate(f_break: np.ndarray, level: np.ndarray, f: np.ndarray) -> np.ndarray:
    """A PSD given at breakpoints, between them a straight line on log–log
    axes (a power law, as specifications are written), zero outside.

    Parameters
    ----------
    f_break : (b,) array
        Breakpoints [Hz], increasing, > 0.
    level : (b,) array
        Levels at the breakpoints [any unit per Hz], ≥ 0; a zero level
        makes the segments on either side of it zero.
    f : (k,) array
        Frequencies [Hz].

    Returns
    -------
    (k,) array
        The levels at f.
    """
    f = np.asarray(f, dtype=float)
    out = np.zeros(f.shape)
    inside = (f >= f_break[0]) & (f <= f_break[-1])
    j = np.clip(np.searchsorted(f_break, f[inside], side="right") - 1, 0, f_break.size - 2)
    lo, hi = level[j], level[j + 1]
    pos = (lo > 0.0) & (hi > 0.0)
    t = np.log(f[inside] / f_break[j]) / np.log(f_break[j + 1] / f_break[j])
    val = np.zeros(t.shape)
    val[pos] = np.exp(np.log(lo[pos]) + t[pos] * (np.log(hi[pos]) - np.log(lo[pos])))
    out[inside] = val
    on = np.isin(f, f_break)                       # breakpoints exactly as given
    out[on] = level[np.searchsorted(f_break, f[on])]
    return out


def random_grid(modes: Modes, f_min: float, f_max: float, n: int,
                breakpoints: np.ndarray | None = None) -> np.ndarray:
    """Frequencies [Hz] on [f_min, f_max]: n log-spaced, the input's
    breakpoints (its corners), and around each damped mode in the band
    points at ``fₙ (1 + ζ s)``: s = tan θ, θ evenly spaced
    (:data:`CORE_STEPS`, :data:`CORE_LIMIT`: the half-power points s = ±1
    among them, up to s = ±1.96), then s growing by :data:`TAIL_RATIO` until the spacing is
    :data:`TAIL_REACH` times the base grid's (or f would leave (0, 2fₙ)).
    An undamped mode has no finite mean square and adds nothing."""
    n = max(n, 2)
    g = [np.geomspace(f_min, f_max, n)]
    if breakpoints is not None:
        g.append(np.asarray(breakpoints, dtype=float))
    step = np.log(f_max / f_min) / (n - 1)                 # the base grid's relative spacing
    core = np.tan(np.arange(-CORE_LIMIT, CORE_LIMIT + 1) * (np.pi / 4.0 / CORE_STEPS))
    core[CORE_LIMIT] = 0.0
    core[CORE_LIMIT - CORE_STEPS], core[CORE_LIMIT + CORE_STEPS] = -1.0, 1.0
    edge = core[-1]
    for f, z in zip(modes.frequency, modes.damping_ratio):
        if not (np.isfinite(f) and f > 0.0 and 0.0 < z < 1.0 and f_min <= f <= f_max):
            continue
        reach = min(TAIL_REACH * step / z, 0.999 / z)
        k = int(np.ceil(np.log(max(reach, edge) / edge) / np.log(TAIL_RATIO)))
        tail = edge * TAIL_RATIO ** np.arange(1, k + 1)
        s = np.concatenate([-tail[::-1], core, tail])
        g.append(f * (1.0 + z * s))
    g = np.unique(np.concatenate(g))
    return g[(g >= f_min) & (g <= f_max)]


def response_psd(H: np.ndarray, S: np.ndarray) -> np.ndarray:
    """The outputs' one-sided PSDs (k, o) [output unit² per Hz].

    H : (k, d, o) complex — outputs per unit input along each of d axes;
    S : (k, d, d) complex Hermitian — the inputs' cross-spectral density
    [input unit² per Hz]."""
    d = S.shape[1]
    out = np.zeros((H.shape[0], H.shape[2]))
    for i in range(d):
        if np.any(S[:, i, i] != 0.0):
            out += S[:, i, i].real[:, None] * (H[:, i].real ** 2 + H[:, i].imag ** 2)
        for j in range(i + 1, d):
            if np.any(S[:, i, j] != 0.0):                  # S_ij + S_ji: 2 Re(H_i S_ij H_j*)
                out += 2.0 * (S[:, i, j][:, None] * H[:, i] * np.conj(H[:, j])).real
    return out


def mean_square(f: np.ndarray, psd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """σ² (o,) = ∫ psd df over the grid f (k,) [Hz] by Simpson's rule for
    uneven steps (a parabola through each pair of steps; the last step
    alone, when their number is odd, by the trapezoidal rule), and a bound
    on its error (o,): its difference from the trapezoidal rule on the
    same points (the lower-order rule's error, which is larger)."""
    h = np.diff(f)
    trap = 0.5 * (h[:, None] * (psd[1:] + psd[:-1])).sum(axis=0)
    m = h.size // 2
    h0, h1 = h[0:2 * m:2], h[1:2 * m:2]
    y0, y1, y2 = psd[0:2 * m:2], psd[1:2 * m + 1:2], psd[2:2 * m + 1:2]
    w = ((h0 + h1) / 6.0)[:, None]
    simpson = (w * ((2.0 - h1 / h0)[:, None] * y0 + ((h0 + h1) ** 2 / (h0 * h1))[:, None] * y1
                    + (2.0 - h0 / h1)[:, None] * y2)).sum(axis=0)
    if h.size % 2:
        simpson = simpson + 0.5 * h[-1] * (psd[-1] + psd[-2])
    return simpson, np.abs(simpson - trap)


@dataclass(frozen=True)
class Miles:
    """Miles' estimate per output: ``frequency`` (o,) [Hz] and
    ``damping_ratio`` (o,) of the mode holding most of its mean square in
    its half-power band, ``share`` (o,) [1] that share, ``rms`` (o,)
    ``√(π ζ fₙ S_y(fₙ))`` [output unit] where the share is at least
    :data:`HALF_POWER_SHARE` (single-mode dominated), NaN elsewhere."""

    frequency: np.ndarray
    damping_ratio: np.ndarray
    share: np.ndarray
    rms: np.ndarray


def miles(f: np.ndarray, psd: np.ndarray, total: np.ndarray, modes: Modes) -> Miles:
    """:class:`Miles` of outputs with PSDs ``psd`` (k, o) on the grid f (k,)
    [Hz] of :func:`random_grid` and mean squares ``total`` (o,).

    A mode is a candidate for an output when its PSD at fₙ is the highest
    at any natural frequency within its half-power band (a heavily damped
    mode's wide band holding a lightly damped mode's sharp peak does not
    own that peak); of the candidates, the one holding the largest share of
    the mean square in its band is the output's mode."""
    o = psd.shape[1]
    best = np.full(o, -1)
    share = np.zeros(o)
    at = np.zeros(o)
    fn_all, z_all = modes.frequency, modes.damping_ratio
    ok = np.isfinite(fn_all) & (z_all > 0.0) & (z_all < 1.0) & (fn_all > f[0]) & (fn_all < f[-1])
    idx = np.flatnonzero(ok)
    near = np.argmin(np.abs(f[None, :] - fn_all[idx, None]), axis=1)   # fₙ's grid point
    peak = psd[near]                                                    # (modes, o)
    for m, k in enumerate(idx):
        fn, z = fn_all[k], z_all[k]
        lo, hi = fn * (1.0 - z) * (1 - 1e-12), fn * (1.0 + z) * (1 + 1e-12)
        band = (f >= lo) & (f <= hi)
        if band.sum() < 2:
            continue
        inside = (fn_all[idx] >= lo) & (fn_all[idx] <= hi)
        owner = np.all(peak[inside] <= peak[m], axis=0)                 # (o,)
        part = np.trapezoid(psd[band], f[band], axis=0)
        sh = np.divide(part, total, out=np.zeros(o), where=total > 0.0)
        better = owner & (sh > share)
        best[better], share[better] = k, sh[better]
        at[better] = peak[m, better]
    fn = np.where(best >= 0, fn_all[best], np.nan)
    z = np.where(best >= 0, z_all[best], np.nan)
    rms = np.where(share >= HALF_POWER_SHARE, np.sqrt(np.pi * z * fn * at), np.nan)
    return Miles(fn, z, share, rms)

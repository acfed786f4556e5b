"""Shock response spectra by Smallwood's ramp-invariant recursive filter.

The shock response spectrum (SRS) of a base acceleration history ``ÿ(t)``
is the peak response of a family of single-degree-of-freedom oscillators
(natural frequency f, quality factor Q = 1/(2ζ)) mounted on that base:

    z̈ + 2ζω ż + ω² z = −ÿ(t),   ẍ = ÿ + z̈ = −(2ζω ż + ω² z),

z the relative displacement, ẍ the absolute acceleration of the mass,
ω = 2πf. Reported per frequency: the maximax absolute acceleration, its
largest positive and largest negative values, and the pseudo-velocity
ω·max|z|.

The filter (D. O. Smallwood, "An improved recursive formula for calculating
shock response spectra", Shock and Vibration Bulletin 51(2), 1981)
----------------------------------------------------------------------
Between two samples (spacing T) the input is taken as the straight line
through them (ramp invariance). With the state s = (z, ż), ṡ = F s + g ÿ,
g = (0, −1), and σ = (t − t_k)/T, the exact step over one sample is

    s_{k+1} = Φ s_k + Γ₀ ÿ_k + Γ₁ (ÿ_{k+1} − ÿ_k),

Φ = e^{FT}, Γ₀ = ∫₀¹ e^{FT(1−σ)} g T dσ, Γ₁ = ∫₀¹ e^{FT(1−σ)} g T σ dσ — all
three are blocks of the exponential of the augmented matrix
[[FT, gT, 0], [0, 0, 1], [0, 0, 0]] (Van Loan). An output r_k = c s_k then
obeys, since (zI − Φ)⁻¹ = (zI + Φ − tr Φ I)/det(zI − Φ) for 2 × 2 matrices,

    r_k = b₀ ÿ_k + b₁ ÿ_{k−1} + b₂ ÿ_{k−2} − a₁ r_{k−1} − a₂ r_{k−2},
    a₁ = −tr Φ, a₂ = det Φ,
    b₀ = c Γ₁, b₁ = c (Γ₀ − Γ₁) + c (Φ − tr Φ I) Γ₁, b₂ = c (Φ − tr Φ I)(Γ₀ − Γ₁),

exact at the samples for a piecewise-linear input. For the absolute
acceleration (c = (−ω², −2ζω)) these are Smallwood's closed forms, with
E = e^{−ζωT}, K = ω_d T, ω_d = ω√(1 − ζ²):

    b₀ = 1 − E sin K / K,  b₁ = 2E (sin K / K − cos K),  b₂ = E² − E sin K / K,
    a₁ = −2E cos K,  a₂ = E²,

which :func:`acceleration_coefficients` evaluates; the relative
displacement's (c = (1, 0)) come from the matrices
(:func:`ramp_invariant_coefficients`). The filter starts from rest with the
input zero before the first sample.

Jumps: a record of an input that jumps (a terminal-peak sawtooth's drop,
a square pulse's ends) holds, at the sample on or after the jump, the
value after it; a filter that joins the samples by straight lines then
spreads the jump over one interval and loses half a sample of its
impulse (peak·Δt/2). With the jumps known (time and size J), the input is
the straight-line record ũ (each jump taken out of the samples from it on)
plus J·H(t − t_J); the filter takes ũ, and each step adds J times the
oscillator's exact step response from rest,

    x(τ) = 1 − e^{−ζωτ} (cos ω_dτ − ζω/ω_d sin ω_dτ),
    z(τ) = −(1 − e^{−ζωτ} (cos ω_dτ + ζω/ω_d sin ω_dτ)) / ω²,

at the samples after it: exact for a piecewise-linear input whose jumps lie
on samples (between two samples, the piece after a jump is taken as the
continuation of the straight line: an error of the order of the slope's
change times Δt²).

Sampling: a sampled peak misses the continuous one by at most a fraction
1 − cos(ωT/2) ≈ (ωT)²/8 of it, so the frequencies are kept below a tenth
of the sampling rate by default (error ≤ 5 %, 1.2 % at a twentieth).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.linalg import expm
from scipy.signal import lfilter

from .pulses import STANDARD_GRAVITY

__all__ = ["ShockSpectrum", "shock_spectrum", "frequency_grid", "acceleration_coefficients",
           "ramp_invariant_coefficients", "step_response", "STANDARD_GRAVITY"]


def frequency_grid(fmin: float, fmax: float, per_octave: int) -> np.ndarray:
    """Logarithmic grid from ``fmin`` [Hz]: ``per_octave`` points an octave,
    the last at or below ``fmax`` [Hz] (``fmax`` itself added when it falls
    between two). Returns (n,) [Hz]."""
    n = int(math.floor(per_octave * math.log2(fmax / fmin) + 1e-9))
    f = fmin * 2.0 ** (np.arange(n + 1) / per_octave)
    if fmax > f[-1] * (1 + 1e-9):
        f = np.append(f, fmax)
    return f


def ramp_invariant_coefficients(omega: np.ndarray, zeta: float, dt: float,
                                output: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The ramp-invariant filter of each oscillator (see the module docstring).

    Parameters
    ----------
    omega : (n,) natural angular frequencies [rad/s]
    zeta : damping ratio [1]
    dt : sample spacing T [s]
    output : (n, 2) the row c of the output r = c (z, ż) for each oscillator

    Returns
    -------
    b : (n, 3), a : (n, 3) with a[:, 0] = 1 (scipy.signal.lfilter's convention).
    """
    omega = np.asarray(omega, dtype=float)
    n = omega.size
    M = np.zeros((n, 4, 4))
    M[:, 0, 1] = dt
    M[:, 1, 0] = -omega ** 2 * dt
    M[:, 1, 1] = -2.0 * zeta * omega * dt
    M[:, 1, 2] = -dt                                   # g = (0, −1): the base's acceleration
    M[:, 2, 3] = 1.0
    E = expm(M)
    Phi, G0, G1 = E[:, :2, :2], E[:, :2, 2], E[:, :2, 3]
    tr = Phi[:, 0, 0] + Phi[:, 1, 1]
    det = Phi[:, 0, 0] * Phi[:, 1, 1] - Phi[:, 0, 1] * Phi[:, 1, 0]
    P = Phi - tr[:, None, None] * np.eye(2)
    c = np.asarray(output, dtype=float)
    cP = np.einsum("ni,nij->nj", c, P)
    g0 = G0 - G1
    b = np.column_stack([np.sum(c * G1, axis=1),
                         np.sum(c * g0, axis=1) + np.sum(cP * G1, axis=1),
                         np.sum(cP * g0, axis=1)])
    a = np.column_stack([np.ones(n), -tr, det])
    return b, a


def acceleration_coefficients(omega: np.ndarray, zeta: float,
                              dt: float) -> tuple[np.ndarray, np.ndarray]:
    """Smallwood's closed-form filter of the absolute acceleration, (n, 3) b
    and a as :func:`ramp_invariant_coefficients` (needs ζ < 1)."""
    omega = np.asarray(omega, dtype=float)
    E = np.exp(-zeta * omega * dt)
    K = omega * math.sqrt(1.0 - zeta * zeta) * dt
    sk = np.sin(K) / K
    b = np.column_stack([1.0 - E * sk, 2.0 * E * (sk - np.cos(K)), E * E - E * sk])
    a = np.column_stack([np.ones_like(E), -2.0 * E * np.cos(K), E * E])
    return b, a


@dataclass(frozen=True)
class ShockSpectrum:
    """The SRS of one acceleration history (n frequencies).

    frequency : (n,) [Hz]; q : quality factor [1];
    positive, negative : (n,) the largest positive and the largest negative
    (as a magnitude, ≥ 0) absolute acceleration [m/s²];
    maximax : (n,) max of the two [m/s²];
    pseudo_velocity : (n,) ω·max|z| [m/s]; displacement : (n,) max|z| [m].
    """

    frequency: np.ndarray
    q: float
    positive: np.ndarray
    negative: np.ndarray
    maximax: np.ndarray
    pseudo_velocity: np.ndarray
    displacement: np.ndarray


def step_response(omega: float, zeta: float, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The oscillator's exact response to a unit step of the base's
    acceleration at τ = 0, from rest (module docstring).

    Parameters
    ----------
    omega : natural angular frequency [rad/s]; zeta : damping ratio < 1;
    tau : (m,) times after the step [s], ≥ 0

    Returns
    -------
    x : (m,) absolute acceleration per unit step [1];
    z : (m,) relative displacement per unit step [s²]
    """
    wd = omega * math.sqrt(1.0 - zeta * zeta)
    s = zeta * omega
    e = np.exp(-s * tau)
    c, sn = np.cos(wd * tau), np.sin(wd * tau)
    x = 1.0 - e * (c - s / wd * sn)
    z = -(1.0 - e * (c + s / wd * sn)) / (omega * omega)
    return x, z


def shock_spectrum(acceleration: np.ndarray, dt: float, frequency: np.ndarray,
                   q: float = 10.0, jumps=()) -> ShockSpectrum:
    """SRS of a base acceleration sampled every ``dt``.

    Parameters
    ----------
    acceleration : (k,) base acceleration ÿ [m/s²], uniformly sampled,
        the oscillators at rest before the first sample
    dt : sample spacing [s]
    frequency : (n,) natural frequencies [Hz], each below 1/(2 dt)
    q : quality factor Q = 1/(2ζ) [1]; ``math.inf`` for undamped oscillators
    jumps : sequence of (index, offset, size)
        Where the input jumps (module docstring): the first sample that
        holds the value after the jump, its time after the jump [s]
        (0 ≤ offset < dt) and the jump, after minus before [m/s²].

    Returns
    -------
    ShockSpectrum
    """
    u = np.array(acceleration, dtype=float)
    f = np.asarray(frequency, dtype=float)
    zeta = 0.0 if math.isinf(q) else 0.5 / q
    omega = 2.0 * math.pi * f
    ba, aa = acceleration_coefficients(omega, zeta, dt)
    bd, ad = ramp_invariant_coefficients(omega, zeta, dt,
                                         np.column_stack([np.ones_like(omega),
                                                          np.zeros_like(omega)]))
    steps = [(int(k), float(off), float(size)) for k, off, size in jumps
             if 0 <= int(k) < u.size and size != 0.0]
    for k, _, size in steps:
        u[k:] -= size
    pos = np.empty(f.size)
    neg = np.empty(f.size)
    disp = np.empty(f.size)
    for i in range(f.size):
        x = lfilter(ba[i], aa[i], u)
        z = lfilter(bd[i], ad[i], u)
        for k, off, size in steps:
            xs, zs = step_response(omega[i], zeta, off + dt * np.arange(u.size - k))
            x[k:] += size * xs
            z[k:] += size * zs
        pos[i] = max(0.0, float(x.max()))
        neg[i] = max(0.0, float(-x.min()))
        disp[i] = float(np.abs(z).max())
    return ShockSpectrum(f, float(q), pos, neg, np.maximum(pos, neg), omega * disp, disp)

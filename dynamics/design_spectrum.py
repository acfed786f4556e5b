"""Design shock spectra: the pseudo-acceleration a specification gives as a
function of frequency, for one damping ratio.

A design spectrum is a table of breakpoints (f_i, S_i) [Hz, m/s²] with
log–log interpolation between them,

    S(f) = S_i (f / f_i)^{ln(S_{i+1}/S_i) / ln(f_{i+1}/f_i)},   f_i ≤ f ≤ f_{i+1},

which is exact for the straight lines of a tripartite plot. Outside the
table: below f_0 the relative displacement of the first breakpoint is held
(S ∝ f², the constant-displacement line), above the last one its
acceleration is held (the zero-period acceleration a rigid item feels).

Tripartite breakpoints (levels of relative displacement D [m],
pseudo-velocity V [m/s] and acceleration A [m/s²]) give

    S(f) = min(ω² D, ω V, A),   ω = 2πf,

whose corners are f_DV = V / (2π D) and f_VA = A / (2π V)
(:func:`tripartite`): the table of its corners and of the band's ends.

The dynamics trusts what it is given; the file reader
(:mod:`flexbed.files.spectrum`) checks what users type.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["DesignSpectrum", "tripartite"]


@dataclass(frozen=True, slots=True)
class DesignSpectrum:
    """A design spectrum of pseudo-acceleration for one damping ratio.

    frequency : (n,) breakpoints [Hz], strictly increasing, > 0, n ≥ 1
    acceleration : (n,) pseudo-acceleration at them [m/s²], > 0
    damping : ζ the spectrum is given for [1]
    """

    frequency: np.ndarray
    acceleration: np.ndarray
    damping: float

    def __post_init__(self):
        f = np.array(self.frequency, dtype=float).reshape(-1)
        a = np.array(self.acceleration, dtype=float).reshape(-1)
        assert f.size == a.size >= 1 and np.all(np.diff(f) > 0) and f[0] > 0 and np.all(a > 0)
        f.setflags(write=False)
        a.setflags(write=False)
        object.__setattr__(self, "frequency", f)
        object.__setattr__(self, "acceleration", a)

    def __call__(self, f) -> np.ndarray:
        """Pseudo-acceleration S(f) [m/s²] at frequencies f [Hz] (any shape, > 0)."""
        f = np.asarray(f, dtype=float)
        lf, la = np.log(self.frequency), np.log(self.acceleration)
        x = np.log(f)
        inside = np.exp(np.interp(x, lf, la)) if lf.size > 1 else np.full(f.shape, la[0])
        below = self.acceleration[0] * (f / self.frequency[0]) ** 2
        return np.where(f < self.frequency[0], below, inside)

    def displacement(self, f) -> np.ndarray:
        """Relative displacement S(f)/ω² [m] at frequencies f [Hz]."""
        w = 2.0 * np.pi * np.asarray(f, dtype=float)
        return self(f) / w ** 2

    def velocity(self, f) -> np.ndarray:
        """Pseudo-velocity S(f)/ω [m/s] at frequencies f [Hz]."""
        return self(f) / (2.0 * np.pi * np.asarray(f, dtype=float))


def tripartite(displacement: float, velocity: float, acceleration: float,
               f_min: float, f_max: float, damping: float) -> DesignSpectrum:
    """The spectrum ``min(ω² D, ω V, A)`` on [f_min, f_max] as breakpoints.

    Parameters
    ----------
    displacement : D, relative displacement level [m]
    velocity : V, pseudo-velocity level [m/s]
    acceleration : A, acceleration level [m/s²]
    f_min, f_max : the band [Hz], 0 < f_min < f_max
    damping : ζ [1]

    Needs f_DV = V/(2πD) < f_VA = A/(2πV) (each level reached); the
    corners inside the band become breakpoints.
    """
    f_dv = velocity / (2.0 * math.pi * displacement)
    f_va = acceleration / (2.0 * math.pi * velocity)
    assert 0 < f_min < f_max and f_dv < f_va
    f = np.array(sorted({f_min, f_max} | {c for c in (f_dv, f_va) if f_min < c < f_max}))
    w = 2.0 * np.pi * f
    s = np.minimum(np.minimum(w ** 2 * displacement, w * velocity), acceleration)
    return DesignSpectrum(f, s, damping)

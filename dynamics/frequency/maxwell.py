"""A generalised Maxwell model fitted to an elastomer's complex stiffness:
the time-domain stand-in for k(f)(1 + iη(f)).

    K(ω) = k∞ + Σ_i k_i iωτ_i / (1 + iωτ_i),   k∞, k_i ≥ 0,

a spring k∞ beside springs k_i in series with dashpots k_i τ_i (each one
internal state, the dashpot's stretch, in a time run). k∞ is the law's
static ``k`` (:attr:`ElastomerTable.k_static`): the relaxed (ω → 0)
stiffness of the model is the stiffness the statics and the preloads use,
so the time run starts at the static equilibrium of the frequency
analyses, and the terms fit the rise ``k(f)(1 + iη(f)) − k``. The relaxation
times τ_i = 1/(2π f_i) are log-spaced, :data:`TERMS_PER_DECADE` per
decade, over the band widened by half a decade each side; the k_i come
from nonnegative least squares (:func:`scipy.optimize.nnls`) on the real
and imaginary parts over :data:`FIT_POINTS` log-spaced frequencies of the
band, each relative to |k(f)(1 + iη)| [Tschoegl, *The Phenomenological
Theory of Linear Viscoelastic Behavior*, 1989, ch. 4; Park & Schapery 1999
for the collocation by least squares].
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .elastomer import ElastomerTable

__all__ = ["MaxwellFit", "fit_maxwell", "TERMS_PER_DECADE", "FIT_POINTS", "CONSTANT_BAND"]

#: relaxation times per decade of frequency
TERMS_PER_DECADE = 2
#: log-spaced frequencies the fit is made and judged on
FIT_POINTS = 200
#: the band [Hz] over which a constant (one-row) elastomer is fitted
CONSTANT_BAND = (1.0, 1000.0)


@dataclass(frozen=True)
class MaxwellFit:
    """A fitted generalised Maxwell model per direction.

    band : (2,) — [Hz]; tau : (N,) — relaxation times [s];
    k_inf : (3,) — the static stiffness, the law's k [N/m]; k : (3, N) [N/m];
    error : (3,) — max over the band of |K_fit − K_table| / |K_table| [1].
    """

    band: tuple
    tau: np.ndarray
    k_inf: np.ndarray
    k: np.ndarray
    error: np.ndarray

    def complex(self, f: np.ndarray) -> np.ndarray:
        """K(ω) (m, 3) complex [N/m] at the frequencies ``f`` (m,) [Hz]."""
        s = 2j * math.pi * np.asarray(f, dtype=float).reshape(-1, 1) * self.tau[None, :]
        return self.k_inf[None, :] + (s / (1.0 + s)) @ self.k.T


def fit_maxwell(table: ElastomerTable) -> MaxwellFit:
    """Fit :class:`MaxwellFit` to ``table`` over its frequency band (a one-row
    table: over :data:`CONSTANT_BAND`), with k∞ = ``table.k_static``."""
    from scipy.optimize import nnls       # only for a scene with elastomer mounts: keeps
                                          # scipy.optimize out of every other scene's start
    f_lo, f_hi = ((float(table.frequency[0]), float(table.frequency[-1]))
                  if table.frequency.size > 1 else CONSTANT_BAND)
    lo, hi = math.log10(f_lo) - 0.5, math.log10(f_hi) + 0.5
    n_terms = int(math.ceil(TERMS_PER_DECADE * (hi - lo))) + 1
    tau = 1.0 / (2.0 * math.pi * np.logspace(lo, hi, n_terms))
    f = np.logspace(math.log10(f_lo), math.log10(f_hi), FIT_POINTS)
    s = 2j * math.pi * f[:, None] * tau[None, :]
    basis = s / (1.0 + s)                                               # (F, N)
    target = table.complex(f)                                           # (F, 3)
    k_inf, k, err = np.array(table.k_static, dtype=float), np.zeros((3, n_terms)), np.zeros(3)
    for d in range(3):
        w = 1.0 / np.abs(target[:, d])
        rise = target[:, d] - k_inf[d]
        A = np.vstack([basis.real * w[:, None], basis.imag * w[:, None]])
        b = np.concatenate([rise.real * w, rise.imag * w])
        k[d], _ = nnls(A, b)
        err[d] = float(np.max(np.abs(basis @ k[d] - rise) * w))
    return MaxwellFit((f_lo, f_hi), tau, k_inf, k, err)

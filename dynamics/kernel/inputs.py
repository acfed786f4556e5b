"""The base's inputs in compiled code: piecewise polynomials and windowed
sinusoids, their values and first and second integrals (one-sided limits
at a segment's end; see :mod:`flexbed.dynamics.kernel`)."""

from __future__ import annotations

import math

from numba import njit

__all__ = ["piecewise_value", "input_value"]


@njit(cache=True, no_cpython_wrapper=True)
def piecewise_value(breaks, origins, coeffs, x, seg_end):
    """A piecewise polynomial at x (see :mod:`flexbed.dynamics.piecewise`).

    breaks (nb,) increasing, +inf padded; origins (nb + 1,); coeffs
    (nb + 1, d + 1) ascending. Right-continuous, except at x ≥ seg_end: the
    piece to the left.
    """
    lo = 0
    hi = breaks.shape[0]
    if x >= seg_end:                  # count of breaks < x
        while lo < hi:
            mid = (lo + hi) // 2
            if breaks[mid] < x:
                lo = mid + 1
            else:
                hi = mid
    else:                             # count of breaks <= x
        while lo < hi:
            mid = (lo + hi) // 2
            if breaks[mid] <= x:
                lo = mid + 1
            else:
                hi = mid
    u = x - origins[lo]
    d = coeffs.shape[1]
    acc = 0.0
    for j in range(d - 1, -1, -1):
        acc = acc * u + coeffs[lo, j]
    return acc


@njit(cache=True, no_cpython_wrapper=True)
def _sinusoid(p, which, t, seg_end):
    """Windowed sinusoid a(t) = A sin(ω (t − s) + φ) on [s, e): value (0),
    first (1) or second (2) integral from s."""
    A, w, ph, s, e = p[0], p[1], p[2], p[3], p[4]
    cph, sph = math.cos(ph), math.sin(ph)
    if which == 0:
        if t >= seg_end:
            inside = s < t <= e
        else:
            inside = s <= t < e
        return A * math.sin(w * (t - s) + ph) if inside else 0.0
    if t <= s:
        return 0.0
    u = min(t, e) - s
    v = A / w * (cph - math.cos(w * u + ph))
    if which == 1:
        return v
    dist = A / w * cph * u - A / (w * w) * (math.sin(w * u + ph) - sph)
    if t > e:
        dist += v * (t - e)
    return dist


@njit(cache=True, no_cpython_wrapper=True)
def input_value(kind, sin, b, o, c, which, t, seg_end):
    """Input value (which = 0), first (1) or second (2) integral at t; one
    row of the ``in_*`` arrays."""
    if kind == 1:
        return _sinusoid(sin, which, t, seg_end)
    return piecewise_value(b[which], o[which], c[which], t, seg_end)


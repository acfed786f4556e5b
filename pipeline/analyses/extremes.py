"""Extremes of a sampled signal, located between the samples.

A run's outputs are exact values of a smooth signal at the output times;
the largest (or smallest) sample misses the true extreme by O(Δt²). The
parabola through that sample and its two neighbours puts it within
O(Δt³) for a smooth signal. The refined value always lies beyond the
extreme sample (so on the side a limit check should err to); at a kink (a
box's edge passed, a pulse's corner) it may pass the true extreme by up to
an eighth of the larger neighbouring difference. At either end of the
record, or on a flat top (a neighbour equal to the extreme sample), the
sample itself is the extreme.
"""

from __future__ import annotations

import numpy as np

__all__ = ["extreme", "Extreme"]


class Extreme(tuple):
    """(value, time): an extreme of a signal and when it occurs [s]."""

    __slots__ = ()

    def __new__(cls, value: float, time: float):
        return super().__new__(cls, (float(value), float(time)))

    value = property(lambda self: self[0])
    time = property(lambda self: self[1])


def extreme(t: np.ndarray, x: np.ndarray, kind: str = "max") -> Extreme:
    """The largest (``kind = "max"``) or smallest (``"min"``) value of x(t).

    Parameters
    ----------
    t : ndarray (k,)
        Increasing sample times [s].
    x : ndarray (k,)
        The signal at those times.
    kind : {"max", "min"}

    Returns
    -------
    Extreme
        (value, time), refined by the parabola through the extreme sample
        and its neighbours when that sample is interior and strictly beyond
        both; the sample itself otherwise.

    >>> t = np.linspace(0.0, 1.0, 11)
    >>> value, when = extreme(t, -(t - 0.43) ** 2, "max")
    >>> round(value, 12) + 0.0, round(when, 12)
    (0.0, 0.43)
    """
    t = np.asarray(t, dtype=float)
    sign = 1.0 if kind == "max" else -1.0
    y = sign * np.asarray(x, dtype=float)
    i = int(np.argmax(y))
    if 0 < i < y.size - 1 and y[i - 1] < y[i] > y[i + 1]:
        s = t[i - 1:i + 2] - t[i]
        a, b, c = np.polyfit(s, y[i - 1:i + 2], 2)
        if a < 0:
            s_top = min(max(-b / (2.0 * a), s[0]), s[2])
            top = (a * s_top + b) * s_top + c
            if top >= y[i]:
                return Extreme(sign * top, t[i] + s_top)
    return Extreme(sign * y[i], t[i])

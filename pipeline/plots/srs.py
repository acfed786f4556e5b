"""Shock response spectra as shock engineers read them: the acceleration
spectra in g (maximax, positive and negative, per axis, the input's beside
them) and the pseudo-velocity spectrum on tripartite paper (log-log
pseudo-velocity against frequency, with the lines of constant displacement
PV = 2πf·d and constant acceleration PV = a/(2πf) drawn and labelled)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from flexbed.plots.figure import STYLES, plt, save_figure

__all__ = ["plot_acceleration_srs", "plot_tripartite"]

#: below this share of the largest value a curve is round-off of an axis
#: the shock does not reach, and is left out
_FLOOR = 1e-6


def plot_acceleration_srs(path: Path, title: str, frequency: np.ndarray, curves: dict,
                          reference: dict, g: float) -> Path:
    """Maximax (solid), positive (dashed) and negative (dotted) absolute
    acceleration spectra per axis on log-log axes, in g (left) and m/s²
    (right); the input's maximax beside them (thin grey).

    Parameters
    ----------
    frequency : (n,) [Hz]
    curves : dict axis ("x", "y", "z") -> (positive, negative, maximax), each (n,) [g]
    reference : dict axis -> (n,) the input's maximax [g]
    g : float — standard gravity [m/s²], for the right-hand axis
    """
    top = max([float(np.max(v[2])) for v in curves.values()]
              + [float(np.max(v)) for v in reference.values()] + [0.0])
    fig, ax = plt.subplots(figsize=(8, 5))
    for c, (pos, neg, mm) in curves.items():
        if np.max(mm) <= _FLOOR * top:
            continue
        style = STYLES[c]
        ax.loglog(frequency, mm, label=f"{c} maximax", **style)
        ax.loglog(frequency, pos, label=f"{c} positive", **{**style, "ls": "--", "lw": 0.8})
        ax.loglog(frequency, neg, label=f"{c} negative", **{**style, "ls": ":", "lw": 0.8})
    for c, v in reference.items():
        if np.max(v) > _FLOOR * top:
            ax.loglog(frequency, v, label=f"input {c} maximax",
                      **{**STYLES[c], "lw": 2.5, "alpha": 0.3})
    if top > 0:
        shown = [float(np.min(v[v > _FLOOR * top])) for v in
                 [c[k] for c in curves.values() for k in range(3)] + list(reference.values())
                 if np.any(v > _FLOOR * top)]
        ax.set_ylim(max(1e-3 * top, 0.5 * min(shown)), 3.0 * top)
    ax.set_xlabel("natural frequency [Hz]")
    ax.set_ylabel("peak absolute acceleration [g]")
    right = ax.secondary_yaxis("right", functions=(lambda a: a * g, lambda a: a / g))
    right.set_ylabel("[m/s²]")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.12, 1.0), fontsize=7, borderaxespad=0.0)
    fig.tight_layout()
    return save_figure(fig, path)


def _decades(lo: float, hi: float, mantissas=(1.0, 2.0, 5.0)) -> list[float]:
    """m × 10^k from lo to hi (lo, hi > 0), m in ``mantissas``."""
    out = []
    for k in range(math.floor(math.log10(lo)) - 1, math.ceil(math.log10(hi)) + 1):
        out += [m * 10.0 ** k for m in mantissas if lo <= m * 10.0 ** k <= hi]
    return out


def _angle(ax, slope: float) -> float:
    """The angle [deg] on screen of a line of log-log ``slope`` in ``ax`` (its
    scales and limits set: the data transform needs no drawing)."""
    (x0, y0), (x1, y1) = ax.transData.transform([(1.0, 1.0), (10.0, 10.0 ** slope)])
    return math.degrees(math.atan2(y1 - y0, x1 - x0))


def plot_tripartite(path: Path, title: str, frequency: np.ndarray, curves: dict,
                    reference: dict, g: float) -> Path:
    """Pseudo-velocity PV = 2πf·max|z| [m/s] against frequency [Hz], log-log,
    on tripartite paper: lines of constant relative displacement d
    (PV = 2πf·d, rising) labelled in mm, and of constant pseudo-acceleration
    a (PV = a/(2πf), falling) labelled in g.

    Parameters
    ----------
    frequency : (n,) [Hz]
    curves : dict axis ("x", "y", "z") -> (n,) [m/s]
    reference : dict axis -> (n,) the input's pseudo-velocity [m/s]
    g : float — standard gravity [m/s²]
    """
    every = [v for v in (*curves.values(), *reference.values())]
    top = max([float(np.max(v)) for v in every] + [0.0])
    fig, ax = plt.subplots(figsize=(8, 6))
    f0, f1 = float(frequency[0]), float(frequency[-1])
    v0, v1 = (1e-3 * top, 3.0 * top) if top > 0 else (1e-3, 1.0)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlim(f0, f1)
    ax.set_ylim(v0, v1)
    grey = dict(color="0.55", lw=0.5)
    label = dict(fontsize=7, color="0.3", rotation_mode="anchor")
    ff = np.array([f0, f1])
    rising, falling = _angle(ax, 1.0), _angle(ax, -1.0)
    # constant displacement d (decades): PV = 2πf d, rising; labelled at the
    # right edge, or the top edge for those that leave through it
    for d in _decades(v0 / (2 * math.pi * f1), v1 / (2 * math.pi * f0), (1.0,)):
        ax.plot(ff, 2 * math.pi * ff * d, **grey)
        fx = min(f1, v1 / (2 * math.pi * d))
        if fx > f0:
            ax.text(fx / 1.05, 2 * math.pi * fx / 1.05 * d, f"{d * 1e3:g} mm", ha="right",
                    va="bottom", rotation=rising, **label)
    # constant pseudo-acceleration a (decades): PV = a/(2πf), falling; labelled
    # at the left edge, or the bottom edge for those that enter through the top
    for a in _decades(v0 * 2 * math.pi * f0 / g, v1 * 2 * math.pi * f1 / g, (1.0,)):
        ax.plot(ff, a * g / (2 * math.pi * ff), **{**grey, "ls": "--"})
        if v0 <= a * g / (2 * math.pi * f0) <= v1:
            fx, ha = f0 * 1.05, "left"
        elif f0 <= a * g / (2 * math.pi * v0) <= f1:
            fx, ha = a * g / (2 * math.pi * v0) / 1.3, "right"
        else:
            continue
        ax.text(fx, a * g / (2 * math.pi * fx), f"{a:g} g", ha=ha, va="bottom",
                rotation=falling, **label)
    for c, v in curves.items():
        if np.max(v) > _FLOOR * top:
            ax.loglog(frequency, v, label=f"{c}", **{**STYLES[c], "lw": 1.6})
    for c, v in reference.items():
        if np.max(v) > _FLOOR * top:
            ax.loglog(frequency, v, label=f"input {c}", **{**STYLES[c], "lw": 2.5,
                                                           "alpha": 0.3})
    ax.set_xlabel("natural frequency [Hz]")
    ax.set_ylabel("pseudo-velocity 2πf·max|z| [m/s]")
    ax.set_title(f"{title}\nsolid grey: constant displacement [mm]; dashed grey: constant "
                 f"pseudo-acceleration [g]", fontsize=9)
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=7, borderaxespad=0.0)
    fig.tight_layout()
    return save_figure(fig, path)

"""The benchmark's diagrams (``flexbed bench``): error against cost, log–log.

Same conventions as every plot (:mod:`flexbed.plots.figure`): 120 dpi,
grid, legend, written to a temporary name then renamed, so a reader never
sees half a file.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from matplotlib.ticker import FuncFormatter, LogLocator, MaxNLocator, NullFormatter

from flexbed.plots.figure import plt, save_figure

__all__ = ["Series", "Panel", "plot_loglog"]

#: one colour and marker per integrator; other series cycle through matplotlib's colours
STYLES = {"rk4": dict(color="k", marker="s"), "adams": dict(color="tab:green", marker="^"),
          "bdf": dict(color="tab:orange", marker="v"), "radau": dict(color="tab:red", marker="D"),
          "dop853": dict(color="tab:blue", marker="o")}


@dataclass
class Series:
    """One line: x, y > 0 (points with y ≤ 0 or NaN are left out), an
    optional text beside each point."""

    name: str
    x: list
    y: list
    labels: list | None = None


@dataclass
class Panel:
    """One log–log axes: its y label and its lines; ``targets`` are (x, y)
    points drawn as crosses (e.g. the project's aims)."""

    ylabel: str
    series: list
    targets: list = field(default_factory=list)


def tick_label(v: float, plain: bool = True) -> str:
    """A tick value as a plain number ("0.05", "200"; when ``plain``), else
    as m×10^k in mathtext ("5×10^-4")."""
    if v <= 0 or plain:
        return f"{v:g}"
    mant, exp = f"{v:.0e}".split("e")
    power = f"10^{{{int(exp)}}}"
    return f"${power}$" if mant == "1" else rf"${mant}\times{power}$"


def readable_log_ticks(axis, limits: tuple[float, float]) -> None:
    """Tick labels of a log axis that do not run into each other.

    Over up to two decades (where matplotlib labels the minor ticks 2–9 ×
    10^k, and 3×10^-1 and 4×10^-1 overlap), the labelled ticks are 1, 2
    and 5 × 10^k, written as plain numbers (0.02, 0.05, 0.1) when the whole
    range lies within 0.001–10 000, else as 2×10^-4 throughout, or a few
    round values when fewer than two of those fall in the range; over more
    decades, the decades only. Minor ticks stay, unlabelled.

    Parameters
    ----------
    axis : matplotlib Axis (``ax.xaxis`` or ``ax.yaxis``)
    limits : (low, high), both > 0
    """
    low, high = sorted(limits)
    decades = np.log10(high / low) if low > 0 else np.inf
    # one style per axis: plain numbers when the whole range reads well so
    plain = 1e-3 <= low and high < 1e4
    labels = FuncFormatter(lambda v, _pos: tick_label(v, plain))
    if decades > 2.0:
        axis.set_major_locator(LogLocator(base=10.0, subs=(1.0,)))
    else:
        k = np.arange(np.floor(np.log10(low)), np.ceil(np.log10(high)) + 1)
        ticks = np.outer(10.0 ** k, (1.0, 2.0, 5.0)).ravel()
        if np.count_nonzero((ticks >= low) & (ticks <= high)) >= 2:
            axis.set_major_locator(LogLocator(base=10.0, subs=(1.0, 2.0, 5.0)))
        else:       # a narrow range (e.g. 0.07-0.085 s): a few round values in it
            axis.set_major_locator(MaxNLocator(nbins=4))
        axis.set_major_formatter(labels)
    axis.set_minor_formatter(NullFormatter())


def plot_loglog(path: Path, title: str, xlabel: str, panels: list[Panel]) -> Path:
    """Panels side by side, log–log, one line per series, written to
    ``path`` (PNG); returns ``path``."""
    return save_figure(loglog_figure(title, xlabel, panels), path)


def loglog_figure(title: str, xlabel: str, panels: list[Panel]):
    """The figure of :func:`plot_loglog` (a matplotlib Figure, not closed)."""
    fig, axes = plt.subplots(1, len(panels), figsize=(5.2 * len(panels), 4.2), squeeze=False)
    for ax, panel in zip(axes[0], panels):
        drawn = False
        for s in panel.series:
            x = np.asarray(s.x, dtype=float)
            y = np.asarray(s.y, dtype=float)
            keep = np.isfinite(x) & np.isfinite(y) & (x > 0) & (y > 0)
            if not np.any(keep):
                continue
            style = STYLES.get(s.name, dict(marker="o"))
            ax.loglog(x[keep], y[keep], label=s.name, lw=1.0, ms=4, **style)
            drawn = True
            if s.labels is not None:
                # above and below the line in turn: neighbours close together
                # (1 and 2 modes, 4 and 6) keep their labels apart
                texts = np.asarray(s.labels, dtype=object)[keep]
                for i, (xi, yi, text) in enumerate(zip(x[keep], y[keep], texts)):
                    ax.annotate(str(text), (xi, yi), textcoords="offset points",
                                xytext=(4, 3) if i % 2 == 0 else (4, -4),
                                va="bottom" if i % 2 == 0 else "top", fontsize=7)
        for i, (tx, ty) in enumerate(panel.targets):
            ax.loglog([tx], [ty], ls="none", marker="x", ms=8, color="tab:purple",
                      label="aims" if i == 0 else None)
            drawn = True
        ax.set_xlabel(xlabel)
        ax.set_ylabel(panel.ylabel)
        if drawn:
            readable_log_ticks(ax.xaxis, ax.get_xlim())
            readable_log_ticks(ax.yaxis, ax.get_ylim())
        ax.grid(True, which="both", alpha=0.3)
        if drawn:
            ax.legend(loc="best", fontsize=8)
        else:
            ax.text(0.5, 0.5, "nothing finished", transform=ax.transAxes, ha="center")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return fig

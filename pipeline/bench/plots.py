"""The benchmark's PNG diagrams: error against cost, log–log (matplotlib, Agg).

Same conventions as :mod:`flexbed.plots`: 120 dpi, grid, legend, written to
a temporary name then renamed, so a reader never sees half a file.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from flexbed.plots import save_figure  # noqa: E402

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


def plot_loglog(path: Path, title: str, xlabel: str, panels: list[Panel]) -> Path:
    """Panels side by side, log–log, one line per series; returns ``path``."""
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
                for xi, yi, text in zip(x[keep], y[keep], np.asarray(s.labels, dtype=object)[keep]):
                    ax.annotate(str(text), (xi, yi), textcoords="offset points", xytext=(4, 3),
                                fontsize=7)
        for i, (tx, ty) in enumerate(panel.targets):
            ax.loglog([tx], [ty], ls="none", marker="x", ms=8, color="tab:purple",
                      label="aims" if i == 0 else None)
            drawn = True
        ax.set_xlabel(xlabel)
        ax.set_ylabel(panel.ylabel)
        ax.grid(True, which="both", alpha=0.3)
        if drawn:
            ax.legend(loc="best", fontsize=8)
        else:
            ax.text(0.5, 0.5, "nothing finished", transform=ax.transAxes, ha="center")
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    return save_figure(fig, path)

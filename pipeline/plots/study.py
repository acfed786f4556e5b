"""A study's plots: each metric against each varied numeric parameter
(``plots/<metric>--<parameter>.png``), and with exactly two varied
parameters a map of each metric over them (``plots/<metric>--map.png``).
Failed points are left out; matplotlib is imported on the first call."""

from __future__ import annotations

import re
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:       # annotations only
    from flexbed.study.table import StudyTable

__all__ = ["plot_study", "varied"]


def _file_part(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9._@-]+", "_", name).strip("_") or "column"


def varied(table: StudyTable) -> list[str]:
    """The numeric parameter columns that take more than one value (a
    column equal to one before it, such as the components of a mount's
    ``k`` varied together, is left out)."""
    out = []
    for name in table.parameters:
        col = table[name]
        if (col.dtype.kind in "if" and np.unique(col).size > 1
                and not any(np.array_equal(col, table[o]) for o in out)):
            out.append(name)
    return out


def plot_study(table: StudyTable, folder: Path) -> list[Path]:
    """Write the plots into ``folder`` (created); return their paths."""
    from flexbed.plots.figure import plt, save_figure

    ok = table.ok
    params = varied(table)
    written = []
    for metric in table.metrics:
        y = table[metric][ok]
        label = f"{metric} [{table.units[metric]}]" if table.units[metric] else metric
        for p in params:
            x = table[p][ok]
            fig, ax = plt.subplots(figsize=(6, 4))
            order = np.argsort(x, kind="stable")
            ax.plot(x[order], y[order], "o", ms=4, color="tab:blue")
            ax.set_xlabel(p)
            ax.set_ylabel(label)
            ax.set_title(f"{table.name}: {metric}", fontsize=9)
            ax.grid(True, alpha=0.3)
            written.append(save_figure(fig, folder / f"{_file_part(metric)}--{_file_part(p)}.png"))
        if len(params) == 2:
            x0, x1 = table[params[0]][ok], table[params[1]][ok]
            fig, ax = plt.subplots(figsize=(6, 5))
            sc = ax.scatter(x0, x1, c=y, s=60, cmap="viridis")
            fig.colorbar(sc, ax=ax, label=label)
            ax.set_xlabel(params[0])
            ax.set_ylabel(params[1])
            ax.set_title(f"{table.name}: {metric}", fontsize=9)
            written.append(save_figure(fig, folder / f"{_file_part(metric)}--map.png"))
    return written

"""What every plot of flexbed shares: matplotlib on its non-interactive Agg
backend, the line styles of the cases and axes, and :func:`save_figure`
(PNG at 120 dpi, written atomically, the figure closed)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from flexbed.files.destination import atomic_write  # noqa: E402

__all__ = ["plt", "STYLES", "save_figure"]

#: line styles of the compared cases and of the axes X, Y, Z
STYLES = {"rigid": dict(color="k", lw=1.2), "flexible": dict(color="tab:blue", lw=1.0, ls="--"),
          "damped": dict(color="tab:red", lw=1.0), "x": dict(color="tab:green", lw=1.0),
          "y": dict(color="tab:orange", lw=1.0), "z": dict(color="k", lw=1.2)}


def save_figure(fig, path: Path) -> Path:
    """Write a figure as PNG atomically (:mod:`flexbed.files.destination`) and close it."""
    try:
        return atomic_write(path, lambda tmp: fig.savefig(tmp, dpi=120, format="png"))
    finally:
        plt.close(fig)

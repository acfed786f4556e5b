"""PNG plots (matplotlib, non-interactive Agg backend)."""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

STYLES = {"rigid": dict(color="k", lw=1.2), "flexible": dict(color="tab:blue", lw=1.0, ls="--"),
          "damped": dict(color="tab:red", lw=1.0), "x": dict(color="tab:green", lw=1.0),
          "y": dict(color="tab:orange", lw=1.0), "z": dict(color="k", lw=1.2)}


def save_figure(fig, path: Path) -> Path:
    """Write a figure as PNG atomically (temporary file, then rename) and close it."""
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.stem}.tmp.png")
    fig.savefig(tmp, dpi=120)
    plt.close(fig)
    tmp.replace(path)
    return path


def plot_responses(path: Path, title: str, curves: dict[str, tuple[np.ndarray, np.ndarray]],
                   labels: dict[str, str], ylabel: str) -> Path:
    """One response per case over time (the paper's Figs. 11–12).

    Parameters
    ----------
    curves : dict case -> (t [s], value)
    """
    fig, ax = plt.subplots(figsize=(8, 4))
    for case, (t, v) in curves.items():
        ax.plot(t, v, label=labels.get(case, case), **STYLES.get(case, {}))
    ax.set_xlabel("time [s]")
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    return save_figure(fig, path)


def plot_series(path: Path, title: str, t: np.ndarray, value: np.ndarray, ylabel: str) -> Path:
    """A single time series (e.g. the base's acceleration, the paper's Fig. 10)."""
    fig, ax = plt.subplots(figsize=(8, 3))
    ax.plot(t, value, color="k", lw=1.0)
    ax.set_xlabel("time [s]")
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    fig.tight_layout()
    return save_figure(fig, path)

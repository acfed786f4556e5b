"""Plots of a random response: output PSDs on log–log axes with the input."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from flexbed.plots.figure import plt, save_figure

__all__ = ["plot_psd"]


def plot_psd(path: Path, title: str, frequency: np.ndarray, psd: np.ndarray, names: list[str],
             unit: str, rms: np.ndarray, input_psd: np.ndarray | None = None,
             input_names: list[str] | None = None, resonances: np.ndarray | None = None) -> Path:
    """PSDs (k, c) [unit²/Hz] on log–log axes, each labelled with its RMS
    [unit]; the input's PSDs (k, d) [same unit²/Hz] in black and greys;
    dotted vertical lines at the natural frequencies."""
    fig, ax = plt.subplots(figsize=(8, 5))
    top = float(np.max(psd)) if psd.size else 1.0
    if input_psd is not None:
        for j, name in enumerate(input_names or []):
            ok = input_psd[:, j] > 0.0
            ax.loglog(frequency[ok], input_psd[ok, j], color=("k", "0.35", "0.6")[j % 3],
                      lw=1.4, ls=("--", ":", "-.")[j % 3], label=f"input {name}")
            top = max(top, float(input_psd[:, j].max()))
    for j, name in enumerate(names):
        ok = psd[:, j] > 0.0
        ax.loglog(frequency[ok], psd[ok, j], lw=1.0, label=f"{name}: {rms[j]:.3g} {unit} RMS")
    for f in resonances if resonances is not None else ():
        ax.axvline(f, color="0.75", lw=0.5, ls=":")
    ax.set_ylim(top * 1e-8, top * 10.0)
    ax.set_xlim(frequency[0], frequency[-1])
    ax.set_xlabel("frequency [Hz]  (dotted: natural frequencies)")
    ax.set_ylabel(f"PSD [{unit}²/Hz]")
    ax.set_title(title)
    ax.grid(True, which="both", lw=0.3, color="0.85")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0)
    fig.tight_layout()
    return save_figure(fig, path)

"""Plots over frequency: the mounted system's decoupling table as a map,
Bode plots with the resonances marked, and a run's shock response spectra."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from flexbed.plots.figure import STYLES, plt, save_figure

__all__ = ["plot_energy", "plot_bode", "plot_shock_spectrum"]


def plot_energy(path: Path, title: str, labels: tuple, frequency: np.ndarray,
                energy: np.ndarray) -> Path:
    """Kinetic energy share [%] per mode (rows) and coordinate (columns)."""
    m, n = energy.shape
    fig, ax = plt.subplots(figsize=(max(6.0, 0.35 * n + 2.0), max(3.0, 0.3 * m + 1.5)))
    im = ax.imshow(100.0 * np.clip(energy, 0.0, 1.0), cmap="Greys", vmin=0.0, vmax=100.0,
                   aspect="auto")
    ax.set_xticks(range(n))
    ax.set_xticklabels(labels, rotation=90, fontsize=7)
    ax.set_yticks(range(m))
    ax.set_yticklabels([f"{k + 1}: {f:.2f} Hz" for k, f in enumerate(frequency)], fontsize=7)
    for k in range(m):
        for j in range(n):
            v = 100.0 * energy[k, j]
            if v >= 5.0:
                ax.text(j, k, f"{v:.0f}", ha="center", va="center", fontsize=6,
                        color="w" if v > 50.0 else "k")
    fig.colorbar(im, ax=ax, label="kinetic energy [%]")
    ax.set_title(title)
    fig.tight_layout()
    return save_figure(fig, path)


def plot_bode(path: Path, title: str, frequency: np.ndarray, H: np.ndarray, names: list[str],
              unit: str, resonances: np.ndarray, isolation: np.ndarray | None = None) -> Path:
    """|H| (log–log) and phase [deg] over frequency for the columns of H
    (k, c); dotted vertical lines at the natural frequencies; the band
    where an isolation column is below 1 shaded."""
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(9.5, 6), sharex=True,
                                 gridspec_kw={"height_ratios": [2, 1]})
    for j, name in enumerate(names):
        a1.loglog(frequency, np.abs(H[:, j]), lw=1.0, label=name)
        a2.semilogx(frequency, np.degrees(np.angle(H[:, j])), lw=1.0)
    for f in resonances:
        for ax in (a1, a2):
            ax.axvline(f, color="0.6", lw=0.6, ls=":")
    if isolation is not None and np.any(np.isfinite(isolation)):
        below = np.isfinite(isolation)
        a1.fill_between(frequency, 0, 1, where=below, color="tab:green", alpha=0.08,
                        transform=a1.get_xaxis_transform(), label="isolation (|T| < 1)")
    if unit == "1":
        a1.axhline(1.0, color="k", lw=0.6)
    a1.set_ylabel(f"|H| [{unit}]")
    a2.set_ylabel("phase [deg]")
    a2.set_yticks([-180, -90, 0, 90, 180])
    a2.set_xlabel("frequency [Hz]  (dotted: natural frequencies)")
    a1.set_title(title)
    for ax in (a1, a2):
        ax.grid(True, which="both", alpha=0.3)
    a1.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=7, borderaxespad=0.0)
    fig.tight_layout()
    return save_figure(fig, path)


def plot_shock_spectrum(path: Path, title: str, frequency: np.ndarray,
                        curves: dict[str, np.ndarray], reference: dict[str, np.ndarray]) -> Path:
    """Maximax shock response spectra on log-log axes: one curve per axis
    (solid), and a driven base's input spectrum beside them (dashed).

    Parameters
    ----------
    frequency : (n,) [Hz]
    curves, reference : dict axis ("x", "y", "z") -> (n,) [m/s²]; a curve
        below 1e-6 of the largest everywhere (round-off of an axis the
        shock does not reach) is left out, and the axis spans four decades
    """
    top = max([float(np.max(v)) for v in (*curves.values(), *reference.values())] + [0.0])
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for c, v in curves.items():
        if np.max(v) > 1e-6 * top:
            ax.loglog(frequency, v, label=f"{c}", **STYLES[c])
    for c, v in reference.items():
        if np.max(v) > 1e-6 * top:
            ax.loglog(frequency, v, label=f"input {c}", **{**STYLES[c], "ls": ":"})
    if top > 0:
        ax.set_ylim(1e-4 * top, 2.0 * top)
    ax.set_xlabel("natural frequency [Hz]")
    ax.set_ylabel("maximax absolute acceleration [m/s²]")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0.0)
    fig.tight_layout()
    return save_figure(fig, path)

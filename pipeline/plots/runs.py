"""A run's plots over time: responses of the compared cases or of a
point's axes, a single time series (the base's input), and the mount
forces, one panel per pair of bodies joined and mount axis."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from flexbed.plots.figure import STYLES, plt, save_figure

__all__ = ["plot_responses", "plot_series", "plot_mount_forces", "mount_forces_figure",
           "mount_style", "mount_groups", "significant_directions"]


def plot_responses(path: Path, title: str, curves: dict[str, tuple[np.ndarray, np.ndarray]],
                   labels: dict[str, str], ylabel: str) -> Path:
    """One response per case over time (the paper's Figs. 11–12).

    Parameters
    ----------
    curves : dict case -> (t [s], value)
    """
    fig, ax = plt.subplots(figsize=(9.5, 4))
    for case, (t, v) in curves.items():
        ax.plot(t, v, label=labels.get(case, case), **STYLES.get(case, {}))
    ax.set_xlabel("time [s]")
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, borderaxespad=0.0)
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


#: line styles of the mounts within one panel: colour and dash pattern both
#: differ between neighbours, so curves drawn on top of each other (symmetric
#: mounts) stay visible: a dashed line over a solid one
MOUNT_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown",
                 "tab:pink", "tab:gray", "tab:olive", "tab:cyan")
MOUNT_DASHES = ("-", "--", ":", "-.")


def mount_style(i: int) -> dict:
    """Line style of the i-th mount of a panel (0-based): 40 distinct
    combinations of colour and dash pattern, wider lines first."""
    colour = MOUNT_COLOURS[i % len(MOUNT_COLOURS)]
    dash = MOUNT_DASHES[(i + i // len(MOUNT_COLOURS)) % len(MOUNT_DASHES)]
    return dict(color=colour, ls=dash, lw=2.0 if dash == "-" else 1.3)


def mount_groups(body_i: list[str], body_j: list[str]) -> list[tuple[str, list[int]]]:
    """Mounts grouped by the pair of bodies they join, in order of first
    appearance: [("base – bed", [0, 1, 2, 3]), ...]."""
    groups: dict[tuple[str, str], list[int]] = {}
    for m, pair in enumerate(zip(body_i, body_j)):
        groups.setdefault(pair, []).append(m)
    return [(f"{a} – {b}", idx) for (a, b), idx in groups.items()]


def significant_directions(force: np.ndarray, share: float = 1e-3) -> list[int]:
    """Mount axes (0, 1, 2) whose peak |force| exceeds ``share`` of the
    largest: the directions worth a panel (at least one)."""
    peak = np.abs(force).max(axis=(0, 1)) if force.size else np.zeros(3)
    keep = [k for k in range(3) if peak[k] > share * peak.max()]
    return keep or [2]


def plot_mount_forces(path: Path, title: str, t: np.ndarray, force: np.ndarray,
                      names: list[str], body_i: list[str], body_j: list[str]) -> Path:
    """Mount forces over time as a PNG (:func:`mount_forces_figure`); returns ``path``."""
    return save_figure(mount_forces_figure(title, t, force, names, body_i, body_j), path)


def mount_forces_figure(title: str, t: np.ndarray, force: np.ndarray, names: list[str],
                        body_i: list[str], body_j: list[str]):
    """Mount forces over time: one panel per pair of bodies joined (rows)
    and mount axis carrying force (columns), a legend beside each row
    (a matplotlib Figure, not closed).

    Parameters
    ----------
    t : ndarray (k,)
        [s].
    force : ndarray (k, M, 3)
        Force along each mount's axes u1, u2, u3 [N].
    names, body_i, body_j : list of str (M,)
        Mount names and the bodies each joins.

    Notes
    -----
    A mount whose curve equals an earlier one's in the panel (to 1e-6 of
    the panel's peak; symmetric mounts) is labelled "M3 (= M1)".
    """
    groups = mount_groups(body_i, body_j)
    dirs = significant_directions(force)
    rows, cols = len(groups), len(dirs)
    width, height = 4.2 * cols + 2.2, 2.4 * rows + 0.8
    fig, axes = plt.subplots(rows, cols, figsize=(width, height), squeeze=False, sharex=True)
    # fixed margins [inch] (a layout engine measured every label twice: half the figure's
    # time): tick labels and the y label on the left of each panel, its title above, the
    # legends in the 2.2 inch column on the right
    fig.subplots_adjust(left=0.85 / width, right=(width - 1.9) / width, bottom=0.5 / height,
                        top=(height - 0.55) / height, wspace=0.95 / (4.2 - 0.95),
                        hspace=0.55 / (2.4 - 0.55))
    for r, (label, members) in enumerate(groups):
        for c, k in enumerate(dirs):
            ax = axes[r, c]
            curves = force[:, members, k]
            scale = float(np.abs(curves).max()) if curves.size else 0.0
            for n, m in enumerate(members):
                same = next((names[members[q]] for q in range(n)
                             if np.abs(curves[:, q] - curves[:, n]).max() <= 1e-6 * scale), None)
                text = names[m] if same is None else f"{names[m]} (= {same})"
                ax.plot(t, curves[:, n], label=text, **mount_style(n))
            ax.set_title(f"{label}: along u{k + 1}", fontsize=9)
            ax.set_ylabel(f"f{k + 1} [N]")
            ax.grid(True, alpha=0.3)
            if r == rows - 1:
                ax.set_xlabel("time [s]")
        axes[r, -1].legend(loc="upper left", bbox_to_anchor=(1.02, 1.0), fontsize=8,
                           frameon=False, handlelength=3.0)
    fig.suptitle(title, fontsize=10)
    return fig

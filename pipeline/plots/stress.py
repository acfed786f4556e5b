"""The map of the bed's peak von Mises stress over a run: each element
coloured by its peak (MPa), the peak's element marked, mount points and
stiffeners drawn, axes in the drawing frame (m)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.collections import PolyCollection

from flexbed.plots.figure import plt, save_figure

__all__ = ["plot_peak_map"]


def plot_peak_map(path: Path, title: str, nodes: np.ndarray, cells: np.ndarray,
                  peak: np.ndarray, where: tuple[float, float], origin: np.ndarray,
                  mounts: np.ndarray | None = None, lines: tuple = ()) -> Path:
    """Write the peak map as PNG.

    Parameters
    ----------
    path : Path
    title : str
    nodes : ndarray (N, 2) or (N, 3)
        Bed-frame node coordinates [m].
    cells : ndarray (ne, 4)
        Quadrilaterals; triangles as (a, b, c, c).
    peak : ndarray (ne,)
        Each element's peak von Mises stress [Pa].
    where : (x, y)
        The peak's place in the bed frame [m].
    origin : ndarray (2,) or (3,)
        The bed frame's origin in the drawing frame [m].
    mounts : ndarray (m, 2), optional
        Mount points in the drawing frame [m].
    lines : tuple of ((x0, y0), (x1, y1))
        Stiffeners in the drawing frame [m].
    """
    o = np.asarray(origin, dtype=float)[:2]
    xy = np.asarray(nodes, dtype=float)[:, :2] + o
    polys = [xy[c[:3]] if c[3] == c[2] else xy[c] for c in np.asarray(cells)]
    span = np.ptp(xy, axis=0)
    tall = span[1] > span[0]
    w, h = (span[0], span[1]) if not tall else (span[1], span[0])
    fig, ax = plt.subplots(figsize=(9.0, max(3.6, 9.0 * h / w * 0.9 + 2.0)))
    if tall:                                   # long side across the page
        polys = [p[:, ::-1] for p in polys]
    coll = PolyCollection(polys, array=np.asarray(peak) / 1e6, cmap="viridis",
                          edgecolors="face", linewidths=0.2)
    ax.add_collection(coll)
    fig.colorbar(coll, ax=ax, label="peak von Mises [MPa]", fraction=0.04, pad=0.02)

    def flip(p):
        p = np.asarray(p, dtype=float)
        return p[..., ::-1] if tall else p

    for a, b in lines:
        seg = flip(np.array([a, b]))
        ax.plot(seg[:, 0], seg[:, 1], color="w", lw=1.5, ls="--", label="stiffener")
    if mounts is not None and len(mounts):
        m = flip(np.asarray(mounts)[:, :2])
        ax.plot(m[:, 0], m[:, 1], "o", mfc="none", mec="tab:red", ms=8, label="mount points")
    p = flip(np.asarray(where, dtype=float) + o)
    ax.plot(p[0], p[1], "x", color="tab:red", ms=12, mew=2.5,
            label=f"peak {np.max(peak) / 1e6:.3g} MPa")
    ax.set_xlabel("y [m]" if tall else "x [m]")
    ax.set_ylabel("x [m]" if tall else "y [m]")
    ax.set_aspect("equal")
    ax.autoscale_view()
    x0, x1 = ax.get_xlim()
    y0, y1 = ax.get_ylim()
    pad = 0.06 * max(x1 - x0, y1 - y0)            # the mount markers clear of the frame
    ax.set_xlim(x0 - pad, x1 + pad)
    ax.set_ylim(y0 - pad, y1 + pad)
    handles, labels = ax.get_legend_handles_labels()
    keep = dict(zip(labels, handles))
    fig.legend(keep.values(), keep.keys(), loc="lower center", ncol=3, frameon=False)
    ax.set_title(title)
    fig.tight_layout(rect=(0, 0.12, 1, 0.98))
    return save_figure(fig, path)

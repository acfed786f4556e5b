"""A synthesised base motion and its match to the design spectrum: the
acceleration history in g, and its SRS (maximax) against the target with
the tolerance band, log-log in g and m/s²."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from flexbed.plots.figure import plt, save_figure

__all__ = ["plot_synthesis"]


def plot_synthesis(path: Path, title: str, syn, g: float) -> Path:
    """Two panels: the acceleration [g] against time [ms]; the achieved SRS
    and the target [g] against frequency [Hz] with the ±tolerance band.

    syn : :class:`flexbed.dynamics.spectrum_synthesis.Synthesis`
    g : standard gravity [m/s²]
    """
    fig, (ax1, ax2) = plt.subplots(2, 1, figsize=(8, 7.5))
    ax1.plot(1e3 * syn.time, syn.acceleration / g, lw=0.5, color="C0")
    ax1.set_xlabel("time [ms]")
    ax1.set_ylabel("base acceleration [g]")
    ax1.set_title(f"{title}: synthesised motion (end velocity {syn.end_velocity:.1e} m/s, "
                  f"displacement {syn.end_displacement:.1e} m)", fontsize=9)
    ax1.grid(True, alpha=0.3)
    band = 10.0 ** (syn.tolerance_db / 20.0)
    f, tgt = syn.frequency, syn.target / g
    ax2.fill_between(f, tgt / band, tgt * band, color="0.85",
                     label=f"target ±{syn.tolerance_db:g} dB")
    ax2.loglog(f, tgt, color="k", lw=1.2, label="target (design spectrum)")
    ax2.loglog(f, syn.achieved / g, "o-", color="C3", ms=3, lw=0.8,
               label=f"achieved (worst {np.abs(syn.error_db).max():.2f} dB)")
    ax2.set_xlabel("natural frequency [Hz]")
    ax2.set_ylabel(f"maximax SRS, ζ = {syn.damping:g} [g]")
    right = ax2.secondary_yaxis("right", functions=(lambda a: a * g, lambda a: a / g))
    right.set_ylabel("[m/s²]")
    ax2.grid(True, which="both", alpha=0.3)
    ax2.legend(loc="lower right", fontsize=8)
    fig.tight_layout()
    return save_figure(fig, path)

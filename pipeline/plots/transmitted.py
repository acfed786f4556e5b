"""Spectra of the force transmitted to the base: narrow-band lines and
third-octave bands in dB re 1 N, one design or two (insertion loss)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from flexbed.analyses.transmitted import db
from flexbed.plots.figure import plt, save_figure

__all__ = ["plot_transmitted"]


def plot_transmitted(path: Path, title: str, cases: dict, axis: int = 2,
                     fmax: float | None = None) -> Path:
    """Narrow-band RMS per line (top) and third-octave band levels (bottom)
    of the total transmitted force along ``axis`` (0, 1, 2: x, y, z), in
    dB re 1 N over a log frequency axis; ``cases``: label → (Spectrum,
    Bands), drawn in that order (the first is the reference)."""
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 6.5), sharex=True)
    name = "xyz"[axis]
    for label, (sp, bands) in cases.items():
        sel = sp.frequency > 0
        a1.semilogx(sp.frequency[sel], db(np.maximum(sp.rms[sel, axis], 1e-12)), lw=0.9,
                    label=label)
        edges = np.append(bands.lower, bands.upper[-1])
        a2.stairs(db(np.maximum(bands.rms[:, axis], 1e-12)), edges, lw=1.4, label=label,
                  baseline=None)
    a2.set_xscale("log")
    top = max(np.max(db(np.maximum(sp.rms[:, axis], 1e-12))) for sp, _ in cases.values())
    low = min(np.min(db(np.maximum(b.rms[:, axis], 1e-12))) for _, b in cases.values())
    for ax in (a1, a2):
        ax.set_ylim(max(low - 10.0, top - 140.0), top + 10.0)
        ax.grid(True, which="both", lw=0.3, color="0.85")
        ax.legend(loc="upper right", fontsize=8, framealpha=0.9)
    a1.set_ylabel(f"F{name} RMS per line [dB re 1 N]")
    a2.set_ylabel(f"F{name} third-octave [dB re 1 N]")
    a2.set_xlabel("frequency [Hz]")
    if fmax is not None:
        a2.set_xlim(left=1.0, right=fmax)
    first = next(iter(cases.values()))[0]
    a1.set_title(f"{title}\nHann window, {first.samples} samples from {first.start:g} s, "
                 f"Δf = {first.resolution:.3g} Hz", fontsize=9)
    fig.tight_layout()
    return save_figure(fig, path)

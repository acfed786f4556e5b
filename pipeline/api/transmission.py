"""The force transmitted to the base as a library call (as ``flexbed
transmitted``): time histories, narrow-band and third-octave spectra, and
the insertion loss of one design against another
(:mod:`flexbed.analyses.transmitted`).

>>> import flexbed
>>> c = flexbed.compare(flexbed.load_scene("raft.toml"))             # doctest: +SKIP
>>> rigid = flexbed.transmitted(c.runs["rigid"], start=2.0)           # doctest: +SKIP
>>> flexible = flexbed.transmitted(c.runs["flexible"], start=2.0)     # doctest: +SKIP
>>> flexible.insertion_loss(rigid)            # dB per band and axis   # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from flexbed.analyses.transmitted import (Bands, Spectrum, TransmittedForce, db,
                                          insertion_loss, spectrum, third_octaves,
                                          transmitted_force)
from flexbed.api.results import Results
from flexbed.errors import InputError
from flexbed.files.results import read_results

__all__ = ["Transmitted", "transmitted"]


@dataclasses.dataclass(frozen=True)
class Transmitted:
    """The force into the base of one run.

    force : TransmittedForce (``time``, ``mounts``, ``per_mount`` (k, Mb,
    3), ``total`` (k, 3) [N]); spectrum : Spectrum of the total (narrow
    band, RMS per line [N]); bands : Bands (third octaves, RMS [N]).
    """

    force: TransmittedForce
    spectrum: Spectrum
    bands: Bands

    @property
    def band_levels(self) -> np.ndarray:
        """Third-octave levels (nb, 3) [dB re 1 N]."""
        return db(self.bands.rms)

    def insertion_loss(self, reference: Transmitted) -> np.ndarray:
        """L_reference − L_this per third-octave band and axis (nb, 3) [dB]:
        positive where this design transmits less."""
        if not isinstance(reference, Transmitted):
            raise InputError(f"flexbed.Transmitted.insertion_loss: reference = {reference!r} "
                             f"is not the result of flexbed.transmitted")
        return insertion_loss(reference.bands, self.bands)


def transmitted(results, *, start: float | None = None, fmax: float | None = None
                ) -> Transmitted:
    """The force the mounts put into the base, and its spectra.

    Parameters
    ----------
    results : Results or path
        A run (:func:`flexbed.simulate`, a :func:`flexbed.compare` run) or
        its results file.
    start : float, optional
        First time analysed [s] (default: the second half of the run).
    fmax : float, optional
        Highest third-octave band [Hz] (default: the Nyquist frequency).
    """
    from flexbed.api.arguments import Arguments

    check = Arguments("transmitted")
    if isinstance(results, Results):
        contents = results.contents
    elif isinstance(results, (str, Path)):
        contents = read_results(results)
    else:
        check.bad("results", results, "a run (flexbed.simulate) or a results file's path")
    start = check.real(start, "start")
    fmax = check.real(fmax, "fmax", positive=True)
    force = transmitted_force(contents)
    t = force.time
    start = 0.5 * (t[0] + t[-1]) if start is None else start
    if not t[0] <= start < t[-1]:
        check.bad("start", start, f"in the run, {t[0]:g} to {t[-1]:g} s")
    if fmax is not None and not fmax >= 1.0:
        check.bad("fmax", fmax, "at least 1 Hz (the lowest third-octave band's)")
    sp = spectrum(t, force.total, float(start))
    return Transmitted(force, sp, third_octaves(sp, 1.0, fmax))

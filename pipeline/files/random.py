"""The random-vibration file (HDF5 via flexbed.files.store).

``flexbed.random`` 1.0 — a stationary random response to base acceleration
PSDs:

- ``frequency`` (k,) [Hz]; ``input/psd`` (k, 3) [g^2/Hz] base acceleration
  auto-spectra X, Y, Z; ``input/psd_si`` (k, 3) [(m/s^2)^2/Hz];
  ``input/rms`` (3,) [g]; ``input/coherence_real``, ``_imag`` (3, 3);
- ``outputs/names``, ``outputs/units`` (o,) SI units;
- ``response/psd`` (k, o) [unit^2/Hz]; ``response/rms``,
  ``response/rms_error`` (the integration error's estimate),
  ``response/three_sigma``, ``response/peak`` (o,) [unit];
  ``response/acceleration_index`` (a,) the acceleration outputs and
  ``response/acceleration_rms_g`` (a,) [g] their RMS;
- ``miles/output`` (s,) the outputs one mode dominates, ``miles/rms`` (s,)
  [unit], ``miles/frequency`` (s,) [Hz], ``miles/damping_ratio`` (s,);
  ``miles/half_power_share`` (o,) [1];
- ``resonances/frequency``, ``resonances/damping_ratio`` (m,);
- root attributes ``psd_source``, ``peak_factor``, ``solve_time`` [s CPU];
  ``scene/toml``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from flexbed.files.store import Dataset, write_file

__all__ = ["write_random", "random_contents", "write_random_contents", "RANDOM_SCHEMA"]

RANDOM_SCHEMA = "flexbed.random"
VERSION = "1.0"
_G0 = 9.80665


def write_random(path, sf, r) -> Path:
    """Write a :class:`flexbed.analyses.random.RandomResponse` as ``flexbed.random``."""
    return write_random_contents(path, *random_contents(sf, r))


def write_random_contents(path, datasets: dict, attrs: dict) -> Path:
    """Write what :func:`random_contents` gave, atomically."""
    return write_file(path, schema=RANDOM_SCHEMA, version=VERSION, datasets=datasets,
                      attrs=attrs)


def random_contents(sf, r) -> tuple[dict, dict]:
    """The datasets and group attributes of :func:`write_random`'s file, in memory."""
    acc = r.acceleration
    dom = np.isfinite(r.miles.rms)
    ds = {
        "frequency": Dataset(r.frequency, "Hz", "frequencies"),
        "input/psd": Dataset(r.input_psd, "g^2/Hz", "base acceleration PSD along X, Y, Z"),
        "input/psd_si": Dataset(r.input_psd * _G0**2, "(m/s^2)^2/Hz",
                                "base acceleration PSD along X, Y, Z"),
        "input/rms": Dataset(r.input_rms, "g", "base acceleration RMS along X, Y, Z"),
        "outputs/names": Dataset(np.array(r.names), "", "output names"),
        "outputs/units": Dataset(np.array(r.units), "", "SI unit of each output"),
        "response/psd": Dataset(r.psd, "see outputs/units, squared per Hz", "output PSD"),
        "response/rms": Dataset(r.rms, "see outputs/units", "RMS (1 sigma)"),
        "response/rms_error": Dataset(r.rms_error, "see outputs/units",
                                      "RMS integration error estimate (Richardson)"),
        "response/three_sigma": Dataset(r.three_sigma, "see outputs/units", "3 sigma"),
        "response/peak": Dataset(r.peak, "see outputs/units", "peak_factor sigma"),
        "response/acceleration_index": Dataset(np.flatnonzero(acc), "1",
                                               "the acceleration outputs' indices"),
        "response/acceleration_rms_g": Dataset(r.rms[acc] / _G0, "g",
                                               "RMS of those accelerations in g"),
        "miles/output": Dataset(np.flatnonzero(dom), "1",
                                "indices of the outputs one mode dominates"),
        "miles/rms": Dataset(r.miles.rms[dom], "see outputs/units",
                             "their Miles' RMS sqrt(pi zeta fn S(fn))"),
        "miles/frequency": Dataset(r.miles.frequency[dom], "Hz", "the dominant mode's frequency"),
        "miles/damping_ratio": Dataset(r.miles.damping_ratio[dom], "1", "its damping ratio"),
        "miles/half_power_share": Dataset(r.miles.share, "1", "per output, the largest share "
                                          "of the mean square in a mode's half-power band"),
        "resonances/frequency": Dataset(r.resonances, "Hz", "natural frequencies in the band"),
        "resonances/damping_ratio": Dataset(r.damping_ratio, "1", "their damping ratios"),
        "scene/toml": Dataset(sf.text, "", "the scene file this came from"),
    }
    attrs = {"": {"psd_source": r.source, "peak_factor": float(r.peak_factor),
                  "solve_time": float(r.solve_time), "scene_digest": sf.digest}}
    return ds, attrs

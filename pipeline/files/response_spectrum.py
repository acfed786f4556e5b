"""The response-spectrum analysis's file (HDF5 via flexbed.files.store).

``flexbed.response_spectrum`` 1.0 — per axis ``x``, ``y``, ``z`` given:

- ``<axis>/modes/frequency`` (m,) [Hz], ``<axis>/modes/participation``
  (m,) [kg^1/2], ``<axis>/modes/effective_mass`` (m,) [kg],
  ``<axis>/modes/spectral_acceleration`` (m,) [m/s²];
- ``<axis>/outputs/names``, ``<axis>/outputs/units`` (k,);
  ``<axis>/modal`` (m, k) each mode's signed peak [outputs/units];
- ``<axis>/combined/<rule>`` (k,) for nrl, srss, cqc, abs [outputs/units];
- group attribute ``mass_included`` [1];
- ``spectrum/toml``, ``scene/toml``; root attributes ``damping`` [1],
  ``spectrum_name``, ``spectrum_units``, ``close_modes`` (the NRL grouping
  fraction), ``max_frequency`` [Hz] (NaN: none), ``solve_time`` [s CPU].
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from flexbed.dynamics.frequency.response_spectrum import CLOSE_MODES, RULES
from flexbed.files.store import Dataset, write_file

__all__ = ["write_rsa", "rsa_contents", "RSA_SCHEMA"]

RSA_SCHEMA = "flexbed.response_spectrum"
VERSION = "1.0"


def rsa_contents(sf, r) -> tuple[dict, dict]:
    """Datasets and group attributes of a
    :class:`flexbed.analyses.response_spectrum.ResponseSpectrum`, in memory."""
    ds, attrs = {}, {}
    for d, a in r.axes.items():
        g = "xyz"[d]
        p = a.peaks
        ds[f"{g}/modes/frequency"] = Dataset(p.frequency, "Hz", "natural frequency (undamped)")
        ds[f"{g}/modes/participation"] = Dataset(p.participation, "kg^1/2",
                                                 "participation factor for the base axis")
        ds[f"{g}/modes/effective_mass"] = Dataset(p.effective_mass, "kg", "modal effective mass")
        ds[f"{g}/modes/spectral_acceleration"] = Dataset(p.spectral, "m/s^2",
                                                         "design spectrum at the mode")
        ds[f"{g}/outputs/names"] = Dataset(np.array(a.names), "", "output names")
        ds[f"{g}/outputs/units"] = Dataset(np.array(a.units), "", "output units")
        ds[f"{g}/modal"] = Dataset(a.modal, "see outputs/units", "each mode's signed peak")
        for rule in RULES:
            ds[f"{g}/combined/{rule}"] = Dataset(a.combined[rule], "see outputs/units",
                                                 f"peaks combined by {rule.upper()}")
        attrs[g] = {"mass_included": float(a.mass_included)}
    ds["spectrum/toml"] = Dataset(r.spectrum.text, "", "the design spectrum file")
    ds["scene/toml"] = Dataset(sf.text, "", "the scene file this came from")
    attrs[""] = {"damping": float(r.damping), "spectrum_name": r.spectrum.name,
                 "spectrum_units": r.spectrum.units, "close_modes": CLOSE_MODES,
                 "max_frequency": math.nan if r.max_frequency is None else float(r.max_frequency),
                 "solve_time": float(r.solve_time), "scene_digest": sf.digest}
    return ds, attrs


def write_rsa(path, sf, r) -> Path:
    """Write a response-spectrum analysis as ``flexbed.response_spectrum``, atomically."""
    ds, attrs = rsa_contents(sf, r)
    return write_file(path, schema=RSA_SCHEMA, version=VERSION, datasets=ds, attrs=attrs)

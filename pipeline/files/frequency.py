"""Files of the frequency-domain analyses (HDF5 via flexbed.files.store).

``flexbed.modal`` 1.0 — the mounted system's modes (base held):

- ``coordinates/labels`` (n,): what each coordinate of q is ("<body> x"
  … "<body> yaw": δr [m] inertial, θ [rad] body frame; "<body> mode k"
  [kg^1/2 m]);
- ``matrices/mass``, ``matrices/stiffness``, ``matrices/damping`` (n, n)
  [SI per coordinate]: M q̈ + C q̇ + K q = f about the equilibrium;
- ``modes/frequency``, ``modes/damped_frequency`` (m,) [Hz],
  ``modes/damping_ratio`` (m,) [1], ``modes/shape_real``,
  ``modes/shape_imag`` (m, n): complex shapes, largest component 1;
  ``modes/overdamped_rates`` (r,) [1/s]: decay rates of the real roots
  (overdamped motions: no modes);
- ``energy/kinetic`` (m, n) [1]: kinetic energy share per coordinate;
  ``energy/strain_mounts`` (m, M, 3) [1] per mount axis,
  ``energy/strain_elastic`` (m,) [1] of the bed's deformation;
- ``effective_mass/undamped_frequency`` (n,) [Hz], ``effective_mass/mass``
  (n, 3) [kg] along X, Y, Z, ``effective_mass/cumulative`` (n, 3) [1];
  root attribute ``moving_mass`` [kg];
- ``mounts/names`` (M,); ``equilibrium/y`` (ny,); ``scene/toml``; root
  attributes ``solve_time`` [s CPU], ``equilibrium_source``.

``flexbed.frf`` 1.0 — one frequency response:

- ``frequency`` (k,) [Hz]; ``outputs/names``, ``outputs/units`` (o,);
  ``response/real``, ``response/imag`` (k, o): H, a response being
  Re(H e^{iωt}) for the unit input Re(e^{iωt}); ``response/magnitude``,
  ``response/phase_deg``;
- ``resonances/frequency``, ``resonances/damping_ratio`` (m,): the modes
  in the band; ``peaks`` (P, 3): output index, frequency [Hz], |H|;
  ``isolation/output`` (c,) the outputs (absolute accelerations along the
  input's axis) whose |H| falls below 1 in the band and
  ``isolation/frequency`` (c,) [Hz] where (|H| = 1, located between grid
  points; |H| < 1 above);
- root attributes ``input`` (what drives it), ``solve_time`` [s CPU],
  ``evaluations``; ``scene/toml``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from flexbed.files.store import Dataset, write_file

__all__ = ["write_modal", "write_frf", "modal_contents", "frf_contents", "write_modal_contents",
           "write_frf_contents", "MODAL_SCHEMA", "FRF_SCHEMA"]

MODAL_SCHEMA = "flexbed.modal"
FRF_SCHEMA = "flexbed.frf"
VERSION = "1.0"


def write_modal(path, sf, mt) -> Path:
    """Write a :class:`flexbed.analyses.modal.Mounted` as ``flexbed.modal``."""
    return write_modal_contents(path, *modal_contents(sf, mt))


def write_modal_contents(path, datasets: dict, attrs: dict) -> Path:
    """Write what :func:`modal_contents` gave as a ``flexbed.modal`` file, atomically."""
    return write_file(path, schema=MODAL_SCHEMA, version=VERSION, datasets=datasets, attrs=attrs)


def modal_contents(sf, mt) -> tuple[dict, dict]:
    """The datasets and group attributes of :func:`write_modal`'s file, in
    memory (``{path: Dataset}``, ``{group: attrs}``): what a study's worker
    hands back for ``--keep-results``."""
    ms, md = mt.ms, mt.modes
    ds = {
        "coordinates/labels": Dataset(np.array(ms.labels), "", "the coordinates of q"),
        "matrices/mass": Dataset(ms.M, "SI", "mass matrix M at rest"),
        "matrices/stiffness": Dataset(ms.K, "SI", "stiffness matrix K = -M dv/dq"),
        "matrices/damping": Dataset(ms.C, "SI", "damping matrix C = -M dv/dv"),
        "modes/frequency": Dataset(md.frequency, "Hz", "natural frequency"),
        "modes/damped_frequency": Dataset(md.damped_frequency, "Hz", "damped frequency"),
        "modes/damping_ratio": Dataset(md.damping_ratio, "1", "damping ratio"),
        "modes/shape_real": Dataset(md.shapes.real, "SI", "mode shapes, real part"),
        "modes/shape_imag": Dataset(md.shapes.imag, "SI", "mode shapes, imaginary part"),
        "modes/overdamped_rates": Dataset(md.overdamped_rates, "1/s",
                                          "decay rates of the real roots (overdamped motions)"),
        "energy/kinetic": Dataset(md.energy, "1", "kinetic energy share per coordinate"),
        "energy/strain_mounts": Dataset(md.strain_mounts, "1",
                                        "strain energy share per mount axis"),
        "energy/strain_elastic": Dataset(md.strain_elastic, "1",
                                         "strain energy share of the bed's deformation"),
        "effective_mass/undamped_frequency": Dataset(md.undamped_frequency, "Hz",
                                                     "undamped natural frequency"),
        "effective_mass/mass": Dataset(md.effective_mass, "kg",
                                       "modal effective mass for base translation X, Y, Z"),
        "effective_mass/cumulative": Dataset(md.cumulative_mass_fraction, "1",
                                             "cumulative effective mass / moving mass"),
        "mounts/names": Dataset(np.array([m.name for m in mt.system.scene.mounts] or [""])
                                [:len(mt.system.scene.mounts)], "", "mount names"),
        "equilibrium/y": Dataset(mt.y_eq, "SI", "the equilibrium state"),
        "scene/toml": Dataset(sf.text, "", "the scene file this came from"),
    }
    attrs = {"": {"moving_mass": float(md.moving_mass), "solve_time": float(mt.solve_time),
                  "equilibrium_source": mt.source, "scene_digest": sf.digest}}
    return ds, attrs


def write_frf(path, sf, r) -> Path:
    """Write a :class:`flexbed.analyses.frf.FRF` as ``flexbed.frf``."""
    return write_frf_contents(path, *frf_contents(sf, r))


def write_frf_contents(path, datasets: dict, attrs: dict) -> Path:
    """Write what :func:`frf_contents` gave as a ``flexbed.frf`` file, atomically."""
    return write_file(path, schema=FRF_SCHEMA, version=VERSION, datasets=datasets, attrs=attrs)


def frf_contents(sf, r) -> tuple[dict, dict]:
    """The datasets and group attributes of :func:`write_frf`'s file, in memory."""
    ds = {
        "frequency": Dataset(r.frequency, "Hz", "frequencies"),
        "outputs/names": Dataset(np.array(r.names), "", "output names"),
        "outputs/units": Dataset(np.array(r.units), "", "units of each output's H"),
        "response/real": Dataset(r.H.real, "see outputs/units", "Re H"),
        "response/imag": Dataset(r.H.imag, "see outputs/units", "Im H"),
        "response/magnitude": Dataset(r.magnitude, "see outputs/units", "|H|"),
        "response/phase_deg": Dataset(r.phase_deg, "deg", "phase of H"),
        "resonances/frequency": Dataset(r.resonances, "Hz", "natural frequencies in the band"),
        "resonances/damping_ratio": Dataset(r.damping_ratio, "1", "their damping ratios"),
        "peaks": Dataset(r.peaks, "1, Hz, see outputs/units",
                         "output index, peak frequency, peak |H|"),
        "scene/toml": Dataset(sf.text, "", "the scene file this came from"),
    }
    if r.isolation_from is not None:
        found = np.flatnonzero(np.isfinite(r.isolation_from))
        ds["isolation/output"] = Dataset(found, "1", "the outputs with an isolation crossing")
        ds["isolation/frequency"] = Dataset(r.isolation_from[found], "Hz",
                                            "their isolation crossing, |H| = 1 (|H| < 1 above)")
    attrs = {"": {"input": r.input, "solve_time": float(r.solve_time),
                  "evaluations": int(r.evaluations), "scene_digest": sf.digest}}
    return ds, attrs

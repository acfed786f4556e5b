"""The response-spectrum analysis of a scene: from its mounted system's modes
(base held, :mod:`flexbed.analyses.modal`) and a design spectrum per axis
(:mod:`flexbed.files.spectrum`), each mode's peak contribution to the mount
deflections and forces (along each mount's axes), the points' absolute
accelerations and displacements relative to the base, and the mounts'
force on the base; combined by NRL, SRSS, CQC and ABS
(:mod:`flexbed.dynamics.frequency.response_spectrum`); tables and CSV text.

Every mode is given the spectrum's damping (DDAM practice: the spectrum is
the damping's; a damping other than the spectrum's is refused). Mount
forces are the springs' (k_t times the deflection): at a modal peak the
rate is zero. Modes above ``max_frequency`` are left out; the share of
the moving mass the kept modes carry is reported per axis.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from flexbed.analyses.linear_points import PointJacobians
from flexbed.analyses.modal import Mounted
from flexbed.analyses.points import Point
from flexbed.dynamics.frequency.response_spectrum import (RULES, ModalPeaks, combine,
                                                          modal_peaks, participation)
from flexbed.dynamics.pulses import STANDARD_GRAVITY
from flexbed.errors import InputError, NumericalError
from flexbed.files.spectrum import SpectrumFile, check_damping

__all__ = ["AxisResponse", "ResponseSpectrum", "response_spectrum", "default_points",
           "rsa_csv", "rsa_text", "modal_text"]

_AXES = "xyz"


@dataclass(frozen=True)
class AxisResponse:
    """The response to one axis's spectrum (m modes kept, k outputs).

    axis : 0|1|2; peaks : ModalPeaks (of the kept modes); names, units : (k,);
    modal : (m, k) each mode's signed peak contribution [units];
    combined : {rule: (k,) combined peak [units]} for every rule of RULES;
    mass_included : share of the moving mass the kept modes carry [1].
    """

    axis: int
    peaks: ModalPeaks
    names: tuple
    units: tuple
    modal: np.ndarray
    combined: dict
    mass_included: float

    def column(self, name: str) -> int:
        try:
            return self.names.index(name)
        except ValueError:
            raise InputError(f"no output {name!r} (outputs: {', '.join(self.names)})") from None


@dataclass(frozen=True)
class ResponseSpectrum:
    """A response-spectrum analysis: ``axes`` {axis: AxisResponse}; the
    spectrum file; ``damping`` [1]; ``frequency`` (m,) of the modes kept
    [Hz]; ``max_frequency`` [Hz] or None; ``solve_time`` [s CPU] of the
    analysis (the modes not included)."""

    spectrum: SpectrumFile
    damping: float
    axes: dict
    frequency: np.ndarray
    max_frequency: float | None
    solve_time: float


def default_points(sf, mt: Mounted) -> list[Point]:
    """The scene's [[point]] tables, else every body's centre of mass (2…)."""
    if sf.points:
        return [Point(p.name, p.body, np.asarray(p.position, dtype=float)) for p in sf.points]
    return [Point(f"{b.name} CM", b.name, np.zeros(3)) for b in mt.system.scene.bodies[1:]]


def _real_shapes(mt: Mounted) -> np.ndarray:
    phi = mt.modes.undamped_shapes
    if np.iscomplexobj(phi):
        if np.abs(phi.imag).max() > 1e-9 * np.abs(phi).max():
            raise NumericalError(f"{mt.system.scene.name}: the undamped modes are complex (an "
                                 f"unsymmetric stiffness with complex eigenvalues): no "
                                 f"response-spectrum analysis")
        phi = phi.real
    return phi


def response_spectrum(sf, mt: Mounted, spectrum: SpectrumFile, *, damping: float | None = None,
                      points: list[Point] | None = None,
                      max_frequency: float | None = None) -> ResponseSpectrum:
    """The response-spectrum analysis of a mounted scene (module docstring).

    Parameters
    ----------
    sf : SceneFile; mt : Mounted (its modes, base held)
    spectrum : the design spectra, one per axis given
    damping : ζ asked [1]; must be the spectrum's (default: it)
    points : points of interest (default :func:`default_points`)
    max_frequency : modes above it [Hz] left out (default: none)
    """
    zeta = check_damping(spectrum, damping)
    pts = default_points(sf, mt) if points is None else points
    t0 = time.process_time()
    ms, md = mt.ms, mt.modes
    phi = _real_shapes(mt)
    f = md.undamped_frequency
    gamma = participation(phi, ms.iota)                                     # (n, 3)
    keep = np.ones(f.size, dtype=bool) if max_frequency is None else f <= max_frequency
    if not keep.any():
        raise InputError(f"max_frequency = {max_frequency!r} Hz: no mode below it (the lowest "
                         f"is {f[0]:.4g} Hz)")
    pj = PointJacobians(sf, mt.system, ms, mt.bed_modes)
    mounts = [m.name for m in mt.system.scene.mounts]
    disp_rows = [ms.D, ms.Fq]
    names = [f"{m} d{k + 1}" for m in mounts for k in range(3)]
    names += [f"{m} f{k + 1}" for m in mounts for k in range(3)]
    units = ["m"] * (3 * len(mounts)) + ["N"] * (3 * len(mounts))
    J = [pj.jacobian(p)[:, 3:] for p in pts]
    disp_rows += J + [ms.Bq]
    names += [f"{p.name} u{c}" for p in pts for c in _AXES] + [f"base F{c.upper()}" for c in _AXES]
    units += ["m"] * (3 * len(pts)) + ["N"] * 3
    acc_names = [f"{p.name} a{c}" for p in pts for c in _AXES]
    O_disp = np.vstack(disp_rows)
    O_acc = np.vstack(J) if J else np.zeros((0, ms.n))
    axes = {}
    for d, spec in spectrum.axes.items():
        fk = f[keep]
        pk = modal_peaks(phi[keep], fk, ms.M, ms.iota[:, d], gamma[keep, d], spec(fk))
        modal = np.hstack([pk.displacement @ O_disp.T, pk.acceleration @ O_acc.T])
        combined = {rule: combine(modal, fk, zeta, rule) for rule in RULES}
        axes[d] = AxisResponse(d, pk, tuple(names + acc_names),
                               tuple(units + ["m/s^2"] * len(acc_names)), modal, combined,
                               float(pk.effective_mass.sum() / md.moving_mass))
    cpu = time.process_time() - t0
    return ResponseSpectrum(spectrum, zeta, axes, f[keep], max_frequency, cpu)


# ------------------------------------------------------------------ tables
def _in_field_units(value: float, unit: str) -> str:
    if unit == "m/s^2":
        return f"{value / STANDARD_GRAVITY:.3f} g"
    if unit == "m":
        return f"{1e3 * value:.3f} mm"
    return f"{value:.1f} N"


def modal_text(r: ResponseSpectrum) -> str:
    """Per axis and mode: frequency, participation, effective mass, the
    spectrum's value (Markdown)."""
    lines = []
    for d, a in r.axes.items():
        p = a.peaks
        lines += [f"\nbase {_AXES[d].upper()}: modes kept carry {100 * a.mass_included:.2f} % of "
                  f"the moving mass",
                  "| mode | f [Hz] | Γ [kg^1/2] | m_eff [kg] | S_a [g] | S_d [mm] |",
                  "|---|---|---|---|---|---|"]
        w2 = (2 * np.pi * p.frequency) ** 2
        for k in range(p.frequency.size):
            gamma = round(float(p.participation[k]), 9) + 0.0
            lines.append(f"| {k + 1} | {p.frequency[k]:.3f} | {gamma:.4g} | "
                         f"{round(p.effective_mass[k], 3) + 0.0:.3f} | "
                         f"{p.spectral[k] / STANDARD_GRAVITY:.3f} | "
                         f"{1e3 * p.spectral[k] / w2[k]:.3f} |")
    return "\n".join(lines).lstrip("\n")


def rsa_text(r: ResponseSpectrum, select=None) -> str:
    """The combined peaks per axis (rows: outputs; columns: the rules), in
    the field's units (mm, N, g), as Markdown; ``select`` (name → bool)
    keeps some outputs."""
    lines = []
    for d, a in r.axes.items():
        lines += [f"\nbase {_AXES[d].upper()} (damping {r.damping:g}):",
                  "| output | " + " | ".join(rule.upper() for rule in RULES) + " |",
                  "|---|" + "---|" * len(RULES)]
        for j, (name, unit) in enumerate(zip(a.names, a.units)):
            if select is not None and not select(name):
                continue
            lines.append(f"| {name} | " + " | ".join(_in_field_units(a.combined[rule][j], unit)
                                                     for rule in RULES) + " |")
    return "\n".join(lines).lstrip("\n")


def rsa_csv(r: ResponseSpectrum) -> str:
    """axis, output, unit, then each rule's combined peak [SI] and, for
    accelerations, in g."""
    head = "axis,output,unit," + ",".join(RULES) + "," + ",".join(f"{x}_g" for x in RULES)
    lines = [head]
    for d, a in r.axes.items():
        for j, (name, unit) in enumerate(zip(a.names, a.units)):
            vals = [a.combined[rule][j] for rule in RULES]
            g = [v / STANDARD_GRAVITY for v in vals] if unit == "m/s^2" else [""] * len(vals)
            lines.append(f"{_AXES[d]},{name},{unit}," + ",".join(f"{v:.10g}" for v in vals) + ","
                         + ",".join(f"{v:.10g}" if v != "" else "" for v in g))
    return "\n".join(lines) + "\n"

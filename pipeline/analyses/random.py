"""Random vibration of a scene's mounted system under base acceleration PSDs
(:mod:`flexbed.files.psd`), by the frequency responses of
:mod:`flexbed.dynamics.frequency.frf` and the spectral sums of
:mod:`flexbed.dynamics.frequency.random`.

Outputs, in this order: each point's acceleration, velocity and
displacement along X, Y, Z (inertial; of a point relative to a body, in
that body's frame: the relative motion), every mount's deflections, then
forces along its three axes, the total force of the mounts on the base
(X, Y, Z). All in SI; accelerations also in g.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from flexbed.analyses.frf import MAX_GRID, default_points
from flexbed.analyses.linear_points import PointJacobians
from flexbed.analyses.elastomer import force_map
from flexbed.analyses.modal import Mounted
from flexbed.analyses.points import Point
from flexbed.files.psd import G0, BasePSD
from flexbed.dynamics.frequency import frf as dfrf
from flexbed.dynamics.frequency import random as drandom
from flexbed.errors import InputError

__all__ = ["RandomResponse", "random_response", "rms_csv", "psd_csv"]

_AXES = "xyz"


@dataclass(frozen=True)
class RandomResponse:
    """The stationary random response.

    frequency : (k,) [Hz]; input_psd : (k, 3) base acceleration auto-spectra
    [g²/Hz]; names, units : (o,) outputs and their SI units; psd : (k, o)
    [unit²/Hz]; rms : (o,) [unit]; rms_error : (o,) the RMS's integration
    error estimate [unit]; peak_factor : float; miles : Miles' estimates
    (:class:`flexbed.dynamics.frequency.random.Miles`, RMS [unit]);
    input_rms : (3,) [g]; resonances, damping_ratio : (m,) the modes in the
    band; solve_time : [s CPU]; source : the PSD's file.
    """

    frequency: np.ndarray
    input_psd: np.ndarray
    names: tuple
    units: tuple
    psd: np.ndarray
    rms: np.ndarray
    rms_error: np.ndarray
    peak_factor: float
    miles: drandom.Miles
    input_rms: np.ndarray
    resonances: np.ndarray
    damping_ratio: np.ndarray
    solve_time: float
    source: str

    @property
    def acceleration(self) -> np.ndarray:
        """(o,) bool: the acceleration outputs (reported in g too)."""
        return np.array([u == "m/s^2" for u in self.units])

    @property
    def three_sigma(self) -> np.ndarray:
        return 3.0 * self.rms

    @property
    def peak(self) -> np.ndarray:
        return self.peak_factor * self.rms

    def column(self, name: str) -> int:
        if name not in self.names:
            raise InputError(f"output {name!r} is not one of this response's "
                             f"({', '.join(self.names)})")
        return self.names.index(name)


def random_outputs(sf, mt: Mounted, points) -> tuple[dfrf.Outputs, list, list]:
    """The outputs' matrices (displacement Jacobians of the points; the
    mounts' deflections and forces and the base force over relative
    motion), names and SI units."""
    ms = mt.ms
    pj = PointJacobians(sf, mt.system, ms, mt.bed_modes)
    rows, names, units = [], [], []
    for pt, rel in points:
        rows.append(pj.jacobian(pt, rel))
        label = pt.name if rel is None else f"{pt.name}@{rel}"
        for letter, unit in (("a", "m/s^2"), ("v", "m/s"), ("d", "m")):
            names += [f"{label} {letter}{c}" for c in _AXES]
            units += [unit] * 3
    mounts = [m.name for m in mt.system.scene.mounts]
    names += [f"{m} d{k + 1}" for m in mounts for k in range(3)]
    units += ["m"] * (3 * len(mounts))
    names += [f"{m} f{k + 1}" for m in mounts for k in range(3)]
    names += [f"base F{c.upper()}" for c in _AXES]
    units += ["N"] * (3 * len(mounts) + 3)
    forces = np.vstack([ms.D, ms.Fq, ms.Bq])
    rates = np.vstack([np.zeros_like(ms.D), ms.Fv, ms.Bv])
    positions = np.vstack(rows) if rows else np.zeros((0, 3 + ms.n))
    return (dfrf.Outputs(positions, forces, rates, order=0,
                         elastomer=force_map(ms, forces.shape[0], ms.D.shape[0])), names, units)


def transfer(ms, omega: np.ndarray, axes: list[int], out: dfrf.Outputs) -> np.ndarray:
    """H (k, 3, o) complex per unit base acceleration along each axis (zero
    for axes not in ``axes``): per point, acceleration, velocity and
    displacement (from the one displacement response: ``−ω²``, ``iω``
    times it), then the relative-motion outputs."""
    p = out.positions.shape[0] // 3
    o = 9 * p + out.forces.shape[0]
    H = np.zeros((omega.size, 3, o), dtype=complex)
    disp, rel = dfrf.base_responses(ms, omega, axes, out)              # (k, r, ·)
    disp = disp.reshape(omega.size, len(axes), p, 1, 3)
    w = omega[:, None, None, None, None]
    pts = np.concatenate([-(w * w) * disp, (1j * w) * disp, disp], axis=3)
    H[:, axes, :9 * p] = pts.reshape(omega.size, len(axes), 9 * p)
    H[:, axes, 9 * p:] = rel
    return H


def random_response(sf, mt: Mounted, psd: BasePSD, *,
                    points: list[tuple[Point, str | None]] | None = None, n: int = 2000,
                    peak_factor: float = 3.0, frequencies: np.ndarray | None = None
                    ) -> RandomResponse:
    """The random response of a mounted scene.

    Parameters
    ----------
    sf : SceneFile
    mt : Mounted
    psd : BasePSD
        Base acceleration PSDs [g²/Hz]; the band is its breakpoints'.
    points : list of (Point, relative_to or None), optional
        Default: the scene's [[point]] tables, else every body's centre of mass.
    n : int
        Log-spaced frequencies of the base grid (2 … :data:`MAX_GRID`); each
        damped mode in the band adds its own about its resonance (29 in its core, and
        tails out to 10 base steps), the PSD its breakpoints.
    peak_factor : float
        The peak reported besides 3σ is ``peak_factor`` σ (> 0).
    frequencies : array [Hz], optional
        Exactly this grid (increasing; no resonance points added).
    """
    if not 2 <= n <= MAX_GRID:
        raise InputError(f"n = {n:,} frequencies: from 2 to {MAX_GRID:,}")
    if not (np.isfinite(peak_factor) and peak_factor > 0.0):
        raise InputError(f"peak factor {peak_factor!r} must be finite and > 0")
    ms, md = mt.ms, mt.modes
    if points is None:
        points = default_points(sf, mt)
    out, names, units = random_outputs(sf, mt, points)
    t0 = time.process_time()
    lo, hi = psd.band
    if frequencies is None:
        f = drandom.random_grid(md, lo, hi, n, psd.breakpoints)
    else:
        f = np.asarray(frequencies, dtype=float)
        if f.size < 2 or not np.all(np.diff(f) > 0.0) or f[0] <= 0.0:
            raise InputError("frequencies: at least 2, increasing, > 0 [Hz]")
    H = transfer(ms, 2.0 * np.pi * f, psd.axes, out)
    S = psd.matrix(f)
    Sy = drandom.response_psd(H, S)
    ms2, err2 = drandom.mean_square(f, Sy)
    rms = np.sqrt(np.maximum(ms2, 0.0))
    # d(√I) = dI / (2√I)
    err = np.divide(err2, 2.0 * rms, out=np.sqrt(err2), where=rms > 0.0)
    mi = drandom.miles(f, Sy, ms2, md)
    cpu = time.process_time() - t0
    inband = (md.frequency >= f[0]) & (md.frequency <= f[-1])
    return RandomResponse(f, psd.level(f), tuple(names), tuple(units), Sy, rms, err,
                          float(peak_factor), mi, psd.rms_g(), md.frequency[inband],
                          md.damping_ratio[inband], cpu, psd.source)


def _fmt(v: float) -> str:
    return "" if not np.isfinite(v) else f"{v:.8g}"


def rms_csv(r: RandomResponse) -> str:
    """One row per output: name, unit, RMS, 3σ, peak (k σ) in SI, the same
    three in g for accelerations, the RMS's integration error, Miles' RMS
    where one mode dominates, that mode's frequency and its share of the
    mean square in its half-power band."""
    k = f"{r.peak_factor:g}"
    lines = [f"output,unit,rms,3sigma,peak_{k}sigma,rms_g,3sigma_g,peak_{k}sigma_g,"
             f"rms_integration_error,miles_rms,mode_Hz,half_power_share"]
    acc = r.acceleration
    for j, (name, unit) in enumerate(zip(r.names, r.units)):
        g = [r.rms[j] / G0, 3.0 * r.rms[j] / G0, r.peak[j] / G0] if acc[j] else [np.nan] * 3
        vals = [r.rms[j], r.three_sigma[j], r.peak[j], *g, r.rms_error[j], r.miles.rms[j],
                r.miles.frequency[j], r.miles.share[j]]
        lines.append(",".join([f'"{name}"' if "," in name else name, unit]
                              + [_fmt(v) for v in vals]))
    return "\n".join(lines) + "\n"


def psd_csv(r: RandomResponse) -> str:
    """frequency [Hz], the input's auto-spectra [g²/Hz], then each output's
    PSD (accelerations in g²/Hz, the others in SI units² per Hz)."""
    acc = r.acceleration
    cols = ["frequency_Hz"] + [f"input {c} [g^2/Hz]" for c in _AXES]
    cols += [f"{n} [{'g^2' if a else u + '^2'}/Hz]" for n, u, a in zip(r.names, r.units, acc)]
    data = np.hstack([r.frequency[:, None], r.input_psd,
                      np.where(acc[None, :], r.psd / G0**2, r.psd)])
    lines = [",".join(f'"{c}"' if "," in c else c for c in cols)]
    lines += [",".join(f"{v:.8g}" for v in row) for row in data]
    return "\n".join(lines) + "\n"

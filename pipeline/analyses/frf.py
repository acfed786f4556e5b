"""Transmissibility of a scene's mounted system: inputs, outputs and the
sweep (:mod:`flexbed.dynamics.frequency.frf`), named and tabulated.

Inputs: a unit base acceleration along X, Y or Z (``"base x"`` …), a
unit force along X, Y or Z at a point of a body (``Point`` + axis), or a
scene's load or unbalance per unit (``"load NAME"``:
:mod:`flexbed.analyses.frf_loads`).
Outputs, in this order: each point's acceleration along X, Y, Z
(inertial, or in a body's frame relative to it), the forces along every
mount's three axes, the total force of the mounts on the base (X, Y, Z).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from flexbed.analyses import frf_loads
from flexbed.analyses.linear_points import PointJacobians
from flexbed.analyses.elastomer import force_map
from flexbed.analyses.modal import Mounted
from flexbed.analyses.points import Point
from flexbed.files.table_reader import FREQUENCY_LIMITS
from flexbed.dynamics.frequency import frf as dfrf
from flexbed.errors import InputError

__all__ = ["FRF", "frequency_response", "parse_input", "frf_csv", "default_band", "MAX_GRID",
           "BAND_LIMITS", "QUANTITIES",
           "default_points"]

#: the most frequencies of a base grid (``n``) or of a given list: each is a
#: solve of the dynamic stiffness and a row of outputs, so 10^5 is minutes
#: of work and hundreds of MB on a large scene; beyond it a request is a slip
MAX_GRID = 100_000
#: [Hz] the band a response may be asked over (the files' rule, for PSD
#: tables too: :data:`flexbed.files.table_reader.FREQUENCY_LIMITS`)
BAND_LIMITS = FREQUENCY_LIMITS

_AXES = "xyz"


@dataclass(frozen=True)
class FRF:
    """Transmissibility over frequency.

    frequency : (k,) [Hz]; names : (o,) output names; units : (o,) units
    of H; H : (k, o) complex (response = Re(H e^{iωt}) for a unit input
    Re(e^{iωt})); input : str; resonances : (m,) natural frequencies in
    the band [Hz]; damping_ratio : (m,) theirs; peaks : (P, 3) (output
    index, frequency [Hz], |H|); isolation_columns : (o,) bool — the
    absolute accelerations along the base's excitation axis, where the
    isolation efficiency 1 − |T| means something; solve_time : float
    [s CPU] of the sweep; evaluations : int frequencies solved;
    isolation_from : (o,) [Hz] the isolation crossing of each isolation
    column (|T| < 1 above it, located between grid points to 1e-12
    relative), NaN elsewhere or where there is none in the band.
    """

    frequency: np.ndarray
    names: tuple
    units: tuple
    H: np.ndarray
    input: str
    resonances: np.ndarray
    damping_ratio: np.ndarray
    peaks: np.ndarray
    isolation_columns: np.ndarray
    solve_time: float
    evaluations: int
    isolation_from: np.ndarray | None = None

    @property
    def magnitude(self) -> np.ndarray:
        return np.abs(self.H)

    @property
    def phase_deg(self) -> np.ndarray:
        return np.degrees(np.angle(self.H))

    @property
    def isolation(self) -> np.ndarray:
        """(k, o) isolation efficiency 1 − |T| [1] where |T| < 1 in the
        isolation columns, NaN elsewhere."""
        out = dfrf.isolation(self.H)
        out[:, ~self.isolation_columns] = np.nan
        return out

    def column(self, name: str) -> int:
        if name not in self.names:
            raise InputError(f"output {name!r} is not one of this FRF's "
                             f"({', '.join(self.names)})")
        return self.names.index(name)


def parse_input(text: str) -> tuple[str, int]:
    """``"base x"``/``"base-x"`` … or ``"force x"`` → (kind, axis);
    ``"load NAME"`` → ("load", -1) (the load's axes are the scene's)."""
    if frf_loads.load_name(text) is not None:
        return "load", -1
    words = text.replace("-", " ").replace(":", " ").split()
    if len(words) != 2 or words[0] not in ("base", "force") or words[1].lower() not in _AXES:
        raise InputError(f"input {text!r}: expected 'base x|y|z', 'force x|y|z' or "
                         f"'load NAME'")
    return words[0], _AXES.index(words[1].lower())


def default_band(fn: np.ndarray) -> tuple[float, float]:
    """[Hz]: a quarter of the lowest natural frequency to twice the highest."""
    f = fn[np.isfinite(fn) & (fn > 0.0)]
    if not f.size:
        return 0.1, 100.0
    return 0.25 * float(f.min()), 2.0 * float(f.max())


#: point quantities of an FRF: name → (time derivative, column letter,
#: unit per unit base acceleration, unit per unit force)
QUANTITIES = {"acceleration": (2, "a", "1", "m/s^2/N"),
              "velocity": (1, "v", "s", "m/s/N"),
              "displacement": (0, "d", "s^2", "m/N")}


def default_points(sf, mt: Mounted) -> list[tuple[Point, str | None]]:
    """The scene's [[point]] tables (absolute, and relative where they say
    so), else the centre of mass of every body 2…."""
    points = []
    for p in sf.points:
        pt = Point(p.name, p.body, np.asarray(p.position, dtype=float))
        points.append((pt, None))
        if p.relative_to:
            points.append((pt, p.relative_to))
    if not points:
        body_names = [b.name for b in mt.system.scene.bodies]
        points = [(Point(f"{b} CM", b, np.zeros(3)), None) for b in body_names[1:]]
    return points


def frequency_response(sf, mt: Mounted, *, input: str = "base z", force_at: Point | None = None,
                       points: list[tuple[Point, str | None]] | None = None,
                       band: tuple[float, float] | None = None, n: int = 400,
                       frequencies: np.ndarray | None = None, quantity: str = "acceleration",
                       deflections: bool = False) -> FRF:
    """The FRF of a mounted scene.

    Parameters
    ----------
    sf : SceneFile
    mt : Mounted
    input : str
        "base x|y|z" (unit base acceleration [m/s²]) or "force x|y|z"
        (unit force [N] at ``force_at``) or "load NAME" (a [[load]] per
        unit [N or N m], an [[unbalance]] per newton of its rotating force:
        :mod:`flexbed.analyses.frf_loads`).
    points : list of (Point, relative_to or None), optional
        Default: the scene's [[point]] tables (absolute, and relative where
        they say so), else the centre of mass of every body 2….
    band : (f_min, f_max) [Hz], optional
        Default :func:`default_band`.
    n : int
        Log-spaced frequencies of the base grid (the resonances add theirs).
    frequencies : array [Hz], optional
        Use exactly these (no refinement).
    quantity : str
        The points' "acceleration" (default), "velocity" or "displacement"
        (of a point relative to a body: the relative displacement); the
        columns ``<point> a|v|d x|y|z``.
    deflections : bool
        Also every mount's deflection along its three axes [m per input],
        columns ``<mount> d1..d3``, after the base force.
    """
    kind, axis = parse_input(input)
    load = None
    if kind == "load":
        load = frf_loads.scene_load(sf, frf_loads.load_name(input), f"input {input!r}")
        kind, axis = "force", load.directions[0]
    if quantity not in QUANTITIES:
        raise InputError(f"quantity {quantity!r}: one of {', '.join(QUANTITIES)}")
    order, letter, unit_base, unit_force = QUANTITIES[quantity]
    ms, md = mt.ms, mt.modes
    pj = PointJacobians(sf, mt.system, ms, mt.bed_modes)
    if points is None:
        points = default_points(sf, mt)
    rows, names, units, iso = [], [], [], []
    acc_unit = unit_base if kind == "base" else unit_force
    for pt, rel in points:
        J = pj.jacobian(pt, rel)
        label = pt.name if rel is None else f"{pt.name}@{rel}"
        rows.append(J)
        names += [f"{label} {letter}{c}" for c in _AXES]
        units += [acc_unit] * 3
        iso += [kind == "base" and rel is None and c == axis and order == 2 for c in range(3)]
    forces, rates = dfrf.mount_outputs(ms)
    mount_names = [m.name for m in mt.system.scene.mounts]
    f_unit = "N/(m/s^2)" if kind == "base" else "1"
    names += [f"{m} f{k + 1}" for m in mount_names for k in range(3)]
    names += [f"base F{c.upper()}" for c in _AXES]
    units += [f_unit] * (3 * len(mount_names) + 3)
    iso += [False] * (3 * len(mount_names) + 3)
    if deflections:
        forces = np.vstack([forces, ms.D])
        rates = np.vstack([rates, np.zeros_like(ms.D)])
        names += [f"{m} d{k + 1}" for m in mount_names for k in range(3)]
        units += ["s^2" if kind == "base" else "m/N"] * (3 * len(mount_names))
        iso += [False] * (3 * len(mount_names))
    positions = np.vstack(rows) if rows else np.zeros((0, 3 + ms.n))
    if load is not None:
        units = [frf_loads.per_unit_load(u, load.per) for u in units]
    if kind == "base":
        inp = dfrf.Input("base", axis)
        label = f"unit base acceleration along {_AXES[axis].upper()} [m/s^2]"
    elif load is not None:
        inp = frf_loads.load_frf_input(ms, mt.system, load)
        label = load.label
    else:
        if force_at is None:
            raise InputError(f"input {input!r} needs the point the force acts at")
        J = pj.jacobian(force_at)
        inp = dfrf.Input("force", axis, J[axis, 3:].copy())
        label = (f"unit force along {_AXES[axis].upper()} [N] at {force_at.name} "
                 f"({force_at.body})")
    f_lo, f_hi = band if band is not None else default_band(md.frequency)
    if not (0.0 < f_lo < f_hi):
        raise InputError(f"band {f_lo!r}–{f_hi!r} Hz must satisfy 0 < f_min < f_max")
    check_request((f_lo, f_hi), n, frequencies)
    t0 = time.process_time()
    sw = dfrf.sweep(ms, md, inp, dfrf.Outputs(positions, forces, rates, order,
                                               force_map(ms, forces.shape[0], 0)), f_lo, f_hi, n,
                    frequencies=frequencies)
    H = np.hstack([sw.acceleration, sw.force])
    iso = np.array(iso, dtype=bool)
    crossing = np.full(len(names), np.nan)
    if iso.any():
        iso_pos = dfrf.Outputs(positions[np.flatnonzero(iso[:positions.shape[0]])],
                               np.zeros((0, ms.n)), np.zeros((0, ms.n)))

        def evaluate(f):
            return np.abs(dfrf.responses(ms, 2.0 * np.pi * f, inp, iso_pos)[0])

        crossing[iso] = dfrf.unit_crossings(evaluate, sw.frequency, np.abs(H[:, iso]),
                                            batched=ms.n > dfrf.DENSE_LIMIT)
    cpu = time.process_time() - t0
    inband = (md.frequency >= sw.frequency[0]) & (md.frequency <= sw.frequency[-1])
    return FRF(sw.frequency, tuple(names), tuple(units), H, label, md.frequency[inband],
               md.damping_ratio[inband], sw.peaks, iso, cpu, sw.evaluations, crossing)


def check_request(band: tuple[float, float], n: int, frequencies: np.ndarray | None) -> None:
    """Refuse, before any work, a request beyond :data:`MAX_GRID` or
    :data:`BAND_LIMITS` (InputError naming the limit)."""
    lo, hi = BAND_LIMITS
    if frequencies is not None:
        if frequencies.size > MAX_GRID:
            raise InputError(f"{frequencies.size:,} frequencies given; the limit is "
                             f"{MAX_GRID:,}")
        f = frequencies
        if not np.all((f >= lo) & (f <= hi)):
            bad = f[~((f >= lo) & (f <= hi))][0]
            raise InputError(f"frequency {bad:g} Hz is outside {lo:g} – {hi:g} Hz")
        return
    if not 2 <= n <= MAX_GRID:
        raise InputError(f"n = {n:,} frequencies: from 2 to {MAX_GRID:,}")
    if not (lo <= band[0] and band[1] <= hi):
        raise InputError(f"band {band[0]:g}–{band[1]:g} Hz: a response is computed within "
                         f"{lo:g} – {hi:g} Hz")


def frf_csv(r: FRF) -> str:
    """frequency [Hz], then per output |H| [its unit] and phase [deg], and
    the isolation efficiency [%] of the isolation columns."""
    cols = ["frequency_Hz"]
    blocks = [r.frequency[:, None]]
    iso = r.isolation
    for j, (name, unit) in enumerate(zip(r.names, r.units)):
        cols += [f"{name} |H| [{unit}]", f"{name} phase [deg]"]
        blocks += [r.magnitude[:, j:j + 1], r.phase_deg[:, j:j + 1]]
        if r.isolation_columns[j]:
            cols.append(f"{name} isolation [%]")
            blocks.append(100.0 * iso[:, j:j + 1])
    data = np.hstack(blocks)
    quoted = [f'"{c}"' if "," in c else c for c in cols]
    lines = [",".join(quoted)]
    for row in data:
        lines.append(",".join("" if not np.isfinite(v) else f"{v:.10g}" for v in row))
    return "\n".join(lines) + "\n"

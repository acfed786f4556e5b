"""The verdict of a run against the scene's limits (issue 23, part 4):
per mount, per piece of equipment, per point of interest and per
clearance, the figures a shock qualification reads, and PASS or FAIL with
the reasons.

Per mount and direction k, from the deflection Δx_k(t) (the results
file's sign: Δx < 0 is compression with body i below and u3 up) and the
static deflection Δx_s:

- compression = max(0, −min Δx), extension = max(0, max Δx) (total), and
  their dynamic parts from Δx − Δx_s, each with the time it peaks;
- stroke used = max(compression / stroke_compression,
  extension / stroke_extension) [1]; more than 1 fails;
- the static load |f_s| (resultant of the three directions' forces)
  against ``rated_load``; the peak of |f(t)| against ``max_force``.

Bottoming on a mount's bump stops (``bump_stop``) is reported (how many
contacts began, the first, the peak contact force), not failed on: the
stroke, force and fragility limits judge its consequences.

Per body after the base: the peak of |r̈| at its centre of mass (or the
fragility's ``point``), inertial, in g against its fragility. Per point
of interest: its peak absolute acceleration in g and, with
``relative_to``, its peak displacement relative to that body from t = 0.
Per clearance: :mod:`flexbed.analyses.clearance`. With the bed's
``allowable_stress``: the plate's peak von Mises stress and each
stiffener's peak |σ| over the output samples against it
(:mod:`flexbed.analyses.bed_stress`). Every extreme is located
between the output samples (:mod:`flexbed.analyses.extremes`); the limits
are :mod:`flexbed.files.limits`'.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from flexbed.analyses.clearance import ClearanceResult, clearance
from flexbed.analyses.extremes import extreme
from flexbed.analyses.points import Point, Run
from flexbed.errors import InputError
from flexbed.files.limits import STANDARD_GRAVITY, Fragility, Limits, MountLimits
from flexbed.files.store import Dataset

__all__ = ["MountVerdict", "BodyVerdict", "PointVerdict", "Verdict", "judge", "contact_events",
           "G"]

#: the g of the tables [m/s²]
G = STANDARD_GRAVITY


@dataclass(frozen=True)
class MountVerdict:
    """One mount over the run; arrays (3,) per mount direction [m, s].

    static_deflection (3,) [m], static_force (3,) [N], static_load [N]
    (resultant); compression, extension (3,) [m] total, with their times;
    dynamic_compression, dynamic_extension (3,) [m] (of Δx − Δx_s), with
    their times; stroke_used (3,) [1] (nan without a limit); peak_force [N]
    (resultant) at peak_force_time [s]; limits; reasons (empty: passed);
    bottoming on its bump stops: contacts (how many began), first_contact
    [s], peak_contact_force [N] (the largest |contact force| of a
    direction) at peak_contact_time [s] (nan, 0 without contact).
    """

    name: str
    static_deflection: np.ndarray
    static_force: np.ndarray
    static_load: float
    compression: np.ndarray
    compression_time: np.ndarray
    extension: np.ndarray
    extension_time: np.ndarray
    dynamic_compression: np.ndarray
    dynamic_compression_time: np.ndarray
    dynamic_extension: np.ndarray
    dynamic_extension_time: np.ndarray
    stroke_used: np.ndarray
    peak_force: float
    peak_force_time: float
    limits: MountLimits
    reasons: tuple
    contacts: int = 0
    first_contact: float = np.nan
    peak_contact_force: float = 0.0
    peak_contact_time: float = np.nan

    @property
    def passed(self) -> bool:
        return not self.reasons

    def usage(self) -> dict:
        """How much of each given limit the run used: ``{"stroke": (used,
        when), "load": (static load / rated, nan), "force": (peak / max,
        when)}`` [1, s], only the kinds the mount has a limit of."""
        out = {}
        if np.any(np.isfinite(self.stroke_used)):
            k = int(np.nanargmax(self.stroke_used))
            ratios = {}
            if self.limits.compression is not None:
                ratios[self.compression_time[k]] = self.compression[k] / self.limits.compression[k]
            if self.limits.extension is not None:
                ratios[self.extension_time[k]] = self.extension[k] / self.limits.extension[k]
            when = max(ratios, key=ratios.get)
            out["stroke"] = (float(self.stroke_used[k]), float(when))
        if self.limits.rated_load is not None:
            out["load"] = (self.static_load / self.limits.rated_load, float("nan"))
        if self.limits.max_force is not None:
            out["force"] = (self.peak_force / self.limits.max_force, self.peak_force_time)
        return out


@dataclass(frozen=True)
class BodyVerdict:
    """A body (bed or equipment): peak absolute acceleration [m/s²] at its
    centre of mass or its fragility's point, when [s], the fragility (or
    None) and the reasons."""

    name: str
    peak_acceleration: float
    time: float
    fragility: Fragility | None
    reasons: tuple

    @property
    def passed(self) -> bool:
        return not self.reasons


@dataclass(frozen=True)
class PointVerdict:
    """A point of interest: peak absolute acceleration [m/s²] and when;
    relative_to, peak displacement relative to it from t = 0 [m] and when
    (nan without relative_to)."""

    name: str
    body: str
    peak_acceleration: float
    time: float
    relative_to: str | None
    peak_relative_displacement: float
    relative_time: float


@dataclass(frozen=True)
class Verdict:
    """The whole verdict: mounts, bodies, points, clearances (ClearanceResult),
    the bed's stresses (StressVerdict per part; empty without an
    allowable stress)."""

    mounts: tuple
    bodies: tuple
    points: tuple
    clearances: tuple
    stresses: tuple = ()

    @property
    def reasons(self) -> tuple:
        """Every failure, one line each, naming what failed."""
        out = [f"mount {m.name!r}: {r}" for m in self.mounts for r in m.reasons]
        out += [f"body {b.name!r}: {r}" for b in self.bodies for r in b.reasons]
        out += [f"clearance {c.clearance.name!r}: {clearance_reason(c)}"
                for c in self.clearances if not c.passed]
        out += [f"bed {s.part}: {r}" for s in self.stresses for r in s.reasons]
        return tuple(out)

    @property
    def passed(self) -> bool:
        return not self.reasons


def clearance_reason(c: ClearanceResult) -> str:
    return (f"minimum {1e3 * c.minimum:.3f} mm below the {1e3 * c.clearance.minimum:g} mm "
            f"allowed at t = {c.time:.4f} s")


def _signed(t: np.ndarray, x: np.ndarray):
    """(compression, its time, extension, its time) of x (k,) [m, s]."""
    low, high = extreme(t, x, "min"), extreme(t, x, "max")
    return max(0.0, -low.value), low.time, max(0.0, high.value), high.time


def _bottoming(run: Run, m: int, limits: MountLimits, events: dict | None) -> dict:
    """Contacts of mount m's bump stops: how many began, the first, and the
    peak contact force from the samples (the contact decided by Δx)."""
    out = {}
    if not any(limits.stops):
        return out
    t = run.t
    dx, dxd = run.mounts["deflection"][:, m, :], run.mounts["rate"][:, m, :]
    peak, when = 0.0, np.nan
    began = []
    for k, stop in enumerate(limits.stops):
        if stop is None:
            continue
        fc = np.abs(stop.force(dx[:, k], dxd[:, k]))
        if np.any(fc > 0):
            top = extreme(t, fc, "max")
            if top.value > peak:
                peak, when = top.value, top.time
        if events is None:                 # from the samples: entries into contact
            touching = fc > 0
            began += t[1:][touching[1:] & ~touching[:-1]].tolist()
            if touching[0]:
                began.insert(0, float(t[0]))
    if events is not None:
        mine = (events["mount"] == m) & events["begins"]
        began = events["time"][mine].tolist()
    out.update(contacts=len(began), first_contact=min(began) if began else np.nan,
               peak_contact_force=peak, peak_contact_time=when)
    return out


def mount_verdict(run: Run, m: int, limits: MountLimits, dx_s: np.ndarray,
                  f_s: np.ndarray, events: dict | None = None) -> MountVerdict:
    """Mount ``m`` of ``run`` with its static deflection and force (3,)
    (``events``: the run's bump-stop contacts, as :func:`judge` takes them)."""
    t = run.t
    dx = run.mounts["deflection"][:, m, :]
    cols = {key: np.zeros(3) for key in ("c", "tc", "e", "te", "dc", "tdc", "de", "tde", "used")}
    reasons = []
    for k in range(3):
        cols["c"][k], cols["tc"][k], cols["e"][k], cols["te"][k] = _signed(t, dx[:, k])
        cols["dc"][k], cols["tdc"][k], cols["de"][k], cols["tde"][k] = _signed(
            t, dx[:, k] - dx_s[k])
        used = []
        for stroke, total, when, word in ((limits.compression, cols["c"][k], cols["tc"][k],
                                           "compression"),
                                          (limits.extension, cols["e"][k], cols["te"][k],
                                           "extension")):
            if stroke is None:
                continue
            used.append(total / stroke[k])
            if total > stroke[k]:
                reasons.append(f"stroke: direction {k + 1} {word} {1e3 * total:.3f} mm is "
                               f"{100 * total / stroke[k]:.0f} % of its {1e3 * stroke[k]:g} mm "
                               f"(t = {when:.4f} s)")
        cols["used"][k] = max(used) if used else np.nan
    load = float(np.linalg.norm(f_s))
    if limits.rated_load is not None and load > limits.rated_load:
        reasons.append(f"load: static {load:.6g} N above the rated {limits.rated_load:g} N")
    peak = extreme(t, np.linalg.norm(run.mounts["force"][:, m, :], axis=1), "max")
    if limits.max_force is not None and peak.value > limits.max_force:
        reasons.append(f"force: peak {peak.value:.6g} N above the maximum "
                       f"{limits.max_force:g} N (t = {peak.time:.4f} s)")
    return MountVerdict(run.mount_names[m], np.array(dx_s, dtype=float),
                        np.array(f_s, dtype=float), load, cols["c"], cols["tc"], cols["e"],
                        cols["te"], cols["dc"], cols["tdc"], cols["de"], cols["tde"],
                        cols["used"], peak.value, peak.time, limits, tuple(reasons),
                        **_bottoming(run, m, limits, events))


def body_verdict(run: Run, b: int, fragility: Fragility | None) -> BodyVerdict:
    """Body ``b``'s peak acceleration against its fragility."""
    name = run.names[b]
    if fragility is not None and fragility.point is not None:
        acc = run.absolute(Point(name, name, np.asarray(fragility.point))).acceleration
    else:
        acc = run.rdd[:, b]
    peak = extreme(run.t, np.linalg.norm(acc, axis=1), "max")
    reasons = ()
    if fragility is not None and peak.value > fragility.peak:
        reasons = (f"fragility: peak {peak.value / G:.4g} g above its {fragility.peak / G:.4g} g "
                   f"(t = {peak.time:.4f} s)",)
    return BodyVerdict(name, peak.value, peak.time, fragility, reasons)


def point_verdict(run: Run, pt: Point) -> PointVerdict:
    """A point of interest's peak acceleration and relative displacement."""
    acc = extreme(run.t, np.linalg.norm(run.absolute(pt).acceleration, axis=1), "max")
    rel, when = np.nan, np.nan
    if pt.relative_to:
        rho = run.relative(pt, pt.relative_to).position
        rel, when = extreme(run.t, np.linalg.norm(rho - rho[0], axis=1), "max")
    return PointVerdict(pt.name, pt.body, acc.value, acc.time, pt.relative_to, rel, when)


def contact_events(datasets) -> dict | None:
    """The bump-stop contacts of a run's datasets (a results file's
    ``contacts/`` group: a mapping of path to array or
    :class:`~flexbed.files.store.Dataset`) as ``time``, ``mount`` and
    ``begins`` arrays, or None where there is none."""
    if "contacts/time" not in datasets:
        return None

    def get(key):
        v = datasets[key]
        return np.asarray(v.data if isinstance(v, Dataset) else v)

    return {"time": get("contacts/time").astype(float), "mount": get("contacts/mount").astype(int),
            "begins": get("contacts/begins").astype(bool)}


def judge(run: Run, limits: Limits, static_deflection: np.ndarray,
          static_force: np.ndarray, events: dict | None = None) -> Verdict:
    """The verdict of a run.

    Parameters
    ----------
    run : Run
        The run (:class:`flexbed.analyses.points.Run`), complete.
    limits : Limits
        The scene's limits (``SceneFile.limits``).
    static_deflection, static_force : ndarray (M, 3)
        The mounts' deflections [m] and forces [N] at the static
        equilibrium.
    events : dict, optional
        The bump-stop contacts the integrator located
        (:func:`contact_events`); without them, counted from the samples.
    """
    mounts = tuple(mount_verdict(run, m, limits.mount(name), static_deflection[m],
                                 static_force[m], events)
                   for m, name in enumerate(run.mount_names))
    bodies = tuple(body_verdict(run, b, limits.body(run.names[b]))
                   for b in range(1, len(run.names)))
    points = tuple(point_verdict(run, pt) for pt in run.scene_points)
    clearances = tuple(clearance(run, c) for c in limits.clearances)
    return Verdict(mounts, bodies, points, clearances, _stresses(run, limits))


def _stresses(run: Run, limits: Limits) -> tuple:
    """The bed's StressVerdicts (empty without an allowable stress)."""
    lim = limits.allowable
    if lim is None or run.modes_data is None:
        return ()
    from flexbed.analyses.bed_stress import in_run_coordinates, stress_verdicts, superpose
    data = run.modes_data
    if data.stress is None:
        raise InputError(f"{data.path}: the modes file holds no stresses (schema older than "
                         f"1.4) and the scene gives allowable_stress; re-run 'flexbed modes "
                         f"--force'")
    s = superpose(in_run_coordinates(data.stress, data.n_modes, run.basis), run.a, run.t)
    return stress_verdicts(s, lim.plate, lim.stiffeners, data.origin)

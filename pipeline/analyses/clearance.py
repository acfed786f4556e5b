"""Clearances (sway space) over a finished run: the distance from a point
on one body to a point, a plane or a box on another body (or the base),
its minimum, when, and the margin against the minimum allowed.

With R(t) the point's motion (:meth:`flexbed.analyses.points.Run.absolute`)
and ρ(t) the same point in the other body's frame
(:meth:`~flexbed.analyses.points.Run.relative`; for the bed, its drawing
frame), the distance is

- to a point Q on the other body: |R − R_Q| (both absolute, so a point on
  the flexible bed moves with its modes);
- to a plane (P0, unit normal n): (ρ − P0)·n, signed, positive on the side
  n points to;
- to a box [lo, hi]: |ρ − clip(ρ, lo, hi)| outside, minus the depth
  min_k min(ρ_k − lo_k, hi_k − ρ_k) inside.

The minimum over the run is located between the output samples
(:func:`flexbed.analyses.extremes.extreme`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from flexbed.analyses.extremes import extreme
from flexbed.analyses.points import Point, Run
from flexbed.files.limits import Clearance

__all__ = ["ClearanceResult", "clearance", "distance"]


@dataclass(frozen=True)
class ClearanceResult:
    """One clearance over a run.

    clearance : Clearance; distance : ndarray (k,) [m] at the output
    times; minimum : float [m]; time : float [s] of the minimum; margin :
    float [m] = minimum − the minimum allowed (negative: violated).
    """

    clearance: Clearance
    distance: np.ndarray
    minimum: float
    time: float
    margin: float

    @property
    def passed(self) -> bool:
        return self.margin >= 0.0


def distance(run: Run, c: Clearance) -> np.ndarray:
    """The distance of clearance ``c`` at each output time of ``run`` (k,) [m]."""
    pt = Point(name=c.name, body=c.body, position=np.asarray(c.point, dtype=float))
    if c.kind == "point":
        other = Point(name=c.name, body=c.other, position=np.asarray(c.geometry[0], dtype=float))
        gap = run.absolute(pt).position - run.absolute(other).position
        return np.linalg.norm(gap, axis=1)
    rho = run.relative(pt, c.other).position
    if c.other == run.bed_body:
        rho = rho + run.bed_centre                      # bed frame -> drawing frame
    if c.kind == "plane":
        origin, normal = (np.asarray(v, dtype=float) for v in c.geometry)
        return (rho - origin) @ normal
    lo, hi = (np.asarray(v, dtype=float) for v in c.geometry)
    outside = np.linalg.norm(rho - np.clip(rho, lo, hi), axis=1)
    depth = np.minimum(rho - lo, hi - rho).min(axis=1)
    return np.where(depth > 0.0, -depth, outside)


def clearance(run: Run, c: Clearance) -> ClearanceResult:
    """Clearance ``c`` over ``run``: its distance, minimum, time and margin."""
    d = distance(run, c)
    low = extreme(run.t, d, "min")
    return ClearanceResult(c, d, low.value, low.time, low.value - c.minimum)

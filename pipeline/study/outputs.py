"""A point's run as its metrics read it, evaluated only as far as they ask.

``flexbed.simulate`` evaluates everything its results file holds at every
output sample (the bodies' motion, angles, mount forces and rates, the
energies: ~25 ms for the reference scene's 3,001 samples, more than its
solve). A study's metrics need a few of these: the peak of a point's
displacement needs the bodies' poses, a mount's peak force the mount
forces. :class:`PointRun` holds the solved motion and evaluates, on first
use, the right-hand side at the samples once (:meth:`System.rhs_batch`,
keeping only the bodies' accelerations and the mounts' deflections and
forces) and the motion of the bodies the asked points need; asked for
the mount forces and points' positions alone (peaks of mount forces and of
displacements), the right-hand side only as far as the mount forces
(:meth:`System.rhs_batch` ``mounts_only``) and the positions from the
states in compiled code (:func:`flexbed.dynamics.sample_passes.point_path`). The
numbers are those of the results file (the same compiled evaluations, the
same formulas in the same order: :func:`flexbed.dynamics.history.body_motion`
and :class:`flexbed.analyses.points.Run`'s kinematics).

Anything else (a point on the bed, whose drawing frame or mode shapes the
results file resolves; any other attribute of :class:`flexbed.Results`)
builds the whole :class:`flexbed.Results` once, as ``flexbed.simulate``
returns it, and answers from it; so does a kept results file.
"""

from __future__ import annotations

from functools import cached_property
from pathlib import Path
from typing import Sequence

import numpy as np

from flexbed.analyses.points import Frames, Point, PointMotion, Run
from flexbed.api.arguments import Arguments
from flexbed.api.results import Results
from flexbed.dynamics.bounded_cache import BoundedCache
from flexbed.dynamics.sample_passes import point_path
from flexbed.dynamics.history import MOTION_CAPTURED, body_motion

__all__ = ["PointRun"]

#: the kernel's work arrays a point's run keeps: the bodies' motion, and
#: the mounts' deflections and forces along their axes
_CAPTURED = MOTION_CAPTURED + ("w_dx", "w_f")
#: those the right-hand side gives as far as the mount forces
#: (:meth:`System.rhs_batch` ``mounts_only``): the base's motion, which the
#: bodies' poses need, and the mounts'
_MOUNTS = ("w_base", "w_dx", "w_f")


#: the points a run was asked for, checked (by body, position and name): a
#: study's metric asks each of its points' runs for the same one
_CHECKED_POINTS = BoundedCache(64)


def _checked_point(body: str, position: Sequence[float], name: str) -> Point:
    """The Point, checked as :meth:`flexbed.Results.point` checks it; its
    position read-only (a kept one is shared by the runs that ask)."""
    check = Arguments("Results.point")
    pt = Point(name=check.name(name, "name"), body=body,
               position=check.position(position, "position"))
    pt.position.flags.writeable = False
    return pt


class _Kinematics(Run):
    """:class:`Run`'s point kinematics over the bodies' motion in memory
    (rigid frames only: no point on the bed, whose frame the results file
    resolves). t (k,) [s]; names : list of str; motion : dict of
    :func:`body_motion`'s arrays (k, nb, 3|4)."""

    def __init__(self, t: np.ndarray, names: list, motion: dict):
        self.path = Path("results")
        self.t, self.names = t, names
        self.r, self.p = motion["position"], motion["euler_parameters"]
        self.rd, self.rdd = motion.get("velocity"), motion.get("acceleration")
        self.w, self.wd = motion.get("angular_velocity"), motion.get("angular_acceleration")
        self.A = Frames(self.p)                                           # [:, b] (k, 3, 3)
        self.bed_body = self.bed_name = self.shapes = None
        self.bed_centre = np.zeros(3)


class PointRun:
    """The ``simulate`` outcome of a study point.

    Parameters
    ----------
    scene : SceneFile
    system : System
        The compiled scene.
    sim : Simulation
        Its solved motion (:func:`flexbed.api.simulation.solved`).
    modes : ModesData or None
        The flexible bed's modes.

    ``t`` (k,) [s], ``mount_force`` (k, M, 3) [N] and ``mount_deflection``
    (k, M, 3) [m] along the mount axes, :meth:`point` as
    :meth:`flexbed.Results.point`; every other attribute (and dataset,
    ``run["energy/balance"]``) of :class:`flexbed.Results` through
    :meth:`results`.
    """

    def __init__(self, scene, system, sim, modes):
        self.scene, self.system, self.sim, self.modes = scene, system, sim, modes
        self._run = sim.motion.run

    complete = property(lambda self: bool(self._run.complete))
    message = property(lambda self: str(self._run.message))
    t = property(lambda self: self._run.t)

    def results(self) -> Results:
        """The whole :class:`flexbed.Results` (built once)."""
        return self._results

    @cached_property
    def _results(self) -> Results:
        from flexbed.api.simulation import results_of
        return results_of(self.scene, self.system, self.sim, self.modes)

    def __getattr__(self, name: str):
        if name.startswith("_"):
            raise AttributeError(name)
        return getattr(self._results, name)

    def __getitem__(self, name: str):
        return self._results[name]

    @property
    def _Y(self) -> np.ndarray:
        return np.ascontiguousarray(self._run.y, dtype=float).reshape(self.t.size, self.system.ny)

    @cached_property
    def _captured(self) -> dict:
        """The whole right-hand side at the samples: :data:`_CAPTURED`."""
        return self.system.rhs_batch(self.t, self._Y, _CAPTURED)[1]

    @cached_property
    def _mounts(self) -> dict:
        """:data:`_MOUNTS` at the samples: from :attr:`_captured` if it was
        evaluated, else from the right-hand side as far as the mount forces
        (the same numbers, bit for bit; the bodies' equations of motion,
        which only the accelerations need, not evaluated)."""
        if "_captured" in self.__dict__:
            return self._captured
        return self.system.rhs_batch(self.t, self._Y, _MOUNTS, mounts_only=True)[1]

    @property
    def mount_force(self) -> np.ndarray:
        return self._mounts["w_f"]

    @property
    def mount_deflection(self) -> np.ndarray:
        return self._mounts["w_dx"]

    @cached_property
    def _parts(self) -> dict:
        """The states by part (views, :meth:`Layout.split`)."""
        return self.system.layout.split(self._Y)

    @cached_property
    def _kinematics(self) -> _Kinematics:
        return _Kinematics(self.t, [b.name for b in self.system.scene.bodies],
                           body_motion(self.system, self._Y, self._captured))

    def _in_memory(self, body: str, relative_to: str | None) -> bool:
        """Whether a point on ``body`` (relative to ``relative_to``) is
        answered from the bodies' motion in memory: a rigid body's."""
        names = [b.name for b in self.system.scene.bodies]
        bed = self.scene.bed.body or (names[1] if len(names) > 1 else None)
        return not (body == bed or body not in names or (relative_to is not None
                                                         and relative_to not in names))

    def _point(self, body: str, position: Sequence[float], name: str) -> Point:
        try:          # by type and repr: 1, 1.0 and True apart, and -0.0 from 0.0
            key = (body, name, tuple((type(v), repr(v)) for v in position))
            hash(key)
        except TypeError:                        # refused below, as the API words it
            key = None
        if key is None:
            return _checked_point(body, position, name)
        return _CHECKED_POINTS.get(key, lambda: _checked_point(body, position, name))

    def point(self, body: str, position: Sequence[float], *, relative_to: str | None = None,
              name: str = "point") -> PointMotion:
        """As :meth:`flexbed.Results.point`."""
        if not self._in_memory(body, relative_to):
            return self._results.point(body, position, relative_to=relative_to, name=name)
        pt = self._point(body, position, name)
        run = self._kinematics
        return run.relative(pt, relative_to) if relative_to else run.absolute(pt)

    def point_position(self, body: str, position: Sequence[float], *,
                       relative_to: str | None = None, name: str = "point") -> np.ndarray:
        """``point(...).position`` (k, 3) [m], the same numbers, computed
        alone for a rigid body's point (its velocity and acceleration are
        not): from the states and the base's motion, without the bodies'
        accelerations (:func:`point_path`)."""
        if not self._in_memory(body, relative_to):
            return self.point(body, position, relative_to=relative_to, name=name).position
        u = np.asarray(self._point(body, position, name).position, dtype=float)
        r, p = self._pose(body)
        if relative_to is None:
            return point_path(r, p, u, r, p, False)
        return point_path(r, p, u, *self._pose(relative_to), True)

    def _pose(self, body: str) -> tuple[np.ndarray, np.ndarray]:
        """A body's origin (k, 3) [m] and Euler parameters (k, 4) as the
        states hold them (the base's from the right-hand side's base motion,
        as :func:`body_poses` takes it), for :func:`point_path`."""
        b = [x.name for x in self.system.scene.bodies].index(body)
        if b == 0:
            r = self._mounts["w_base"][:, 0]
            p = np.zeros((r.shape[0], 4))
            p[:, 0] = 1.0
        else:
            parts = self._parts
            r, p = parts["r"][:, b - 1], parts["p"][:, b - 1]         # views of the states
        return r, p

"""A point's run as its metrics read it, evaluated only as far as they ask.

``flexbed.simulate`` evaluates everything its results file holds at every
output sample (the bodies' motion, angles, mount forces and rates, the
energies: ~25 ms for the reference scene's 3,001 samples, more than its
solve). A study's metrics need a few of these: the peak of a point's
displacement needs the bodies' poses, a mount's peak force the mount
forces. :class:`PointRun` holds the solved motion and evaluates, on first
use, the right-hand side at the samples once (:meth:`System.rhs_batch`,
keeping only the bodies' accelerations and the mounts' deflections and
forces) and the motion of the bodies the asked points need. The numbers
are those of the results file (the same compiled evaluations, the same
formulas: :func:`flexbed.dynamics.history.body_motion` and
:class:`flexbed.analyses.points.Run`'s kinematics).

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

from flexbed.analyses.points import Point, PointMotion, Run
from flexbed.api.arguments import Arguments
from flexbed.api.results import Results
from flexbed.dynamics.history import MOTION_CAPTURED, body_motion
from flexbed.dynamics.rotation import A as rotation_matrix

__all__ = ["PointRun"]

#: the kernel's work arrays a point's run keeps: the bodies' motion, and
#: the mounts' deflections and forces along their axes
_CAPTURED = MOTION_CAPTURED + ("w_dx", "w_f")


class _Frames:
    """The rotation matrices (k, 3, 3) of the bodies' frames, each computed
    when first indexed (``frames[:, b]``, as :class:`Run` reads its ``A``):
    a metric's point needs one or two bodies' of nb."""

    def __init__(self, p: np.ndarray):
        self.p, self._done = p, {}

    def __getitem__(self, index: tuple) -> np.ndarray:
        whole, b = index
        assert whole == slice(None), index
        if b not in self._done:
            self._done[b] = rotation_matrix(self.p[:, b])
        return self._done[b]


class _Kinematics(Run):
    """:class:`Run`'s point kinematics over the bodies' motion in memory
    (rigid frames only: no point on the bed, whose frame the results file
    resolves). t (k,) [s]; names : list of str; motion : dict of
    :func:`body_motion`'s arrays (k, nb, 3|4)."""

    def __init__(self, t: np.ndarray, names: list, motion: dict):
        self.path = Path("results")
        self.t, self.names = t, names
        self.r, self.p = motion["position"], motion["euler_parameters"]
        self.rd, self.rdd = motion["velocity"], motion["acceleration"]
        self.w, self.wd = motion["angular_velocity"], motion["angular_acceleration"]
        self.A = _Frames(self.p)                                          # [:, b] (k, 3, 3)
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

    @cached_property
    def _captured(self) -> dict:
        Y = np.ascontiguousarray(self._run.y, dtype=float).reshape(self.t.size, self.system.ny)
        return self.system.rhs_batch(self.t, Y, _CAPTURED)[1]

    @property
    def mount_force(self) -> np.ndarray:
        return self._captured["w_f"]

    @property
    def mount_deflection(self) -> np.ndarray:
        return self._captured["w_dx"]

    @cached_property
    def _kinematics(self) -> _Kinematics:
        Y = np.ascontiguousarray(self._run.y, dtype=float).reshape(self.t.size, self.system.ny)
        return _Kinematics(self.t, [b.name for b in self.system.scene.bodies],
                           body_motion(self.system, Y, self._captured))

    def point(self, body: str, position: Sequence[float], *, relative_to: str | None = None,
              name: str = "point") -> PointMotion:
        """As :meth:`flexbed.Results.point`."""
        names = [b.name for b in self.system.scene.bodies]
        bed = self.scene.bed.body or (names[1] if len(names) > 1 else None)
        if body == bed or body not in names or (relative_to is not None
                                                and relative_to not in names):
            return self._results.point(body, position, relative_to=relative_to, name=name)
        check = Arguments("Results.point")
        pt = Point(name=check.name(name, "name"), body=body,
                   position=check.position(position, "position"))
        run = self._kinematics
        return run.relative(pt, relative_to) if relative_to else run.absolute(pt)

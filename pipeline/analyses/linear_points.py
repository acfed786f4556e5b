"""Points of interest in the linear mounted system: the Jacobian of a point's
position over [base translation (3), q (n)], computed by the very point
machinery of :mod:`flexbed.analyses.points` (rigid points, points on the
flexible bed moving with its modes, offsets off the mid-surface, motion
relative to a body in its frame) applied to states about the equilibrium.

A point's position is linear in translations and modal coordinates, so
their columns are differenced over ±1 mm (exact but for round-off); the
rotations' columns over ±1e-6 rad (central differences, O(1e-12))."""

from __future__ import annotations

import numpy as np

from flexbed.analyses.points import Point, Run
from flexbed.dynamics.frequency.mounted import MountedSystem
from flexbed.dynamics.system import System
from flexbed.files.modes import ModesData
from flexbed.files.scene import SceneFile
from flexbed.files.store import Dataset, in_memory

__all__ = ["PointJacobians", "point_jacobians"]

_H_LINEAR = 1e-3          # translations [m] and modal coordinates [kg^1/2 m]
_H_ROTATION = 1e-6        # rotations [rad]


class PointJacobians:
    """The perturbed states of one mounted system opened as a run, so that
    any point's Jacobian costs one pass of the point machinery.

    Parameters
    ----------
    sf : SceneFile
    system : System
    ms : MountedSystem
    modes : ModesData, optional
        A flexible bed's modes.
    """

    def __init__(self, sf: SceneFile, system: System, ms: MountedSystem,
                 modes: ModesData | None = None):
        n = ms.n
        h = np.where(_rotation_mask(ms.labels), _H_ROTATION, _H_LINEAR)
        cols = 3 + n
        k = 2 * cols
        # the 2 (3 + n) perturbed states at once, row 2c + side: the
        # equilibrium for the base's columns (c < 3, the base then moved
        # below), q = ±h e_(c−3) for the others (MountedSystem.state of each
        # row, in one pass; the same numbers row by row)
        Q = np.zeros((k, n))
        Q[2 * np.arange(3, cols), np.arange(n)] = h
        Q[2 * np.arange(3, cols) + 1, np.arange(n)] = -h
        Y = ms.states(Q)
        pos, eul = system.poses(Y)
        axes = np.arange(3)
        pos[2 * axes, 0, axes] += _H_LINEAR
        pos[2 * axes + 1, 0, axes] += -_H_LINEAR
        modal = Y[:, system.layout.q_modal]
        step = np.empty(cols)
        step[:3] = pos[2 * axes, 0, axes] - pos[2 * axes + 1, 0, axes]
        step[3:] = 2.0 * h
        # translations and modal coordinates: the step the state really took
        for c in range(3, cols):
            lab = ms.labels[c - 3]
            if lab.endswith((" x", " y", " z")):
                b, axis = int(ms.body[c - 3]), "xyz".index(lab[-1])
                step[c] = pos[2 * c, b, axis] - pos[2 * c + 1, b, axis]
        self.step = step
        zeros = np.zeros((k, system.nb, 3))
        ds = {
            "time": Dataset(np.arange(k, dtype=float), "s"),
            "bodies/names": Dataset(np.array([b.name for b in system.scene.bodies]), ""),
            "bodies/position": Dataset(pos, "m"),
            "bodies/euler_parameters": Dataset(eul, "1"),
            "bodies/velocity": Dataset(zeros, "m/s"),
            "bodies/acceleration": Dataset(zeros, "m/s^2"),
            "bodies/angular_velocity": Dataset(zeros, "rad/s"),
            "bodies/angular_acceleration": Dataset(zeros, "rad/s^2"),
            "modal/coordinates": Dataset(modal, "kg^1/2 m"),
            "modal/rates": Dataset(np.zeros_like(modal), "kg^1/2 m/s"),
            "modal/accelerations": Dataset(np.zeros_like(modal), "kg^1/2 m/s^2"),
            "scene/toml": Dataset(sf.text, ""),
        }
        flex = dict(system.scene.flexible)
        for fb in flex.values():
            if fb.basis is not None:
                ds["modal/basis"] = Dataset(fb.basis, "1")
        attrs = {"bed": {"model": "flexible" if flex else "rigid",
                         "plate_input_hash": sf.bed.plate.digest(),
                         "n_modes": int(sum(fb.n_modes for fb in flex.values()))}}
        self.run = Run(in_memory(ds, attrs), modes=modes if flex else None)
        self.n = n

    def position(self, point: Point) -> np.ndarray:
        """(3,) the point's inertial position at the equilibrium [m] (the
        first sample: the base moved, the bodies not)."""
        return self.run.absolute(point).position[0].copy()

    def jacobian(self, point: Point, relative_to: str | None = None) -> np.ndarray:
        """(3, 3 + n): the point's position [m] (inertial, or in the frame of
        ``relative_to``) per unit base translation and per unit q."""
        P = self.run.position(point, relative_to or None)
        return ((P[0::2] - P[1::2]) / self.step[:, None]).T


def _rotation_mask(labels) -> np.ndarray:
    return np.array([lab.endswith((" roll", " pitch", " yaw")) for lab in labels], dtype=bool)


def point_jacobians(sf: SceneFile, system: System, ms: MountedSystem,
                    modes: ModesData | None = None) -> PointJacobians:
    """See :class:`PointJacobians`."""
    return PointJacobians(sf, system, ms, modes)

"""The static equilibrium as a library call (the paper's Table 2).

>>> import flexbed
>>> eq = flexbed.statics(flexbed.load_scene())            # doctest: +SKIP
>>> eq.position[2], eq.orientation_deg[2]                 # doctest: +SKIP
>>> eq.save("lee1999-equilibrium.h5")                     # doctest: +SKIP
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from flexbed.api.arguments import Arguments
from flexbed.api.bed_modes import compiled
from flexbed.dynamics.rotation import angles_from_p
from flexbed.dynamics.statics import Equilibrium
from flexbed.dynamics.system import System
from flexbed.files.modes import ModesData
from flexbed.files.results import write_equilibrium
from flexbed.files.scene import SceneFile
from flexbed.stages.simulation import equilibrium
from flexbed.threads import limited

__all__ = ["Statics", "statics"]


@dataclasses.dataclass(frozen=True)
class Statics:
    """The static equilibrium of a scene (the paper's Table 2).

    Attributes
    ----------
    scene : SceneFile
    body_names : tuple of str
    position : ndarray (nb, 3)
        Centres of mass [m], inertial frame.
    euler_parameters : ndarray (nb, 4)
        Scalar first [1].
    orientation_deg : ndarray (nb, 3)
        Roll, pitch, yaw [deg] (X-Y-Z about body axes).
    equilibrium : Equilibrium
        Newton–Raphson's result: ``iterations``, ``residual``, ``y`` (the
        state at rest, layout :mod:`flexbed.dynamics.layout`), ….
    system : System
        The compiled scene it belongs to.
    """

    scene: SceneFile
    body_names: tuple
    position: np.ndarray
    euler_parameters: np.ndarray
    orientation_deg: np.ndarray
    equilibrium: Equilibrium
    system: System

    def save(self, path: str | Path) -> Path:
        """Write the equilibrium file (as ``flexbed static -o``)."""
        return write_equilibrium(Path(path), self.scene, self.system, self.equilibrium)


def _statics_of(scene: SceneFile, system: System, eq: Equilibrium) -> Statics:
    pos, p = system.poses(eq.y)
    return Statics(scene, tuple(b.name for b in system.scene.bodies), pos, p,
                   np.degrees(angles_from_p(p)), eq, system)


@limited()
def statics(scene: SceneFile, *, modes: ModesData | None = None, tol: float | None = None,
            sag: bool | None = None) -> Statics:
    """The static equilibrium, base held (Newton–Raphson).

    Parameters
    ----------
    scene : SceneFile
    modes : ModesData, optional
        A flexible bed's modes (default: computed in memory).
    tol : float, optional
        Tolerance (default the scene's ``static_tol``).
    sag : bool, optional
        Include the bed's elastic sag (default the scene's ``static_sag``).

    Raises NumericalError when no equilibrium is found.
    """
    check = Arguments("statics")
    scene, modes = check.scene(scene), check.modes(modes)
    tol = check.real(tol, "tol", positive=True)
    sag = check.flag(sag, "sag", optional=True)
    system = compiled(scene, modes)
    return _statics_of(scene, system, equilibrium(scene, system, tol=tol, sag=sag))

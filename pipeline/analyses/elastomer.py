"""A scene's elastomer mounts attached to its mounted system (the hook of
the frequency analyses: :mod:`flexbed.dynamics.frequency.elastomer`)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from flexbed.dynamics.frequency.elastomer import complex_stiffness
from flexbed.dynamics.frequency.elastomer_modes import elastomer_modes
from flexbed.dynamics.frequency.modal import Modes
from flexbed.dynamics.frequency.mounted import MountedSystem
from flexbed.dynamics.rotation import A as rotation_matrix
from flexbed.dynamics.system import System
from flexbed.errors import NumericalError

__all__ = ["with_elastomers", "force_map", "modes_of"]


def with_elastomers(ms: MountedSystem, system: System, elastomers: tuple) -> MountedSystem:
    """``ms`` with the complex stiffness of ``elastomers`` ((mount index,
    ElastomerTable) pairs, :attr:`flexbed.files.scene.SceneFile.elastomers`);
    ``ms`` itself when there are none. The frequency responses of a system
    with elastomers take the dense path (its sparse matrices are dropped:
    they hold the static stiffness only)."""
    if not elastomers:
        return ms
    _, p = system.poses(ms.y_eq)
    A = rotation_matrix(p[system.body_i])                             # (M, 3, 3)
    axes = np.einsum("mij,mkj->mki", A, system.U)                      # rows A_i u_k
    sign = (system.body_i == 0).astype(float) - (system.body_j == 0).astype(float)
    cs = complex_stiffness(dict(elastomers), ms.D, ms.Dv, axes, sign)
    return replace(ms, elastomer=cs, sparse=None)


def force_map(ms: MountedSystem, rows: int, first: int) -> np.ndarray | None:
    """The ``elastomer`` matrix of :class:`flexbed.dynamics.frequency.frf.Outputs`
    (rows, r) whose force rows hold the mount-axis forces and the base force
    (:func:`~flexbed.dynamics.frequency.frf.mount_outputs`) from row
    ``first`` on; None without elastomers."""
    if ms.elastomer is None:
        return None
    fm = ms.elastomer.force_map()
    out = np.zeros((rows, fm.shape[1]))
    out[first:first + fm.shape[0]] = fm
    return out


def modes_of(ms: MountedSystem, label: str) -> Modes:
    """The modes of ``ms``, each with its elastomers at its own frequency
    (:func:`~flexbed.dynamics.frequency.elastomer_modes.elastomer_modes`);
    NumericalError naming ``label`` (the scene file) when a mode's
    frequency does not settle."""
    try:
        return elastomer_modes(ms)
    except RuntimeError as exc:
        raise NumericalError(f"{label}: {exc}") from None

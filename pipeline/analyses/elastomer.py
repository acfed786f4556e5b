"""A scene's elastomer mounts attached to its mounted system (the hook of
the frequency analyses: :mod:`flexbed.dynamics.frequency.elastomer`)."""

from __future__ import annotations

from dataclasses import replace

from flexbed.dynamics.frequency.elastomer import complex_stiffness
from flexbed.dynamics.frequency.mounted import MountedSystem

__all__ = ["with_elastomers"]


def with_elastomers(ms: MountedSystem, elastomers: tuple) -> MountedSystem:
    """``ms`` with the complex stiffness of ``elastomers`` ((mount index,
    ElastomerTable) pairs, :attr:`flexbed.files.scene.SceneFile.elastomers`);
    ``ms`` itself when there are none. The frequency responses of a system
    with elastomers take the dense path (its sparse matrices are dropped:
    they hold the static stiffness only)."""
    cs = complex_stiffness(dict(elastomers), ms.D, ms.Dv)
    return ms if cs is None else replace(ms, elastomer=cs, sparse=None)

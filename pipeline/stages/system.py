"""A scene file compiled into the dynamics' system; a flexible bed reads its
modes file, checked against the scene's plate."""

from __future__ import annotations

from pathlib import Path

from flexbed.dynamics.errors import SceneError
from flexbed.dynamics.system import System
from flexbed.errors import InputError
from flexbed.files.modes import ModesData
from flexbed.files.scene import SceneFile
from flexbed.stages.flexible_bed import load_modes_for, with_flexible_bed
from flexbed.stages.modes import default_modes_path

__all__ = ["compile_scene"]


def compile_scene(sf: SceneFile, modes_file: str | Path | None = None, *,
                  modes: ModesData | None = None, **flex) -> System:
    """The compiled system of a scene file.

    A flexible bed takes its modes from ``modes`` (in memory) or else reads
    its modes file (``modes_file``, default where ``flexbed modes`` writes
    it); either is checked against the scene's plate. ``flex`` goes to
    :func:`flexbed.stages.flexible_bed.flexible_body`."""
    scene = sf.scene
    if sf.bed.flexible:
        data = modes if modes is not None else load_modes_for(
            sf, modes_file or default_modes_path(sf))
        scene = with_flexible_bed(sf, data, **flex)
    try:
        return System(scene)
    except SceneError as exc:
        raise InputError(f"{sf.source.name}: {exc}") from None

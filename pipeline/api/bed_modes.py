"""The bed's modes as a library call, computed once per plate in a process,
and the compiled scene the other calls share.

>>> import flexbed
>>> scene = flexbed.vary(flexbed.load_scene(), {"bed.model": "flexible"})
>>> data = flexbed.modes(scene)                           # doctest: +SKIP
>>> data = flexbed.modes(scene, file="bed-modes.h5")      # doctest: +SKIP
"""

from __future__ import annotations

from pathlib import Path

from flexbed.api.arguments import Arguments
from flexbed.dynamics.system import System
from flexbed.files.modes import ModesData, modes_data
from flexbed.files.scene import SceneFile
from flexbed.stages.modes import compute_modes, ensure_modes, require_bed
from flexbed.stages.system import compile_scene
from flexbed.threads import limited

__all__ = ["modes", "modes_request", "compiled"]

_MODES: dict[tuple, ModesData] = {}      # modes computed in memory, by plate and request


def _modes_in_memory(sf: SceneFile) -> ModesData:
    key = modes_request(sf)
    if key not in _MODES:
        if len(_MODES) >= 8:
            _MODES.pop(next(iter(_MODES)))
        _MODES[key] = modes_data(compute_modes(sf))
    return _MODES[key]


def modes_request(sf: SceneFile) -> tuple:
    """What a bed's modes depend on: (plate hash, modes, fmax, correction
    modes) — the key under which they are computed once and shared."""
    bed = sf.bed
    return (bed.plate.digest(), bed.modes, bed.fmax,
            bed.correction_modes if bed.static_correction else 0)


@limited()
def modes(scene: SceneFile, *, file: str | Path | None = None, force: bool = False) -> ModesData:
    """Free–free modes and modal invariants of the scene's bed.

    Parameters
    ----------
    scene : SceneFile
    file : path, optional
        Keep them in this modes file: reused when it was made from the same
        plate inputs and holds the modes asked for, else computed and
        written (as ``flexbed modes -o FILE``).
    force : bool
        With ``file``: recompute whatever it holds.

    Returns
    -------
    ModesData
        Frequencies [Hz], nodal shapes, invariants (``path`` is None when
        computed in memory).

    Raises
    ------
    InputError
        A scene with no ``[bed]`` table (as ``flexbed modes`` refuses it).
    """
    check = Arguments("modes")
    scene = check.scene(scene)
    file = check.path(file, "file")
    force = check.flag(force, "force")
    require_bed(scene)
    if file is not None:
        data, _ = ensure_modes(scene, file, force=force, log=lambda m: None)
        return data
    return _modes_in_memory(scene)


def compiled(scene: SceneFile, modes_given: ModesData | None, **flex) -> System:
    """The scene compiled for the dynamics; a flexible bed's modes computed
    in memory (:func:`modes`) when none are given."""
    if scene.bed.flexible and modes_given is None:
        modes_given = modes(scene)
    return compile_scene(scene, modes=modes_given, **flex)

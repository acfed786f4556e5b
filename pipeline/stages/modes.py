"""The bed-modes stage: the modes file of a scene's bed, reused when it was
made from the same plate inputs and holds the modes asked for, else computed."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING

from flexbed.errors import InputError
from flexbed.files.modes import ModesData, read_modes_file, write_modes_file
from flexbed.files.scene import SceneFile
from flexbed.interrupts import Interrupted, held, kept

if TYPE_CHECKING:
    from flexbed.fem.bed import BedModes

__all__ = ["default_modes_path", "require_bed", "ensure_modes", "compute_modes"]


def require_bed(sf: SceneFile) -> None:
    """Refuse a scene with no ``[bed]`` table (a base and bodies on mounts
    alone): it has no bed whose modes could be computed, only the default
    plate its reader fills in. (A ``[bed]`` with ``model = "rigid"`` has
    its plate: its modes are those a flexible bed would keep.)

    Raises
    ------
    InputError
        One line naming the scene file.
    """
    if not sf.has_bed:
        raise InputError(f"{sf.source.name}: no [bed] table: the scene has no bed to compute "
                         f"the modes of")


def default_modes_path(sf: SceneFile) -> Path:
    """Where a scene's modes file goes when no ``-o`` is given."""
    if sf.bed.modes_file:
        return sf.source.parent / sf.bed.modes_file
    return Path.cwd() / f"{sf.output_name}-modes.h5"


def ensure_modes(sf: SceneFile, path: Path, *, n_modes: int | None = None,
                 fmax: float | None = None, force: bool = False,
                 log=print) -> tuple[ModesData, bool]:
    """Return the modes file for the scene's bed, computing it if needed.

    Parameters
    ----------
    sf : SceneFile
    path : Path
        Modes file.
    n_modes, fmax : optional
        Request (default: the scene's ``[bed]`` modes / fmax).
    force : bool
        Recompute whatever the file holds.
    log : callable
        Receives one-line progress messages.

    Returns
    -------
    data : ModesData
    reused : bool
        True when the existing file was used.
    """
    if n_modes is None and fmax is None:
        n_modes, fmax = sf.bed.modes, sf.bed.fmax
    # the static correction draws on the modes above the kept ones
    extra = sf.bed.correction_modes if sf.bed.static_correction else 0
    spec = sf.bed.plate
    if path.exists() and not force:
        try:
            data = read_modes_file(path)
        except InputError as exc:
            log(f"modes: {exc}; recomputing")
        else:
            if data.input_hash != spec.digest():
                log(f"modes: {path} was made from other plate inputs; recomputing")
            elif not data.covers(n_modes, fmax) or data.n_modes < extra:
                log(f"modes: {path} holds {data.n_modes} modes, fewer than asked; recomputing")
            else:
                return data, True
    bed = compute_modes(sf, n_modes=n_modes, fmax=fmax)
    with held() as pending:       # modes computed are written whole, whatever the signal
        write_modes_file(path, bed)
    if pending:
        raise kept(Interrupted(pending[0]), f"after the modes were computed; they are in {path}")
    return read_modes_file(path), False


def compute_modes(sf: SceneFile, *, n_modes: int | None = None,
                  fmax: float | None = None) -> BedModes:
    """The scene's bed modes, computed (no file).

    Parameters
    ----------
    sf : SceneFile
    n_modes, fmax : optional
        Request (default: the scene's ``[bed]`` modes / fmax); the static
        correction's ``correction_modes`` are added when it is on.

    Returns
    -------
    BedModes
        With each mode's estimated discretisation error (``accuracy``:
        :mod:`flexbed.fem.accuracy` for a given mesh, the auto mesh's own).
    """
    from flexbed.fem.bed import compute_bed_modes   # scikit-fem, only to compute
    from flexbed.fem.modes import ModesError

    if n_modes is None and fmax is None:
        n_modes, fmax = sf.bed.modes, sf.bed.fmax
    extra = sf.bed.correction_modes if sf.bed.static_correction else 0
    spec = sf.bed.plate
    try:
        if sf.bed.auto and fmax is not None and n_modes is None:
            try:                       # modes = "auto" keeps at least one mode
                bed = compute_bed_modes(spec, fmax=fmax)
            except ModesError:
                bed = compute_bed_modes(spec, n_modes=1)
        elif n_modes is not None:
            bed = compute_bed_modes(spec, n_modes=max(n_modes, extra))
        else:
            bed = compute_bed_modes(spec, fmax=fmax)
        if bed.modes.omega.size < extra:
            bed = compute_bed_modes(spec, n_modes=extra)
    except ModesError as exc:
        text = str(exc)
        if extra and extra != n_modes and text.startswith(f"modes = {extra}:"):
            text = "correction_modes" + text[len("modes"):]     # the entry that asked for them
        raise InputError(f"{sf.source.name}: bed: {text}") from None
    if bed.accuracy is None:
        bed = replace(bed, accuracy=given_mesh_accuracy(bed))
    return bed


def given_mesh_accuracy(bed: BedModes):
    """The estimated error of modes on a given mesh (:func:`flexbed.fem.accuracy.estimate`),
    or None when it has no comparison mesh (a mesh file; a comparison mesh
    the geometry refuses); a Kirchhoff bed's with its theory error against
    the shell (:func:`flexbed.fem.theory_error.theory_error`)."""
    from flexbed.fem.accuracy import estimate
    from flexbed.fem.geometry import GeometryError
    from flexbed.fem.modes import ModesError
    from flexbed.fem.spec import PlateSpecError
    try:
        acc = estimate(bed)
        if acc is not None and bed.spec.theory == "kirchhoff":
            from flexbed.fem.theory_error import theory_error
            acc = replace(acc, theory_error=theory_error(bed, acc.error))
        return acc
    except (GeometryError, PlateSpecError, ModesError):
        return None

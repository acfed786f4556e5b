"""Points on the bed as the scene gives them (drawing frame) to the bed's
own frame (origin at its composite centre of mass): mount ends and points
of interest on the bed are checked to lie on it, then moved by −c."""

from __future__ import annotations

from dataclasses import replace
from typing import Callable

import numpy as np

from flexbed.files.bed_section import BedSection


def points_on_bed(bed: BedSection, name: str, mounts: list, points: list,
                  fail: Callable[[str, str], None]) -> tuple[list, list]:
    """Mounts and points of interest with the bed's points in the bed frame.

    Parameters
    ----------
    bed : BedSection
    name : str
        The bed body's name.
    mounts, points : list
        Mounts (:class:`flexbed.dynamics.scene.Mount`) and points of interest
        as read, bed points in the drawing frame [m].
    fail : callable
        ``fail(entry, message)`` raises the scene reader's one-line error.

    A point off the bed (outside its outline or in a cut-out) is refused for
    a flexible bed or one with geometry keys (a rigid plain rectangle takes
    any body-fixed point, as before).
    """
    from flexbed.fem.layout import off_bed
    if bed.flexible or bed.plate.geometry is not None:
        for m in mounts:
            for key in ("i", "j"):
                pt = getattr(m, f"point_{key}")
                if getattr(m, f"body_{key}") == name and off_bed(bed.plate, pt[None, :])[0]:
                    fail(f"mount {m.name!r}", f"point_{key} = {pt.tolist()} m is off the bed "
                                              f"(outside its outline or in a cut-out)")
        for p in points:
            if p.body == name and off_bed(bed.plate, np.array(p.position)[None, :])[0]:
                fail(f"point {p.name!r}", f"position = {list(p.position)} m is off the bed "
                                          f"(outside its outline or in a cut-out)")
    c = bed.mass_properties.centre
    if not np.any(c):
        return mounts, points
    mounts = [replace(m, point_i=m.point_i - c if m.body_i == name else m.point_i,
                      point_j=m.point_j - c if m.body_j == name else m.point_j)
              for m in mounts]
    points = [replace(p, position=tuple(np.array(p.position) - c)) if p.body == name else p
              for p in points]
    return mounts, points

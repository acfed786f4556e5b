"""The layout numbers a mount designer places and an optimiser aims at
(analysis ``modal``), checked against the scene before anything runs.

Kinds:

- ``decoupling`` [1]: for each rigid-body mode of the mounted system, the
  share of its kinetic energy in its dominant direction. A mode's energy
  table (:attr:`flexbed.Modal.energy`, one share per coordinate) is summed
  per direction — x, y, z, roll, pitch, yaw over the moving bodies
  (``by = "direction"``, default: a bed mode that the equipment follows
  is still a pure x mode), or taken per coordinate (``by =
  "coordinate"``: "equipment A x" and "bed x" apart); a flexible bed's
  elastic coordinates form one more group. The rigid-body modes are the
  modes whose dominant group is a direction, by increasing frequency, six
  per moving body (columns ``decoupling.mode1`` …); ``modes = [first,
  last]`` (1-based, inclusive) keeps some of them. 1 is a mode wholly in
  one direction (Ford's energy decoupling, generalised to several bodies).
  ``directions = ["y", "roll", …]`` instead: one column per direction
  (``decoupling.y`` …), the share of the rigid-body mode dominated by
  that direction (the largest, when several are; by direction only).
- ``highest_frequency`` [Hz]: the highest natural frequency of those
  rigid-body modes (or of ``modes = [first, last]``): the number a
  constraint holds below an excitation frequency / √2.
- ``rigid_frequencies`` [Hz]: the natural frequency of each of those
  modes, one column each (``rigid_frequency.mode1`` …): the same bound as
  a constraint per mode, which a gradient method follows better than the
  maximum (a maximum has a kink where two modes cross).

A rigid-body mode a point's scene lacks at run time (overdamped, or an
elastic mode of the bed dominating) fails that point.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from flexbed.errors import InputError, NumericalError
from flexbed.files.scene import SceneFile
from flexbed.files.table_reader import short_repr
from flexbed.study.metric_keys import OneColumn, _options
from flexbed.study.spec import MetricTable

__all__ = ["Decoupling", "HighestFrequency", "RigidFrequencies", "LAYOUT_KINDS", "direction_shares",
           "rigid_modes", "DIRECTIONS"]

#: the directions of a rigid body's coordinates, as the modal labels end
DIRECTIONS = ("x", "y", "z", "roll", "pitch", "yaw")
_BY = ("direction", "coordinate")


def direction_shares(energy: np.ndarray, labels: tuple, by: str = "direction") -> np.ndarray:
    """Kinetic-energy shares grouped.

    Parameters
    ----------
    energy : (m, n) — each mode's kinetic energy share per coordinate [1]
    labels : (n,) — the coordinates' labels ("equipment A roll", "bed mode 3")
    by : "direction" or "coordinate"

    Returns
    -------
    (m, g) shares [1]: per direction (six columns, then one for all the
    elastic coordinates) or, by coordinate, the rigid coordinates then the
    elastic group.
    """
    words = [lab.rsplit(" ", 1)[-1] for lab in labels]
    rigid = np.array([w in DIRECTIONS and " mode " not in lab for w, lab in zip(words, labels)])
    elastic = energy[:, ~rigid].sum(axis=1, keepdims=True)
    if by == "coordinate":
        return np.hstack([energy[:, rigid], elastic])
    groups = [energy[:, rigid & (np.array(words) == d)].sum(axis=1) for d in DIRECTIONS]
    return np.hstack([np.column_stack(groups), elastic])


def rigid_modes(modal, by: str = "direction") -> tuple[np.ndarray, np.ndarray]:
    """(indices, shares): the modes (0-based, by increasing frequency)
    whose dominant group is a rigid direction or coordinate, and the share
    of that group in each [1]."""
    shares = direction_shares(np.asarray(modal.energy), tuple(modal.labels), by)
    dominant = np.argmax(shares, axis=1)
    keep = np.flatnonzero(dominant < shares.shape[1] - 1)
    return keep, shares[keep, dominant[keep]]


def _range(scene: SceneFile, opts: dict, where: str) -> tuple[int, int]:
    n = 6 * (len(scene.scene.bodies) - 1)
    if n < 1:
        raise InputError(f"{where}: the scene has no moving body")
    span = opts.get("modes", [1, n])
    if (not isinstance(span, list) or len(span) != 2
            or not all(isinstance(k, int) and not isinstance(k, bool) for k in span)
            or not 1 <= span[0] <= span[1] <= n):
        raise InputError(f"{where}: modes = {short_repr(span)} must be [first, last] with "
                         f"1 <= first <= last <= {n} (six rigid-body modes per moving body)")
    return span[0], span[1]


def _by(opts: dict, where: str) -> str:
    by = opts.get("by", "direction")
    if by not in _BY:
        raise InputError(f"{where}: by = {short_repr(by)} must be one of {', '.join(_BY)}")
    return by


def _chosen(modal, first: int, last: int, by: str) -> tuple[np.ndarray, np.ndarray]:
    idx, shares = rigid_modes(modal, by)
    if idx.size < last:
        raise NumericalError(f"modal: {idx.size} rigid-body modes found, mode {last} asked "
                             f"(overdamped motions, or elastic modes of the bed dominating)")
    return idx[first - 1:last], shares[first - 1:last]


@dataclass(frozen=True)
class Decoupling:
    """Each rigid-body mode's kinetic-energy share in its dominant
    direction (see the module)."""

    kind: str
    first: int
    last: int
    by: str
    label: str | None
    directions: tuple = ()
    analysis = "modal"

    @classmethod
    def build(cls, table: MetricTable, scene: SceneFile, where: str) -> "Decoupling":
        opts = _options(table, ("modes", "by", "directions"), where)
        first, last = _range(scene, opts, where)
        dirs = opts.get("directions", [])
        if (not isinstance(dirs, list) or len(set(map(str, dirs))) != len(dirs)
                or not all(d in DIRECTIONS for d in dirs)):
            raise InputError(f"{where}: directions = {short_repr(dirs)} must be a list of "
                             f"distinct directions among {', '.join(DIRECTIONS)}")
        if dirs and ("modes" in opts or opts.get("by", "direction") != "direction"):
            raise InputError(f"{where}: directions picks the modes by their dominant direction: "
                             f"give it without modes and by")
        count = len(dirs) or last - first + 1
        if opts.get("name") and count != 1:
            raise InputError(f"{where}: name applies to one column (one mode or direction)")
        return cls(table.kind, first, last, _by(opts, where), opts.get("name"), tuple(dirs))

    @property
    def columns(self) -> tuple:
        if self.label:
            return (self.label,)
        if self.directions:
            return tuple(f"decoupling.{d}" for d in self.directions)
        tail = "" if self.by == "direction" else ".coordinate"
        return tuple(f"decoupling.mode{k}{tail}" for k in range(self.first, self.last + 1))

    @property
    def units(self) -> tuple:
        return ("1",) * len(self.columns)

    def values(self, outcomes: dict) -> tuple:
        if not self.directions:
            _, shares = _chosen(outcomes["modal"], self.first, self.last, self.by)
            return tuple(float(s) for s in shares)
        m = outcomes["modal"]
        groups = direction_shares(np.asarray(m.energy), tuple(m.labels))
        dominant = np.argmax(groups, axis=1)
        out = []
        for d in self.directions:
            j = DIRECTIONS.index(d)
            rows = np.flatnonzero(dominant == j)
            if not rows.size:
                raise NumericalError(f"modal: no mode is dominated by direction {d}")
            out.append(float(groups[rows, j].max()))
        return tuple(out)


@dataclass(frozen=True)
class HighestFrequency(OneColumn):
    """The highest natural frequency of the rigid-body modes [Hz]."""

    kind: str
    column: str
    first: int
    last: int
    analysis = "modal"
    unit = "Hz"

    @classmethod
    def build(cls, table: MetricTable, scene: SceneFile, where: str) -> "HighestFrequency":
        opts = _options(table, ("modes",), where)
        first, last = _range(scene, opts, where)
        return cls(table.kind, opts.get("name") or table.kind, first, last)

    def values(self, outcomes: dict) -> tuple:
        m = outcomes["modal"]
        idx, _ = _chosen(m, self.first, self.last, "direction")
        return (float(np.max(np.asarray(m.frequency)[idx])),)


@dataclass(frozen=True)
class RigidFrequencies:
    """The natural frequency of each rigid-body mode [Hz]."""

    kind: str
    first: int
    last: int
    analysis = "modal"

    @classmethod
    def build(cls, table: MetricTable, scene: SceneFile, where: str) -> "RigidFrequencies":
        opts = _options(table, ("modes",), where)
        if opts.get("name"):
            raise InputError(f"{where}: name does not apply (one column per mode)")
        first, last = _range(scene, opts, where)
        return cls(table.kind, first, last)

    @property
    def columns(self) -> tuple:
        return tuple(f"rigid_frequency.mode{k}" for k in range(self.first, self.last + 1))

    @property
    def units(self) -> tuple:
        return ("Hz",) * (self.last - self.first + 1)

    def values(self, outcomes: dict) -> tuple:
        m = outcomes["modal"]
        idx, _ = _chosen(m, self.first, self.last, "direction")
        return tuple(float(f) for f in np.asarray(m.frequency)[idx])


#: the kinds this module adds to :data:`flexbed.study.metrics.KINDS`
LAYOUT_KINDS = {"decoupling": Decoupling, "highest_frequency": HighestFrequency,
                "rigid_frequencies": RigidFrequencies}

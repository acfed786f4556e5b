"""The modes file: what the bed-modes stage hands to the dynamics stage.

Schema ``flexbed.modes``, version 1.4 (1.0 – 1.3 files still read;
1.2 adds triangles to ``mesh/cells``, 1.3 the group ``accuracy``, 1.4 the
group ``stress``: each mode's stresses, :mod:`flexbed.files.modes_stress`). Layout
(every dataset has ``units``):

=================================  ==============  =====================  =========
dataset                            shape           units                  from
=================================  ==============  =====================  =========
``plate/<input>`` (attributes)     –               as in the scene     inputs
``mesh/nodes``                     (N, 3)          m                      mesh
``mesh/cells``                     (ne, 4)         1                      mesh
``modes/frequency``                (n,)            Hz                     FE
``modes/omega``                    (n,)            rad/s                  FE
``modes/label``                    (n,)            –                      FE
``modes/symmetry``                 (n,)            –                      FE
``modes/translation``              (n, N, 3)       kg^-1/2                FE
``modes/rotation``                 (n, N, 3)       rad kg^-1/2 m^-1       FE
``modes/twist``                    (n, N)          kg^-1/2 m^-2           FE
``modes/rigid_omega``              (3,) or (6,)    rad/s                  FE
``invariants/mass``                ()              kg                     solid
``invariants/first_moment``        (3,)            kg m                   solid
``invariants/inertia``             (3, 3)          kg m^2                 solid
``invariants/phi_integral``        (3, n)          kg^1/2                 FE
``invariants/u_cross_phi``         (3, n)          kg^1/2 m               FE
``invariants/phi_cross_phi``       (n, 3, n)       1                      FE
``invariants/modal_mass``          (n, n)          1                      FE
``invariants/inertia_first_order`` (n, 3, 3)       kg^1/2 m               FE
``invariants/inertia_second_order`` (n, n, 3, 3)   1                      FE
``invariants/modal_stiffness``     (n, n)          s^-2                   FE
``accuracy/frequency_error``       (n,)            1                      FE
``accuracy/mac``                   (n,)            1                      FE
``accuracy/theory_error``          (n,)            1                      FE
=================================  ==============  =====================  =========

``accuracy`` (since 1.3; absent when not estimated, e.g. a mesh file): each
mode's estimated discretisation error f_h / f_converged − 1 (NaN: no
estimate) and the MAC of its match on the comparison mesh
(:mod:`flexbed.fem.accuracy`); its attributes ``method``, ``mesh``,
``comparison``, ``ratio``, ``rate``, ``element_size`` [m], ``tolerance``
(``element_size = "auto"``: the tolerance the mesh was chosen for, else
NaN) and ``history`` (the meshes ``auto`` tried); a Kirchhoff bed's also
``theory_error``, f_kirchhoff / f_shell − 1 of the converged frequencies
(:mod:`flexbed.fem.theory_error`).

The ``invariants/`` rows are :data:`INVARIANTS`: the one definition of
the modal invariants that :mod:`flexbed.fem` computes and
:mod:`flexbed.dynamics` takes (tests/test_modes_file.py checks both sides
against it).

Group ``mesh`` attribute ``origin_in_drawing_frame`` (2,) [m]: where the
bed frame's origin (the centre of mass) is in the frame the scene gives the
bed's geometry and points in (its z is minus the nodes' z).

Root attributes: ``schema``, ``schema_version``, ``creator``, ``created``,
``input_hash`` (SHA-256 of the plate inputs), ``n_modes``,
``next_frequency`` (Hz of the first elastic mode not stored: the file holds
every mode below it). Each invariant has a ``source`` attribute saying
where it comes from.

``plate/theory`` says which model made the file ("kirchhoff" when absent).
A Kirchhoff file's rotations are (∂w/∂y, −∂w/∂x, 0) and its twist completes
the bicubic Hermite data; a Mindlin shell's translations have all three
components, its rotations are (θx, θy, in-plane rotation ½(∂v/∂x − ∂u/∂y),
the last averaged from the elements at the node), its twist is zero, its
mesh cells are bilinear quadrilaterals and (since 1.2, from a mesh file of
triangles) linear triangles stored as (a, b, c, c) — the last two corners
the same node, :mod:`flexbed.fem.cells` — and its mass, first moment and
inertia come from the FE mass matrix ("from" = FE for every row).
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

import numpy as np

from flexbed.fem.accuracy import Accuracy
from flexbed.fem.invariants import Invariants
from flexbed.fem.spec import PlateSpec

from flexbed.errors import InputError
from flexbed.files.modes_stress import read_stress, stress_datasets
from flexbed.files.store import Dataset, read_file, write_file

if TYPE_CHECKING:       # annotation only: reading a modes file needs no FE code
    from flexbed.fem.bed import BedModes
    from flexbed.fem.modal_stress import ModalStress

SCHEMA = "flexbed.modes"
#: 1.1: plate/theory (absent: "kirchhoff"), Mindlin shells; 1.2: triangles in
#: mesh/cells as (a, b, c, c) (a file of quads is laid out as in 1.1)
#: 1.3: the group accuracy (absent: not estimated)
#: 1.4: the group stress (absent: None)
VERSION = "1.4"
MAJOR = 1
_LATER_KEYS = ("theory", "geometry", "masses", "stiffeners", "mesh_tolerance", "mesh_points")
_JSON_KEYS = ("geometry", "masses", "stiffeners", "mesh_points")
_ACCURACY_ATTRS = ("method", "mesh", "comparison", "ratio", "rate", "tolerance",
                   "element_size", "history")


def _origin(xy, nodes: np.ndarray) -> np.ndarray:
    """The bed frame's origin in the drawing frame (3,): x, y as recorded,
    z from the mid-surface's height (−z of the nodes)."""
    xy = np.asarray(xy, dtype=float).reshape(-1)[:2]
    z = -float(nodes[0, 2]) if len(nodes) else 0.0
    return np.array([xy[0], xy[1], z]) if xy.size == 2 else np.array([0.0, 0.0, z])


def _plate_attrs(spec: PlateSpec) -> dict:
    """The plate inputs as HDF5 attributes (the geometry as JSON text)."""
    d = spec.as_dict()
    for key in _JSON_KEYS:
        if key in d:
            d[key] = json.dumps(d[key], sort_keys=True)
    return d

@dataclass(frozen=True)
class Invariant:
    """One modal invariant: a field of :class:`flexbed.fem.invariants.Invariants`
    (what fem computes), of :class:`flexbed.dynamics.flexible.FlexibleBody`
    (what the dynamics takes) and the dataset ``invariants/<name>``.

    Attributes
    ----------
    name : str
    symbol : str
        Shabana's number ("I1" … "I9"; "K" the modal stiffness).
    shape : tuple of int or "n"
        "n": the number of modes.
    unit : str
    description : str
    """

    name: str
    symbol: str
    shape: tuple
    unit: str
    description: str

    def shape_for(self, n: int) -> tuple[int, ...]:
        """The shape with ``n`` modes."""
        return tuple(n if d == "n" else d for d in self.shape)


#: The modal invariants, in the file's order: the contract between flexbed.fem
#: and flexbed.dynamics (which never import each other), written once here;
#: the modes file's reader maps it onto the first, the flexible bed's stage
#: (:mod:`flexbed.stages.flexible_bed`) onto the second.
INVARIANTS = (
    Invariant("mass", "I1", (), "kg", "I1 = integral of rho dV"),
    Invariant("first_moment", "I2", (3,), "kg m", "I2 = integral of rho u0 dV"),
    Invariant("inertia", "I7", (3, 3), "kg m^2",
              "I7 = integral of rho u0~T u0~ dV (inertia tensor about the centre of mass)"),
    Invariant("phi_integral", "I3", (3, "n"), "kg^1/2", "I3 = integral of rho Phi dV, (3, n)"),
    Invariant("u_cross_phi", "I4", (3, "n"), "kg^1/2 m",
              "I4 = integral of rho u0~ Phi dV, (3, n)"),
    Invariant("phi_cross_phi", "I5", ("n", 3, "n"), "1",
              "I5[k, :, l] = integral of rho Phi_k~ Phi_l dV"),
    Invariant("modal_mass", "I6", ("n", "n"), "1",
              "I6 = integral of rho Phi^T Phi dV (generalized mass)"),
    Invariant("inertia_first_order", "I8", ("n", 3, 3), "kg^1/2 m",
              "I8[k] = integral of rho u0~T Phi_k~ dV"),
    Invariant("inertia_second_order", "I9", ("n", "n", 3, 3), "1",
              "I9[k, l] = integral of rho Phi_k~T Phi_l~ dV"),
    Invariant("modal_stiffness", "K", ("n", "n"), "s^-2", "Phi^T K Phi (generalized stiffness)"),
)
REQUIRED = ("mesh/nodes", "mesh/cells", "modes/frequency", "modes/omega", "modes/translation",
            "modes/rotation", "modes/twist") + tuple(f"invariants/{v.name}" for v in INVARIANTS)


@dataclass(frozen=True)
class ModesData:
    """A modes file read back: plain arrays, no FE objects.

    Attributes
    ----------
    path : Path or None
        The file it was read from (None: computed in memory).
    plate : PlateSpec
        The inputs the file was computed from.
    input_hash : str
    frequency, omega : ndarray (n,)
    labels, symmetry : tuple of str
    nodes : ndarray (N, 3)
    cells : ndarray (ne, 4)
    translation, rotation : ndarray (n, N, 3)
    twist : ndarray (n, N)
    rigid_omega : ndarray (3,)
    invariants : Invariants
    next_frequency : float
        The file holds every elastic mode below this frequency [Hz].
    created, creator : str
    origin : ndarray (3,)
        The bed frame's origin (the bed's centre of mass) in the drawing
        frame the scene's bed points are given in [m] (zero for the plain
        rectangle).
    accuracy : Accuracy or None
        Each mode's estimated discretisation error (None: not estimated,
        or a file older than 1.3).
    stress : ModalStress or None
        Each mode's stresses at the element centres (None: a file older
        than 1.4).
    """

    path: Path | None
    plate: PlateSpec
    input_hash: str
    frequency: np.ndarray
    omega: np.ndarray
    labels: tuple[str, ...]
    symmetry: tuple[str, ...]
    nodes: np.ndarray
    cells: np.ndarray
    translation: np.ndarray
    rotation: np.ndarray
    twist: np.ndarray
    rigid_omega: np.ndarray
    invariants: Invariants
    next_frequency: float
    created: str
    creator: str
    origin: np.ndarray = field(default_factory=lambda: np.zeros(3))
    accuracy: Accuracy | None = None
    stress: ModalStress | None = None

    @property
    def n_modes(self) -> int:
        """Number of elastic modes stored."""
        return int(self.frequency.size)

    def covers(self, n_modes: int | None = None, fmax: float | None = None) -> bool:
        """True when the file holds the modes asked for (a number, or all
        below ``fmax`` Hz)."""
        if n_modes is not None:
            return n_modes <= self.n_modes
        return fmax is not None and fmax <= self.next_frequency


def write_modes_file(path: str | Path, bed: BedModes) -> Path:
    """Write the modes file atomically.

    Parameters
    ----------
    path : path-like
    bed : BedModes
        Output of :func:`flexbed.fem.bed.compute_bed_modes`.
    """
    m = bed.modes
    mindlin = bed.spec.theory == "mindlin"
    d: dict[str, Dataset] = {
        "mesh/nodes": Dataset(bed.nodes, "m", "node coordinates in the bed frame (origin at "
                              "the centre of mass)"),
        "mesh/cells": Dataset(bed.cells.astype(np.int64), "1",
                              "node indices of each cell: quads, triangles as (a, b, c, c)"),
        "modes/frequency": Dataset(m.frequency, "Hz", "elastic free-free frequencies"),
        "modes/omega": Dataset(m.omega, "rad/s", "circular frequencies"),
        "modes/label": Dataset(np.array(m.labels, dtype=object), "",
                               "shape of each mode by its bending energy"),
        "modes/symmetry": Dataset(np.array(m.symmetry, dtype=object), "",
                                  "S/A under x -> -x, then y -> -y"),
        "modes/translation": Dataset(bed.translation, "kg^-1/2",
                                     "mass-normalised nodal translations (mode, node, xyz)"),
        "modes/rotation": Dataset(bed.rotation, "rad kg^-1/2 m^-1",
                                  "nodal rotations (theta_x, theta_y, in-plane rotation)"
                                  if mindlin else "nodal rotations (dw/dy, -dw/dx, 0)"),
        "modes/twist": Dataset(bed.twist, "kg^-1/2 m^-2",
                               "zero: the Mindlin shell's fields are bilinear" if mindlin else
                               "nodal d2w/dxdy (Hermite data for points between nodes)"),
        "modes/rigid_omega": Dataset(m.rigid_omega, "rad/s",
                                     "solver frequencies of the vectors identified as rigid"),
    }
    inv = bed.invariants
    for v in INVARIANTS:
        d[f"invariants/{v.name}"] = Dataset(np.asarray(getattr(inv, v.name), dtype=float), v.unit,
                                            v.description, attrs={"source": inv.source(v.name)})
    acc = bed.accuracy
    if acc is not None:
        d["accuracy/frequency_error"] = Dataset(
            np.asarray(acc.error, dtype=float), "1",
            "estimated discretisation error of each frequency, f_h / f_converged - 1 "
            "(NaN: no estimate)", missing=True)
        d["accuracy/mac"] = Dataset(np.asarray(acc.mac, dtype=float), "1",
                                    "MAC of each mode with its match on the comparison mesh")
        if acc.theory_error is not None:
            d["accuracy/theory_error"] = Dataset(
                np.asarray(acc.theory_error, dtype=float), "1",
                "Kirchhoff bed: converged frequency against the shear-deformable shell's, "
                "f_kirchhoff / f_shell - 1 (NaN: no matching shell mode)", missing=True)
    attrs: dict[str, Mapping[str, Any]] = {
        "": {"input_hash": bed.spec.digest(), "n_modes": int(m.omega.size),
             "next_frequency": (m.omega_next / (2 * math.pi)
                                if math.isfinite(m.omega_next) else math.inf),
             "description": "free-free modes and modal invariants of the common bed"},
        "plate": _plate_attrs(bed.spec),
        "mesh": {"origin_in_drawing_frame": np.asarray(bed.origin, dtype=float),
                 "origin_units": "m"},
        "invariants": ({"model": "every invariant, mass properties included, from the FE "
                                 "consistent mass of the Mindlin shell"}
                       if inv.model_mass else
                       {"solid": "mass, first_moment, inertia: exact solid plate geometry",
                        "fe": "all terms with Phi: FE mass forms with the kept modes"}),
    }
    if acc is not None:
        attrs["accuracy"] = {k: getattr(acc, k) for k in _ACCURACY_ATTRS}
        attrs["accuracy"]["element_size_units"] = "m"
    if getattr(bed, "stress", None) is not None:
        stress_d, stress_attrs = stress_datasets(bed.stress)
        d.update(stress_d)
        attrs.update(stress_attrs)
    return write_file(path, schema=SCHEMA, version=VERSION, datasets=d, attrs=attrs)


def modes_data(bed: BedModes, path: Path | None = None) -> ModesData:
    """The modes of :func:`flexbed.fem.bed.compute_bed_modes` as :class:`ModesData`
    without a file (``path`` None), as :func:`read_modes_file` would give them."""
    m = bed.modes
    return ModesData(
        path=path, plate=bed.spec, input_hash=bed.spec.digest(),
        frequency=np.asarray(m.frequency, dtype=float), omega=np.asarray(m.omega, dtype=float),
        labels=tuple(str(v) for v in m.labels), symmetry=tuple(str(v) for v in m.symmetry),
        nodes=np.asarray(bed.nodes, dtype=float), cells=np.asarray(bed.cells, dtype=np.int64),
        translation=np.asarray(bed.translation, dtype=float),
        rotation=np.asarray(bed.rotation, dtype=float), twist=np.asarray(bed.twist, dtype=float),
        rigid_omega=np.asarray(m.rigid_omega, dtype=float), invariants=bed.invariants,
        next_frequency=(m.omega_next / (2 * math.pi) if math.isfinite(m.omega_next)
                        else math.inf),
        created="", creator="", origin=_origin(bed.origin, bed.nodes), accuracy=bed.accuracy,
        stress=getattr(bed, "stress", None))


def read_modes_file(path: str | Path) -> ModesData:
    """Read and check a modes file.

    Raises
    ------
    InputError
        Not a modes file, another version, damaged, or inconsistent shapes;
        the message names the file and the dataset.
    """
    c = read_file(path, schema=SCHEMA, major=MAJOR, required=REQUIRED)
    root = c.attrs.get("", {})
    try:
        stored = dict(c.attrs["plate"])
        for key in _JSON_KEYS:
            if key in stored:
                stored[key] = json.loads(str(stored[key]))
        # keys added after version 1.0 (theory, geometry) take their defaults when absent
        plate = PlateSpec.from_dict({f.name: stored[f.name] for f in fields(PlateSpec)
                                     if f.name in stored or f.name not in _LATER_KEYS})
    except (KeyError, ValueError, TypeError) as exc:
        raise InputError(f"{c.path}: group 'plate' does not hold valid plate inputs ({exc})") \
            from None
    input_hash = str(root.get("input_hash", ""))
    if input_hash != plate.digest():
        raise InputError(f"{c.path}: input_hash does not match the plate inputs stored "
                         "with it (file edited or damaged); re-run 'flexbed modes --force'")
    freq = np.asarray(c.get("modes/frequency"), dtype=float)
    n = freq.size
    nodes = np.asarray(c.get("mesh/nodes"), dtype=float)
    N = nodes.shape[0]
    expect = {"modes/omega": (n,), "modes/translation": (n, N, 3), "modes/rotation": (n, N, 3),
              "modes/twist": (n, N)}
    expect.update({f"invariants/{v.name}": v.shape_for(n) for v in INVARIANTS})
    for name, shape in expect.items():
        got = np.shape(c.get(name))
        if got != shape:
            raise InputError(f"{c.path}: dataset '{name}' has shape {got}, expected {shape}")
    if nodes.ndim != 2 or nodes.shape[1] != 3 or (
            plate.is_rectangle and (plate.nx + 1) * (plate.ny + 1) != N):
        raise InputError(f"{c.path}: dataset 'mesh/nodes' does not match the "
                         f"{plate.nx} x {plate.ny} mesh of the plate inputs")
    inv = Invariants(**{v.name: (float(c.get(f"invariants/{v.name}")) if v.shape == ()
                                 else np.asarray(c.get(f"invariants/{v.name}"), dtype=float))
                        for v in INVARIANTS}, model_mass=plate.theory == "mindlin")

    accuracy = _read_accuracy(c, n)

    def strings(name: str) -> tuple[str, ...]:
        value = c.datasets.get(name)
        return tuple(str(v) for v in value) if value is not None else ("",) * n

    return ModesData(
        path=c.path, plate=plate, input_hash=input_hash, frequency=freq,
        omega=np.asarray(c.get("modes/omega"), dtype=float),
        labels=strings("modes/label"), symmetry=strings("modes/symmetry"),
        nodes=nodes, cells=np.asarray(c.get("mesh/cells")),
        translation=np.asarray(c.get("modes/translation"), dtype=float),
        rotation=np.asarray(c.get("modes/rotation"), dtype=float),
        twist=np.asarray(c.get("modes/twist"), dtype=float),
        rigid_omega=np.asarray(c.datasets.get("modes/rigid_omega", np.zeros(3)), dtype=float),
        invariants=inv, next_frequency=float(root.get("next_frequency", math.inf)),
        created=str(root.get("created", "")), creator=str(root.get("creator", "")),
        origin=_origin(c.attrs.get("mesh", {}).get("origin_in_drawing_frame", (0.0, 0.0)),
                       nodes), accuracy=accuracy, stress=read_stress(c, n))


def _read_accuracy(c, n: int) -> Accuracy | None:
    """The group ``accuracy`` (None when the file has none)."""
    if "accuracy/frequency_error" not in c.datasets:
        return None
    arrays = {}
    for name in ("frequency_error", "mac"):
        arrays[name] = np.asarray(c.get(f"accuracy/{name}"), dtype=float)
        if arrays[name].shape != (n,):
            raise InputError(f"{c.path}: dataset 'accuracy/{name}' has shape "
                             f"{arrays[name].shape}, expected ({n},)")
    if "accuracy/theory_error" in c.datasets:
        arrays["theory_error"] = np.asarray(c.get("accuracy/theory_error"), dtype=float)
        if arrays["theory_error"].shape != (n,):
            raise InputError(f"{c.path}: dataset 'accuracy/theory_error' has shape "
                             f"{arrays['theory_error'].shape}, expected ({n},)")
    a = c.attrs.get("accuracy", {})
    try:
        return Accuracy(error=arrays["frequency_error"], mac=arrays["mac"],
                        method=str(a["method"]), mesh=str(a["mesh"]),
                        comparison=str(a["comparison"]), ratio=float(a["ratio"]),
                        rate=float(a["rate"]), tolerance=float(a["tolerance"]),
                        element_size=float(a["element_size"]), history=str(a["history"]),
                        theory_error=arrays.get("theory_error"))
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(f"{c.path}: group 'accuracy' lacks a valid attribute ({exc})") \
            from None

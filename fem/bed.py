"""The bed-modes stage in one call: plate → free–free modes → nodal mode
shapes → modal invariants, with the time each step took."""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from .accuracy import Accuracy
from .invariants import Invariants, modal_invariants, shell_invariants
from .modal_stress import ModalStress, modal_stress
from .modes import ModeSet, free_free_modes
from .plate import PlateModel, assemble_plate
from .grid_shapes import nodal_motions
from .shell import ShellModel, assemble_shell
from .spec import PlateSpec


@dataclass(frozen=True)
class BedModes:
    """Everything the modes file holds.

    Attributes
    ----------
    spec : PlateSpec
        Inputs.
    nodes : ndarray (N, 3)
        Node coordinates in the bed frame [m]; z is the mid-surface's, 0
        unless fixed masses lift the centre of mass.
    cells : ndarray (ne, 4)
        Node indices of each cell, counter-clockwise (a Mindlin mesh's
        triangles as (a, b, c, c)).
    modes : ModeSet
        Frequencies, labels.
    translation : ndarray (n, N, 3)
        Mode translations at the nodes [kg^-1/2].
    rotation : ndarray (n, N, 3)
        Mode rotations at the nodes [rad kg^-1/2 m^-1].
    twist : ndarray (n, N)
        ∂²w/∂x∂y at the nodes [kg^-1/2 m^-2] (completes the Hermite data;
        zero for the Mindlin shell, whose fields are bilinear).
    invariants : Invariants
    timings : dict
        Seconds spent in "assemble", "eigen", "invariants".
    origin : ndarray (2,)
        Where the nodes' origin (the bed's centre of mass) is in the
        drawing frame the geometry was given in [m].
    accuracy : Accuracy or None
        The estimated discretisation error of each mode
        (:mod:`flexbed.fem.accuracy`); an auto mesh's says what was chosen
        (:mod:`flexbed.fem.auto_size`). None: not estimated.
    stress : ModalStress or None
        Each mode's stresses at the element centres
        (:mod:`flexbed.fem.modal_stress`).
    """

    spec: PlateSpec
    nodes: np.ndarray
    cells: np.ndarray
    modes: ModeSet
    translation: np.ndarray
    rotation: np.ndarray
    twist: np.ndarray
    invariants: Invariants
    timings: dict = field(default_factory=dict)
    origin: np.ndarray = field(default_factory=lambda: np.zeros(2))
    accuracy: Accuracy | None = None
    stress: ModalStress | None = None


def bed_modes_from_model(model: PlateModel | ShellModel,
                         modes: ModeSet) -> tuple[np.ndarray, ...]:
    """Nodal translation (n, N, 3), rotation (n, N, 3) and twist (n, N)."""
    if isinstance(model, ShellModel):
        phi = modes.vectors
        return (model.translations(phi), model.rotations(phi),
                np.zeros((phi.shape[1], model.nodes.shape[0])))
    d = model.node_dofs
    phi = modes.vectors
    w, w_x, w_y, w_xy = (phi[d[i]].T for i in range(4))
    translation, rotation = nodal_motions(w, w_x, w_y)
    return translation, rotation, w_xy


def assemble_bed(spec: PlateSpec) -> PlateModel | ShellModel:
    """The FE model of the spec's theory: Kirchhoff plate or Mindlin shell."""
    return assemble_shell(spec) if spec.theory == "mindlin" else assemble_plate(spec)


def compute_bed_modes(spec: PlateSpec, n_modes: int | None = None,
                      fmax: float | None = None) -> BedModes:
    """Run the whole stage for one plate.

    Parameters
    ----------
    spec : PlateSpec
    n_modes : int, optional
        Elastic modes to keep.
    fmax : float, optional
        Instead: keep every elastic mode below this frequency [Hz].

    Returns
    -------
    BedModes
        With no ``accuracy`` for a given mesh (:func:`flexbed.fem.accuracy.estimate`
        adds it); a spec with ``mesh_tolerance`` (``element_size = "auto"``)
        is solved on the mesh chosen for it, with its accuracy
        (:func:`flexbed.fem.auto_size.choose_mesh`).
    """
    if spec.auto_mesh:
        from .auto_size import choose_mesh
        return choose_mesh(spec, n_modes=n_modes, fmax=fmax)
    t0 = time.perf_counter()
    model = assemble_bed(spec)
    t1 = time.perf_counter()
    modes = free_free_modes(model, n_modes=n_modes, fmax=fmax)
    t2 = time.perf_counter()
    translation, rotation, twist = bed_modes_from_model(model, modes)
    if isinstance(model, ShellModel):
        invariants = shell_invariants(model, modes)
        cells = model.cells.copy()
    else:
        invariants = modal_invariants(model, modes)
        cells = model.mesh.t.T.copy()
    stress = modal_stress(model, modes.vectors)
    t3 = time.perf_counter()
    nodes = np.column_stack([model.nodes, np.full(model.nodes.shape[0],
                                                  getattr(model, "mid_z", 0.0))])
    return BedModes(spec=spec, nodes=nodes, cells=cells, modes=modes,
                    translation=translation, rotation=rotation, twist=twist,
                    invariants=invariants,
                    timings={"assemble": t1 - t0, "eigen": t2 - t1, "invariants": t3 - t2},
                    origin=getattr(model, "origin", np.zeros(2)), stress=stress)

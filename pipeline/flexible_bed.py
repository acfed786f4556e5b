"""Hand-off from the modes file to the dynamics: the flexible bed as plain
arrays, checked against the scene that asks for it."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from dynamics.errors import SceneError
from dynamics.flexible import FlexibleBody, modal_damping, rayleigh_damping
from dynamics.scene import Scene
from fem.shapes import GridShapes, OutsidePlateError

from .errors import InputError
from .modes_file import ModesData, read_modes_file
from .scene_file import SceneFile


def bed_name(sf: SceneFile) -> str:
    """Name of the scene's bed body (``[bed] body``, default body 2)."""
    if sf.bed.body is not None:
        return sf.bed.body
    if len(sf.scene.bodies) < 2:
        raise InputError(f"{sf.source.name}: bed: the scene has no second body to be the bed")
    return sf.scene.bodies[1].name


def kept_modes(sf: SceneFile, data: ModesData) -> int:
    """How many of the file's modes the scene keeps (checked against the file)."""
    where = f"{sf.source.name}: bed"
    if sf.bed.fmax is not None:
        if sf.bed.fmax > data.next_frequency:
            raise InputError(f"{where}: fmax = {sf.bed.fmax:g} Hz, but {data.path} holds the "
                             f"modes below {data.next_frequency:.4g} Hz only; re-run "
                             f"'flexbed modes --fmax {sf.bed.fmax:g}'")
        kept = int(np.sum(data.frequency < sf.bed.fmax))
        return max(kept, 1) if sf.bed.auto else kept       # "auto" keeps at least one
    if sf.bed.modes > data.n_modes:
        raise InputError(f"{where}: modes = {sf.bed.modes}, but {data.path} holds only "
                         f"{data.n_modes}; re-run 'flexbed modes --modes {sf.bed.modes}'")
    return sf.bed.modes


def flexible_body(sf: SceneFile, data: ModesData, *, n_modes: int | None = None,
                  damped: bool = True, full: bool | None = None) -> FlexibleBody:
    """The bed as a :class:`FlexibleBody` with the scene's points and damping.

    Parameters
    ----------
    sf : SceneFile
    data : ModesData
        Must have been made from the scene's plate (hash checked).
    n_modes : int, optional
        Modes kept (default: the scene's choice); 0 gives the rigid bed
        through the flexible machinery.
    damped : bool
        Apply the scene's Rayleigh coefficients or damping ratios (False: α = β = 0).
    full : bool, optional
        Keep the configuration-dependent invariants (False: first-order
        set); default: the scene's ``invariants`` key.
    """
    where = f"{sf.source.name}: bed"
    if full is None:
        full = sf.bed.invariants == "full"
    if data.input_hash != sf.bed.plate.digest():
        raise InputError(f"{where}: the modes file {data.path} was made for another bed "
                         f"(plate inputs differ); re-run 'flexbed modes'")
    n = kept_modes(sf, data) if n_modes is None else n_modes
    if n > data.n_modes:
        raise InputError(f"{where}: {n} modes asked, {data.path} holds {data.n_modes}")
    name = bed_name(sf)
    pts = [m.point_i for m in sf.scene.mounts if m.body_i == name]
    pts += [m.point_j for m in sf.scene.mounts if m.body_j == name]
    pts += [p.position for p in sf.points if p.body == name]
    points = np.unique(np.array(pts, dtype=float).reshape(-1, 3), axis=0)
    shapes = GridShapes.from_nodes(data.nodes, data.translation[:n], data.rotation[:n],
                                   data.twist[:n])
    for m in sf.scene.mounts:
        for key, point in (("body_i", m.point_i), ("body_j", m.point_j)):
            if getattr(m, key) == name:
                try:
                    shapes.at(np.asarray(point, dtype=float)[None, :])
                except OutsidePlateError as exc:
                    raise InputError(f"{sf.source.name}: mount '{m.name}': "
                                     f"point on the bed {exc}") from None
    try:
        trans, _ = shapes.at(points) if len(points) else (np.zeros((n, 0, 3)), None)
    except OutsidePlateError as exc:
        raise InputError(f"{sf.source.name}: point of interest on the bed: {exc}") from None
    inv = data.invariants
    k = slice(0, n)
    K = inv.modal_stiffness[k, k]
    I6 = inv.modal_mass[k, k]
    if not damped:
        C = np.zeros((n, n))
    elif sf.bed.damping_ratio is not None:
        ratio = sf.bed.damping_ratio
        if len(ratio) not in (1, n):
            raise InputError(f"{where}: damping_ratio has {len(ratio)} values for {n} modes")
        C = modal_damping(data.omega[:n], ratio if len(ratio) > 1 else ratio[0])
    else:
        alpha, beta = sf.bed.rayleigh
        C = rayleigh_damping(I6, K, alpha, beta)
    try:
        return FlexibleBody(
            mass=inv.mass, first_moment=inv.first_moment, inertia=inv.inertia,
            phi_integral=inv.phi_integral[:, k], u_cross_phi=inv.u_cross_phi[:, k],
            phi_cross_phi=inv.phi_cross_phi[k, :, k], modal_mass=I6,
            inertia_first_order=inv.inertia_first_order[k],
            inertia_second_order=inv.inertia_second_order[k, k],
            modal_stiffness=K, modal_damping=C, points=points,
            point_shapes=np.transpose(trans, (1, 2, 0)), full=full)
    except SceneError as exc:
        raise InputError(f"{where}: {exc}") from None


def with_flexible_bed(sf: SceneFile, data: ModesData, **kwargs) -> Scene:
    """The scene's dynamics model with its bed flexible (see :func:`flexible_body`)."""
    fb = flexible_body(sf, data, **kwargs)
    try:
        return replace(sf.scene, flexible=((bed_name(sf), fb),))
    except SceneError as exc:
        raise InputError(f"{sf.source.name}: {exc}") from None


def load_modes_for(sf: SceneFile, path: str | Path) -> ModesData:
    """Read the modes file a flexible-bed stage needs, with a message that
    says which stage to run when it is missing."""
    path = Path(path)
    if not path.exists():
        raise InputError(f"{path}: no modes file; run 'flexbed modes {sf.source}' first "
                         f"(or give --modes-file)")
    return read_modes_file(path)

"""Hand-off from the modes file to the dynamics: the flexible bed as plain
arrays, checked against the scene that asks for it."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np

from flexbed.dynamics.errors import SceneError
from flexbed.dynamics.flexible import FlexibleBody, modal_damping, rayleigh_damping
from flexbed.dynamics.scene import Scene
from flexbed.fem.quad_shapes import mode_shapes
from flexbed.fem.grid_shapes import OutsidePlateError

from flexbed.errors import InputError
from flexbed.files.bed_section import plate_mismatch
from flexbed.files.modes import INVARIANTS, ModesData, read_modes_file
from flexbed.stages.residual_modes import change_of_modes, residual_basis
from flexbed.files.scene import SceneFile


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
    pts += [ld.point for ld in sf.scene.loads if ld.body == name]
    points = np.unique(np.array(pts, dtype=float).reshape(-1, 3), axis=0)
    shapes = mode_shapes(data.plate.theory, data.nodes, data.cells, data.translation[:n],
                         data.rotation[:n], data.twist[:n])
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
    omega = data.omega[:n]
    arrays = {"I3": inv.phi_integral[:, k], "I4": inv.u_cross_phi[:, k],
              "I5": inv.phi_cross_phi[k, :, k], "I6": inv.modal_mass[k, k],
              "I8": inv.inertia_first_order[k], "I9": inv.inertia_second_order[k, k],
              "K": inv.modal_stiffness[k, k], "shapes": trans}
    basis = np.eye(data.n_modes, n)
    if sf.bed.static_correction:
        basis, arrays, omega = _corrected(sf, data, n, name, points)
    K, I6 = arrays["K"], arrays["I6"]
    n_coords = K.shape[0]
    if not damped:
        C = np.zeros((n_coords, n_coords))
    elif sf.bed.damping_ratio is not None:
        ratio = sf.bed.damping_ratio
        if len(ratio) not in (1, n_coords):
            raise InputError(f"{where}: damping_ratio has {len(ratio)} values for {n_coords} "
                             f"modal coordinates")
        C = modal_damping(omega, ratio if len(ratio) > 1 else ratio[0])
    else:
        alpha, beta = sf.bed.rayleigh
        C = rayleigh_damping(I6, K, alpha, beta)
    # the invariants by the modes file's names (INVARIANTS): those of the kept
    # modal coordinates, the rigid-body ones (I1, I2, I7) as the file has them
    invariants = {v.name: arrays.get(v.symbol, getattr(inv, v.name)) for v in INVARIANTS}
    try:
        return FlexibleBody(
            **invariants, modal_damping=C, points=points,
            point_shapes=np.transpose(arrays["shapes"], (1, 2, 0)), full=full, basis=basis)
    except SceneError as exc:
        raise InputError(f"{where}: {exc}") from None


def _corrected(sf: SceneFile, data: ModesData, n: int, name: str,
               points: np.ndarray) -> tuple:
    """The kept modes plus residual vectors (:mod:`flexbed.stages.residual_modes`):
    (basis (N, n + m), invariants and point shapes in those coordinates,
    their circular frequencies (n + m,) [rad/s])."""
    N = min(sf.bed.correction_modes, data.n_modes)
    if N <= n:
        raise InputError(f"{sf.source.name}: bed: static_correction needs modes beyond the "
                         f"{n} kept, and correction_modes = {sf.bed.correction_modes} with "
                         f"{data.path} holding {data.n_modes}; raise correction_modes")
    shapes = mode_shapes(data.plate.theory, data.nodes, data.cells, data.translation[:N],
                         data.rotation[:N], data.twist[:N])
    mounts = [m.point_i for m in sf.scene.mounts if m.body_i == name]
    mounts += [m.point_j for m in sf.scene.mounts if m.body_j == name]
    mount_pts = np.unique(np.array(mounts, dtype=float).reshape(-1, 3), axis=0)
    at_mounts, _ = shapes.at(mount_pts)                                  # (N, P, 3)
    inv = data.invariants
    a = slice(0, N)
    T, w = residual_basis(inv.modal_mass[a, a], inv.modal_stiffness[a, a],
                          at_mounts.reshape(N, -1), n)
    at_points, _ = shapes.at(points) if len(points) else (np.zeros((N, 0, 3)), None)
    arrays = change_of_modes(
        T, I3=inv.phi_integral[:, a], I4=inv.u_cross_phi[:, a], I5=inv.phi_cross_phi[a, :, a],
        I6=inv.modal_mass[a, a], I8=inv.inertia_first_order[a],
        I9=inv.inertia_second_order[a, a], K=inv.modal_stiffness[a, a], shapes=at_points)
    basis = np.zeros((data.n_modes, T.shape[1]))
    basis[:N] = T
    return basis, arrays, np.concatenate([data.omega[:n], w])


def with_flexible_bed(sf: SceneFile, data: ModesData, **kwargs) -> Scene:
    """The scene's dynamics model with its bed flexible (see :func:`flexible_body`).

    The bed body's mass and inertia must be the plate's (checked when the
    scene file is read if it says ``model = "flexible"``, here again for a
    scene read as rigid and made flexible, e.g. by ``compare``)."""
    body = sf.scene.bodies[sf.scene.body_index(bed_name(sf))]
    J = body.inertia
    given = np.diag(J).tolist() if np.all(J == np.diag(np.diag(J))) else J.tolist()
    why = plate_mismatch(sf.bed.plate, body.mass, given)
    if why:
        raise InputError(f"{sf.source.name}: body {body.name!r}: {why}")
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

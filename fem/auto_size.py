"""``element_size = "auto"``: the mesh chosen for a stated accuracy.

The search
----------
The tolerance (``mesh_tolerance``, default 0.5 %) applies to the modes the
file holds: those asked for, and at least the first
:data:`MIN_CHECKED` (10) elastic modes. Meshes are those of
:func:`flexbed.fem.auto_mesh.mesh_spec` (nodes at the stiffeners, fixed
masses and mount points; graded at free edges).

1. Solve at H = the shorter side / 4 and at h = H / 2; estimate each mode's
   error at h by Richardson extrapolation from H (:mod:`flexbed.fem.accuracy`,
   p = 2, modes matched by MAC).
2. If the largest |error| is within the tolerance, h is the mesh.
   Otherwise predict the size that gives :data:`SAFETY` × the tolerance
   (error ∝ h²: h' = h √(SAFETY tol / error)), solve there and at 2h' (or
   reuse the last mesh when it is within 15 % of 2h'), and estimate again.
   A mode without a match (MAC < 0.5: the coarser mesh cannot show it yet)
   halves h.
3. The search stops at the mesh within the tolerance, or at the finest
   mesh :data:`flexbed.fem.spec.MAX_DOFS` allows (then the estimate says by
   how much the tolerance is missed).

The estimate stored with the modes is the last pair's: the chosen mesh
against the mesh about twice as coarse.
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from .accuracy import EXTRA_MODES, RATES, Accuracy, compare, element_size
from .auto_mesh import grading_points, max_cells_size, mesh_spec, start_size
from .spec import MAX_DOFS, PlateSpec

#: the tolerance holds on at least this many elastic modes
MIN_CHECKED = 10
#: aim at this fraction of the tolerance when predicting the size
SAFETY = 0.7
#: at most this many meshes are solved
MAX_STEPS = 8


def _solve(spec: PlateSpec, h: float, n_modes: int | None, fmax: float | None):
    """The modes of the auto bed's mesh at h: all below fmax or n_modes, and
    at least MIN_CHECKED."""
    from .bed import compute_bed_modes
    concrete = mesh_spec(spec, h)
    if n_modes is not None:
        return compute_bed_modes(concrete, n_modes=max(n_modes, MIN_CHECKED))
    bed = compute_bed_modes(concrete, n_modes=MIN_CHECKED)
    if bed.modes.omega_next < 2 * math.pi * fmax:
        bed = compute_bed_modes(concrete, fmax=fmax)
    return bed


def _comparison(spec: PlateSpec, h: float, n: int):
    from .bed import compute_bed_modes
    return compute_bed_modes(mesh_spec(spec, h), n_modes=n + EXTRA_MODES)


def _words(spec: PlateSpec, h: float, bed) -> str:
    parts = [f"element_size {h:.4g} m chosen ({bed.cells.shape[0]} elements, "
             f"{bed.nodes.shape[0]} nodes)"]
    if spec.stiffeners:
        parts.append("stiffeners along mesh lines")
    nodes_at = []
    for n, what in ((len(spec.masses), "fixed mass"), (len(spec.mesh_points), "mount point")):
        if n:
            nodes_at.append(f"{n} {what}" + ("es" if n > 1 and what.endswith("s") else
                                             "s" if n > 1 else ""))
    if nodes_at:
        parts.append("nodes at " + " and ".join(nodes_at))
    if grading_points(spec, h):
        parts.append("graded at free edges")
    return "; ".join(parts)


def choose_mesh(spec: PlateSpec, n_modes: int | None = None, fmax: float | None = None):
    """The modes of an auto bed on the mesh chosen for its tolerance.

    Parameters
    ----------
    spec : PlateSpec
        With ``mesh_tolerance`` set.
    n_modes, fmax
        The modes asked for (as :func:`flexbed.fem.bed.compute_bed_modes`).

    Returns
    -------
    BedModes
        ``spec`` the auto spec as given, the chosen mesh's nodes, cells and
        modes, and ``accuracy`` saying what was chosen and its estimated
        error per mode.
    """
    tol = spec.mesh_tolerance
    rate = RATES["mindlin"]
    h_floor = max_cells_size(spec, MAX_DOFS)
    H = start_size(spec)
    h = H / 2
    fine = _solve(spec, h, n_modes, fmax)
    coarse = _comparison(spec, H, fine.modes.omega.size)
    tried = []
    for step in range(MAX_STEPS):
        ratio = (element_size(coarse.nodes, coarse.cells)
                 / element_size(fine.nodes, fine.cells))
        err, value = compare(fine, coarse, ratio, rate)
        worst = float(np.nanmax(np.abs(err))) if np.any(np.isfinite(err)) else math.inf
        unmatched = bool(np.any(~np.isfinite(err)))
        tried.append(f"{h:.4g} m: {100 * worst:.3g} %" + (" (modes unmatched)" if unmatched
                                                           else ""))
        if ((worst <= tol and not unmatched) or h <= h_floor * (1 + 1e-9)
                or step == MAX_STEPS - 1):
            break
        shrink = 0.5 if unmatched or not math.isfinite(worst) else \
            min(math.sqrt(SAFETY * tol / worst), 0.8)
        h_new = max(h * shrink, h_floor)
        if abs(2 * h_new / h - 1) <= 0.15:
            H, coarse = h, fine
            fine = _solve(spec, h_new, n_modes, fmax)
        else:
            fine = _solve(spec, h_new, n_modes, fmax)
            H = 2 * h_new
            coarse = _comparison(spec, H, fine.modes.omega.size)
        h = h_new
    hit = worst <= tol and not unmatched
    history = "; ".join(tried) + ("" if hit else " (the search stopped short of the tolerance)")
    accuracy = Accuracy(
        error=err, mac=value,
        method=f"Richardson extrapolation from the mesh at {H:.4g} m (frequencies "
               f"converging as h^{rate:g}, modes matched by MAC)",
        mesh=_words(spec, h, fine), comparison=f"element_size {H:.4g} m", ratio=ratio,
        rate=rate, tolerance=tol, element_size=element_size(fine.nodes, fine.cells),
        history=history)
    return replace(fine, spec=spec, accuracy=accuracy)

"""How far each mode's frequency is from the converged one: a second mesh
and Richardson extrapolation.

The method
----------
The bed is solved again on a mesh about twice as coarse (the *comparison
mesh*: the nx × ny grid halved, or the geometry meshed at twice the element
size; a Kirchhoff grid is cheap to solve and is compared with the grid
twice as fine, :data:`FINER_DOFS`), each mode is matched to its own on
that mesh by shape (the MAC of the mid-surface translations at a lattice
of points on both meshes, the pairs assigned one to one), and with
frequencies f_h (the mesh) and f_H (the comparison mesh, element size
ratio r = H / h) and the element's rate of convergence p,

    f_∞ ≈ f_h + (f_h − f_H) / (r^p − 1),     error = f_h / f_∞ − 1

(Richardson extrapolation; signed: positive when the mesh is too stiff).
The rates are the elements' for smooth modes, checked on the reference bed
(tests/test_accuracy.py): p = 2 for the Mindlin shell (MITC4 bilinear
fields; observed 1.9–2.0 on the bending modes of the auto meshes,
:mod:`flexbed.fem.auto_mesh`) and p = 4 for the Kirchhoff plate
(Bogner–Fox–Schmit bicubics; observed 3.4–3.95 from 10 × 10 to 40 × 40).

How good it is, against converged shell references (tests/test_accuracy.py):
within a factor of 2 of the true error on every mode of the plain and the
cut-out bed at h = 0.1 m, and on their bending modes at 0.05 m. Modes
whose error has a slower component are underestimated: the torsion modes
(the free corners' and the cut-out's re-entrant corners' singularities:
at 0.05 m their true errors of 0.1–0.25 % were estimated 2–5 x low, still
below the largest error of the bending modes, which governs an auto
mesh); the stiffened bed, whose frequencies do not converge monotonically
(some fall from 0.1 to 0.05 m and rise from 0.05 to 0.025 m), so the
estimate can have the wrong sign there. A mode matched with a MAC below
:data:`MIN_MAC` has no estimate (NaN). A mesh file has no comparison mesh:
its modes carry no estimate.

It costs one more solve, on about a quarter of the nodes (a Kirchhoff
grid: four times the nodes, still a fraction of a second up to 50 × 50).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from .cells import areas, is_triangle, locate, point_shape
from .grid_shapes import GridShapes
from .geometry import BedGeometry
from .spec import PlateSpec

#: rate of convergence of the frequencies, |f_h − f| ∝ h^p, per theory
RATES = {"mindlin": 2.0, "kirchhoff": 4.0}
#: a mode matched below this MAC has no estimate
MIN_MAC = 0.5
#: modes computed on the comparison mesh beyond the mesh's own
EXTRA_MODES = 6
#: a Kirchhoff grid is compared with the grid twice as fine up to this many
#: degrees of freedom (a cheap solve; coarse grids of long elements are out
#: of the asymptotic range: the 10 x 10 grid's 6th mode against 5 x 5 was
#: estimated 4.5 x low), beyond it with the grid twice as coarse
FINER_DOFS = 20_000


@dataclass(frozen=True)
class Accuracy:
    """Estimated discretisation error of each mode's frequency.

    Attributes
    ----------
    error : ndarray (n,)
        f_h / f_∞ − 1, estimated [-] (NaN: no estimate).
    mac : ndarray (n,)
        MAC of each mode with its match on the comparison mesh [-].
    method : str
        How it was estimated (one line).
    mesh, comparison : str
        The mesh and the comparison mesh, in words.
    ratio : float
        Element size ratio H / h of the two meshes [-].
    rate : float
        Rate p assumed [-].
    tolerance : float
        ``element_size = "auto"``: the tolerance the mesh was chosen for [-]
        (NaN for a given mesh).
    element_size : float
        Typical element side of the mesh (95th percentile of √area) [m].
    history : str
        ``auto``: the meshes tried and their largest estimated errors.
    theory_error : ndarray (n,) or None
        A Kirchhoff bed: each mode's converged frequency against the
        shear-deformable shell's, f_Kirchhoff / f_shell − 1 [-]
        (:mod:`flexbed.fem.theory_error`; NaN: no matching shell mode).
    """

    error: np.ndarray
    mac: np.ndarray
    method: str
    mesh: str
    comparison: str
    ratio: float
    rate: float
    tolerance: float = math.nan
    element_size: float = math.nan
    history: str = ""
    theory_error: np.ndarray | None = None

    @property
    def worst(self) -> float:
        """Largest |error| over the modes with an estimate (NaN if none) [-]."""
        e = np.abs(self.error[np.isfinite(self.error)])
        return float(e.max()) if e.size else math.nan

    def summary(self) -> str:
        """One line: the mesh, the largest estimated error, the method."""
        w = self.worst
        shown = f"{100 * w:.2g} %" if math.isfinite(w) else "not estimated"
        tol = (f" (tolerance {100 * self.tolerance:g} %)" if math.isfinite(self.tolerance)
               else "")
        line = (f"mesh: {self.mesh}; estimated discretisation error of the frequencies up to "
                f"{shown}{tol}, by {self.method}")
        t = self.theory_error
        if t is not None and np.any(np.isfinite(t)):
            k = int(np.nanargmax(np.abs(t)))
            line += (f"; the Kirchhoff theory against the shear-deformable shell: up to "
                     f"{100 * t[k]:+.2g} % (mode {k + 1})")
        return line


def richardson(f_fine: np.ndarray, f_coarse: np.ndarray, ratio: float, rate: float
               ) -> np.ndarray:
    """Relative error f_h / f_∞ − 1 of ``f_fine`` (n,), from the same modes
    ``f_coarse`` (n,) on a mesh ``ratio`` times coarser, converging as h^rate."""
    f_fine, f_coarse = np.asarray(f_fine, float), np.asarray(f_coarse, float)
    f_inf = f_fine + (f_fine - f_coarse) / (ratio ** rate - 1.0)
    return f_fine / f_inf - 1.0


def element_size(nodes: np.ndarray, cells: np.ndarray) -> float:
    """Typical element side of a mesh: the 95th percentile of √(cell area) [m]."""
    return float(np.percentile(np.sqrt(np.abs(areas(nodes[:, :2], cells))), 95))


def _located(bed, pts: np.ndarray) -> list:
    """(cell, natural coordinates) of each drawing-frame point (P, 2) on a
    shell mesh, or None off it."""
    local = pts - bed.origin
    nodes, cells = bed.nodes[:, :2], bed.cells
    return [locate(nodes, cells, x, y) for x, y in local]


def _shell_translations(bed, where: list) -> np.ndarray:
    """Mid-surface translations (n, P, 3) at located points."""
    tri = is_triangle(bed.cells)
    out = np.empty((bed.translation.shape[0], len(where), 3))
    for i, (c, s) in enumerate(where):
        N, _ = point_shape(bool(tri[c]), s)
        out[:, i] = np.einsum("a,kaj->kj", N, bed.translation[:, bed.cells[c]])
    return out


def lattice_shapes(fine, coarse, count: int = 200) -> tuple[np.ndarray, np.ndarray]:
    """Mid-surface translations of both mode sets, flattened (n, 3P), at
    about ``count`` points of a regular lattice over the bed where both
    meshes are (drawing frame; either theory)."""
    xy = fine.nodes[:, :2] + fine.origin
    lo, hi = xy.min(axis=0), xy.max(axis=0)
    ext = hi - lo
    k = math.sqrt(count / max(ext[0] * ext[1], 1e-300))
    nx, ny = (max(3, int(round(k * e))) for e in ext)
    X, Y = np.meshgrid(lo[0] + ext[0] * (np.arange(nx) + 0.5) / nx,
                       lo[1] + ext[1] * (np.arange(ny) + 0.5) / ny)
    pts = np.column_stack([X.ravel(), Y.ravel()])
    beds = (fine, coarse)
    where = [_located(b, pts) if b.spec.theory == "mindlin" else None for b in beds]
    keep = np.array([all(w is None or w[i] is not None for w in where)
                     for i in range(len(pts))], dtype=bool)
    out = []
    for bed, w in zip(beds, where):
        if w is None:                                # the Kirchhoff rectangle: any point
            ev = GridShapes.from_nodes(bed.nodes, bed.translation, bed.rotation, bed.twist)
            local = np.column_stack([pts[keep] - bed.origin, np.zeros(int(keep.sum()))])
            out.append(ev.at(local)[0])
        else:
            out.append(_shell_translations(bed, [w[i] for i in np.flatnonzero(keep)]))
    return tuple(v.reshape(v.shape[0], -1) for v in out)


def mac(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Modal assurance criterion of every pair of rows, (na, nb) in [0, 1]."""
    num = (a @ b.T) ** 2
    den = np.outer(np.sum(a * a, axis=1), np.sum(b * b, axis=1))
    return num / np.maximum(den, 1e-300)


def match(fine, coarse) -> tuple[np.ndarray, np.ndarray]:
    """Each mode of ``fine`` paired with one of ``coarse`` (one to one, the
    largest total MAC): (index into coarse (n,), MAC (n,))."""
    from scipy.optimize import linear_sum_assignment
    m = mac(*lattice_shapes(fine, coarse))
    rows, cols = linear_sum_assignment(-m)
    index = np.full(m.shape[0], -1)
    index[rows] = cols
    value = np.zeros(m.shape[0])
    value[rows] = m[rows, cols]
    return index, value


def compare(fine, coarse, ratio: float, rate: float) -> tuple[np.ndarray, np.ndarray]:
    """Estimated error (n,) and matching MAC (n,) of ``fine``'s modes from
    the comparison modes ``coarse`` (both :class:`~flexbed.fem.bed.BedModes`)."""
    index, value = match(fine, coarse)
    f = fine.modes.frequency
    fc = np.where(index >= 0, coarse.modes.frequency[np.maximum(index, 0)], np.nan)
    err = richardson(f, fc, ratio, rate)
    return np.where(value >= MIN_MAC, err, np.nan), value


def grid_words(spec: PlateSpec) -> str:
    """The mesh of a spec in words."""
    g = spec.geometry
    if g is None:
        return f"{spec.nx} x {spec.ny} grid"
    if g.mesh_file is not None:
        return "mesh file"
    return f"element_size {g.element_size:.4g} m" if g.element_size else \
        f"{spec.nx} x {spec.ny} spacing"


def comparison_spec(spec: PlateSpec) -> tuple[PlateSpec, float] | None:
    """The comparison mesh of a given (not auto) mesh and the size ratio H / h:
    a Kirchhoff grid doubled (ratio 1/2) up to :data:`FINER_DOFS`, else the
    grid halved (nx, ny → round(nx/2), round(ny/2)), or the geometry at
    twice its element size; None for a mesh file or a 1 x 1 grid."""
    g = spec.geometry
    if g is not None and g.mesh_file is not None:
        return None
    if spec.theory == "kirchhoff" and 4 * (2 * spec.nx + 1) * (2 * spec.ny + 1) <= FINER_DOFS:
        return replace(spec, nx=2 * spec.nx, ny=2 * spec.ny), 0.5
    if g is None and not spec.stiffeners:
        nx2, ny2 = max(1, round(spec.nx / 2)), max(1, round(spec.ny / 2))
        if (nx2, ny2) == (spec.nx, spec.ny):
            return None
        return (replace(spec, nx=nx2, ny=ny2),
                math.sqrt(spec.nx * spec.ny / (nx2 * ny2)))
    if g is not None and g.element_size is not None:
        h = g.element_size
    else:
        from .auto_mesh import outline_polygon
        ext = np.ptp(outline_polygon(spec), axis=0)
        h = min(ext[0] / spec.nx, ext[1] / spec.ny)
    return replace(spec, geometry=replace(g or BedGeometry(), element_size=2.0 * h)), 2.0


def estimate(bed) -> Accuracy | None:
    """The estimated error of a :class:`~flexbed.fem.bed.BedModes` on a given
    mesh (see the module's text); None when there is no comparison mesh."""
    from .bed import compute_bed_modes
    from .modes import ModesError
    found = comparison_spec(bed.spec)
    if found is None:
        return None
    spec2, ratio = found
    n = bed.modes.omega.size
    k = n + EXTRA_MODES
    while True:
        try:
            coarse = compute_bed_modes(spec2, n_modes=k)
            break
        except ModesError:
            if k <= n:
                return None
            k = max(n, k // 2)
    rate = RATES[bed.spec.theory]
    if ratio > 1:
        err, value = compare(bed, coarse, ratio, rate)
        how = f"a {ratio:.3g} x coarser mesh"
    else:                               # a finer comparison: extrapolate from it
        index, value = match(bed, coarse)
        f, f2 = bed.modes.frequency, coarse.modes.frequency[index]
        f_inf = f2 / (1.0 + richardson(f2, f, 1.0 / ratio, rate))
        err = np.where(value >= MIN_MAC, f / f_inf - 1.0, np.nan)
        how = f"a {1 / ratio:.3g} x finer mesh"
    return Accuracy(error=err, mac=value,
                    method=f"Richardson extrapolation with {how} "
                           f"(frequencies converging as h^{rate:g})",
                    mesh=grid_words(bed.spec), comparison=grid_words(spec2), ratio=ratio,
                    rate=rate, element_size=element_size(bed.nodes, bed.cells))

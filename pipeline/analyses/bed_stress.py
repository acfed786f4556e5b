"""Stresses in the bed over a run, by modal superposition.

σ(t) = Σ_i σ_i a_i(t): the modes file's modal stresses
(:mod:`flexbed.fem.modal_stress`, at element centres) times the run's
modal coordinates, taken to the file's modes through the run's
``modal/basis`` (the kept modes, then the static correction's residual
vectors, :mod:`flexbed.stages.residual_modes`), so that a run with
``static_correction = true`` has its stresses corrected at the mounts as
its motion is. von Mises and principal stresses come from the superposed
components at each instant (never from the modes' own measures).

The peak von Mises stress of the bed (over elements, both faces and time)
and the peak |σ| at the extreme fibres of each stiffener are found with
their place and time; t = 0 is the static equilibrium (the bed's sag)
when the run starts from it. The time loop goes in chunks of frames, so
memory stays at chunk × elements.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
from threadpoolctl import threadpool_limits

from flexbed.errors import InputError
from flexbed.fem.modal_stress import ModalStress

__all__ = ["Peak", "BedStresses", "StressVerdict", "superpose", "bed_stresses_of_run",
           "in_run_coordinates", "stress_verdicts"]

#: frames per block of the superposition (its arrays stay in cache)
CHUNK = 64
FACES = ("top", "bottom")


@dataclass(frozen=True)
class Peak:
    """A peak stress and where and when it occurs.

    Attributes
    ----------
    value : float
        The stress [Pa] (von Mises in the plate; |σ| in a stiffener).
    x, y : float
        Place in the bed frame [m] (an element centre, or a beam element's
        mid-point).
    index : int
        The element (or beam element) 0-based.
    where : str
        "top" or "bottom" face; a stiffener's fibre as its height above
        the centroid ("fibre +0.05 m").
    time : float
        [s].
    """

    value: float
    x: float
    y: float
    index: int
    where: str
    time: float


@dataclass(frozen=True)
class BedStresses:
    """The bed's stresses over a run.

    Attributes
    ----------
    time : ndarray (k,) [s]
    peak_map : ndarray (ne,)
        Each element's largest von Mises stress over both faces and the run [Pa].
    initial : ndarray (ne, 2)
        von Mises stress at t = time[0], top and bottom face [Pa].
    bed : Peak
        The plate's peak von Mises stress.
    initial_peak : Peak
        The plate's largest von Mises stress at t = time[0].
    stiffeners : tuple of (str, Peak)
        Each stiffener's peak |σ| at its extreme fibres.
    centres : ndarray (ne, 2)
        Element centres in the bed frame [m].
    """

    time: np.ndarray
    peak_map: np.ndarray
    initial: np.ndarray
    bed: Peak
    initial_peak: Peak
    stiffeners: tuple
    centres: np.ndarray


def _von_mises_basis(stress: ModalStress) -> np.ndarray:
    """Per mode, (p, √3 q, √3 τ) at each element's top and bottom faces,
    (n, 3·ne·2) in three contiguous parts, p = (σxx + σyy)/2, q = (σxx − σyy)/2: since
    σ_vM² = σxx² − σxx σyy + σyy² + 3τ² = p² + 3q² + 3τ², the von Mises
    stress of any combination a of the modes is the length of a @ W per
    element and face — one matrix product and a sum of squares."""
    faces = stress.faces(np.eye(stress.n_modes))                  # (n, ne, 2, 3)
    sx, sy, txy = faces[..., 0], faces[..., 1], faces[..., 2]
    root3 = np.sqrt(3.0)
    W = np.stack([0.5 * (sx + sy), 0.5 * root3 * (sx - sy), root3 * txy], axis=1)
    return W.reshape(stress.n_modes, -1)          # (n, 3 · ne · 2): each part contiguous


def _scan(a32: np.ndarray, W32: np.ndarray, ne: int, chunk: int) -> tuple:
    """σ_vM² = |a W|² per element and face over the frames, in blocks of
    ``chunk``: the peak map (ne, 2) and the peak (value², frame, element,
    face)."""
    k = a32.shape[0]
    peak_map = np.zeros((ne, 2), dtype=np.float32)
    best = (-1.0, 0, 0, 0)                                   # value², frame, element, face
    y = np.empty((chunk, W32.shape[1]), dtype=np.float32)
    for s in range(0, k, chunk):
        c = min(chunk, k - s)
        yc = np.matmul(a32[s:s + c], W32, out=y[:c])
        np.multiply(yc, yc, out=yc)
        parts = yc.reshape(c, 3, ne, 2)
        vm2 = parts[:, 0] + parts[:, 1]                        # (c, ne, 2): von Mises²
        vm2 += parts[:, 2]
        top = vm2.max(axis=0)
        np.maximum(peak_map, top, out=peak_map)
        e, face = np.unravel_index(int(np.argmax(top)), top.shape)
        if top[e, face] > best[0]:
            best = (float(top[e, face]), s + int(np.argmax(vm2[:, e, face])), int(e), int(face))
    return peak_map, best


def _peak(value: float, xy: np.ndarray, index: int, where: str, time: float) -> Peak:
    return Peak(float(value), float(xy[0]), float(xy[1]), int(index), where, float(time))


def superpose(stress: ModalStress, a: np.ndarray, t: np.ndarray,
              chunk: int = CHUNK) -> BedStresses:
    """Peaks of σ(t) = Σ σ_i a_i(t).

    Parameters
    ----------
    stress : ModalStress
        With n modes (already in the run's coordinates, see
        :meth:`ModalStress.transformed`).
    a : ndarray (k, n)
        Modal coordinates [kg^1/2 m].
    t : ndarray (k,)
        Times [s].
    chunk : int
        Frames per block.

    Returns
    -------
    BedStresses
    """
    a = np.asarray(a, dtype=float)
    t = np.asarray(t, dtype=float)
    if t.size == 0:
        raise InputError("the run has no frames: no stresses to recover")
    ne = stress.centres.shape[0]
    W = _von_mises_basis(stress)                               # (n, 3 * ne * 2)
    # the scan in single precision (relative round-off ~1e-7 on σ_vM²), the
    # peaks reported recomputed in double precision where the scan found them
    W32, a32 = W.astype(np.float32), a.astype(np.float32)
    with threadpool_limits(limits=1, user_api="blas"):     # small products: one thread
        peak_map, best = _scan(a32, W32, ne, chunk)
    peak_map = np.sqrt(peak_map.max(axis=1).astype(float))
    _, frame, e, face = best
    value = float(np.linalg.norm(a[frame] @ W.reshape(-1, 3, ne, 2)[:, :, e, face]))
    bed = _peak(value, stress.centres[e], e, FACES[face], t[frame])
    initial = np.sqrt(np.sum((a[0] @ W).reshape(3, ne, 2) ** 2, axis=0))
    e0, f0 = np.unravel_index(int(np.argmax(initial)), initial.shape)
    initial_peak = _peak(initial[e0, f0], stress.centres[e0], e0, FACES[f0], t[0])
    stiff = []
    for st in stress.stiffeners:
        if st.fibres.size == 0:
            sig = (a @ st.axial)[..., None]
            heights = np.zeros(1)
        else:
            sig, heights = st.fibre_stress(a), st.fibres
        mag = np.abs(sig)                                          # (k, ke, f)
        f, e, fib = np.unravel_index(int(np.argmax(mag)), mag.shape)
        stiff.append((st.name, _peak(mag[f, e, fib], st.centres[e], e,
                                     f"fibre {heights[fib]:+.4g} m", t[f])))
    return BedStresses(time=t, peak_map=peak_map, initial=initial, bed=bed,
                       initial_peak=initial_peak, stiffeners=tuple(stiff),
                       centres=stress.centres)


def in_run_coordinates(stress: ModalStress, n_file: int, basis: np.ndarray) -> ModalStress:
    """The modes file's n_file modal stresses in a run's coordinates,
    a_file = basis @ a (basis (N' <= n_file, n))."""
    T = np.zeros((n_file, basis.shape[1]))
    T[:basis.shape[0]] = basis
    return stress.transformed(T)


@dataclass(frozen=True)
class StressVerdict:
    """A part of the bed (the plate, or a stiffener by name) against its
    allowable stress: its peak (von Mises in the plate, |σ| at a
    stiffener's extreme fibres) over the output samples, its place in the
    scene's drawing frame, the allowable [Pa], the reasons (empty: passed)."""

    part: str
    peak: Peak
    allowable: float
    reasons: tuple

    @property
    def passed(self) -> bool:
        return not self.reasons

    @property
    def usage(self) -> float:
        """peak / allowable [1]."""
        return self.peak.value / self.allowable


def stress_verdicts(s: BedStresses, plate: float, stiffeners: float,
                    origin: np.ndarray) -> tuple:
    """The plate's and each stiffener's :class:`StressVerdict` (allowables
    [Pa]; places moved to the drawing frame, whose origin is the bed
    frame's ``origin`` (2,) or (3,))."""
    o = np.asarray(origin, dtype=float)[:2]
    out = []
    for part, p, limit in [("plate", s.bed, plate)] + [(f"stiffener {name!r}", p, stiffeners)
                                                        for name, p in s.stiffeners]:
        p = replace(p, x=p.x + float(o[0]), y=p.y + float(o[1]))
        reasons = ()
        if p.value > limit:
            reasons = (f"stress: peak {p.value / 1e6:.4g} MPa above the allowable "
                       f"{limit / 1e6:.4g} MPa at ({p.x:.4g}, {p.y:.4g}) m, "
                       f"{p.where}, t = {p.time:.4f} s",)
        out.append(StressVerdict(part, p, float(limit), reasons))
    return tuple(out)


def run_stress(results: str | Path, modes_file: str | Path | None = None):
    """The modal stresses in a flexible-bed run's coordinates and the run's
    modal coordinates: (ModalStress, a (k, n), t (k,), ModesData).

    Raises
    ------
    InputError
        A rigid-bed run, a modes file without stresses (older than 1.4: re-run
        ``flexbed modes``), or one that does not match the run.
    """
    from flexbed.analyses.points import find_modes_file
    from flexbed.files.results import read_results

    c = read_results(results)
    bed = c.attrs.get("bed", {})
    if str(bed.get("model", "rigid")) != "flexible":
        raise InputError(f"{c.path}: the run's bed is rigid: it has no stresses (run with "
                         f"[bed] model = \"flexible\")")
    data, path = find_modes_file(c.path, bed, modes_file)
    if data.stress is None:
        raise InputError(f"{path}: the modes file holds no stresses (schema older than 1.4); "
                         f"re-run 'flexbed modes --force'")
    n = int(bed.get("n_modes", 0))
    basis = c.datasets.get("modal/basis")
    basis = np.eye(n) if basis is None else np.asarray(basis, dtype=float)
    if basis.shape[0] > data.n_modes or basis.shape[1] != n:
        raise InputError(f"{c.path}: the run's {n} modal coordinates draw on "
                         f"{basis.shape[0]} modes, {path} holds {data.n_modes}; re-run "
                         f"'flexbed modes'")
    a = np.asarray(c.get("modal/coordinates"), dtype=float)[:, :n]
    t = np.asarray(c.get("time"), dtype=float)
    return in_run_coordinates(data.stress, data.n_modes, basis), a, t, data


def bed_stresses_of_run(results: str | Path, modes_file: str | Path | None = None
                        ) -> BedStresses:
    """:func:`superpose` over a results file (see :func:`run_stress`)."""
    stress, a, t, _ = run_stress(results, modes_file)
    return superpose(stress, a, t)

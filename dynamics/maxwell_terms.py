"""Elastomer mounts in time runs: generalised Maxwell terms as internal states.

A mount direction r with a Maxwell series (fitted to its elastomer table by
:func:`flexbed.dynamics.frequency.maxwell.fit_maxwell`) carries, beside its
law (linear: ``k d + c ḋ``, where k = k∞ is the relaxed stiffness), one
term per relaxation time τ_i: a spring k_i in series with a dashpot
k_i τ_i, whose internal state z_i is the deflection at the junction
(the spring's stretch is d − z_i):

    f_r = k d + c ḋ + Σ_i k_i (d − z_i),       ż_i = (d − z_i) / τ_i,

d the mount's deflection along its axis. Under ``e^{iωt}`` this is
``K(ω) = k + Σ_i k_i iωτ_i / (1 + iωτ_i)`` (+ iωc), the fitted series. The
states sit after the positions and rates in y (:mod:`flexbed.dynamics.layout`),
one per term with k_i > 0; the compiled right-hand side adds the forces
to the mount's (results, powers, the bodies) and writes the rates
(:mod:`flexbed.dynamics.kernel`).

**Statics.** At rest ż_i = 0, so z_i = d: the terms carry no force and
the static stiffness is k∞ = k, the law's. The static solver evaluates the
right-hand side with the terms *relaxed* (:func:`relaxed`: the kernel
takes z_i = d whatever y holds), and a state at rest gets z_i = d
(:func:`relax_states`).
"""

from __future__ import annotations

import contextlib
from dataclasses import dataclass

import numpy as np

from .errors import SceneError

__all__ = ["MaxwellSeries", "check_maxwell", "maxwell_tables", "relaxed", "relax_states"]


@dataclass(frozen=True, slots=True)
class MaxwellSeries:
    """The Maxwell terms of one mount, per direction.

    mount : str — the mount's name; tau : (N,) — relaxation times [s] > 0;
    k : (3, N) — each term's spring per direction [N/m] ≥ 0 (0: no term).
    """

    mount: str
    tau: np.ndarray
    k: np.ndarray

    def __post_init__(self):
        where = f"mount {self.mount!r}: maxwell"
        tau = np.array(self.tau, dtype=float).reshape(-1)
        k = np.array(self.k, dtype=float)
        if k.shape != (3, tau.size):
            raise SceneError(f"{where}: k has shape {k.shape}, expected (3, {tau.size})")
        if not np.all(np.isfinite(tau) & (tau > 0)):
            raise SceneError(f"{where}: tau = {tau.tolist()} must be finite and > 0 s")
        if not np.all(np.isfinite(k) & (k >= 0)):
            raise SceneError(f"{where}: k = {k.tolist()} must be finite and >= 0 N/m")
        tau.setflags(write=False)
        k.setflags(write=False)
        object.__setattr__(self, "tau", tau)
        object.__setattr__(self, "k", k)

    @property
    def n_states(self) -> int:
        """Terms with k_i > 0 (one internal state each)."""
        return int(np.count_nonzero(self.k))


def check_maxwell(maxwell, mount_names: list) -> tuple:
    """``maxwell`` as a tuple of MaxwellSeries, at most one per mount, each
    naming a mount of ``mount_names``."""
    out = tuple(maxwell)
    seen = set()
    for i, s in enumerate(out):
        if not isinstance(s, MaxwellSeries):
            raise SceneError(f"maxwell[{i}] = {s!r} is not a MaxwellSeries")
        if s.mount not in mount_names:
            raise SceneError(f"maxwell[{i}]: mount {s.mount!r} is not a mount")
        if s.mount in seen:
            raise SceneError(f"mount {s.mount!r}: two Maxwell series")
        seen.add(s.mount)
    return out


def maxwell_tables(maxwell: tuple, mount_names: list, z0: int) -> dict:
    """The kernel's tables of the terms, sorted by (mount, direction) row:
    ``mx_ints`` (nt, 2) the row 3 m + direction and the state's offset in y
    (from ``z0``, in that order); ``mx_k`` (nt, 2) k_i [N/m] and 1/τ_i
    [1/s]; ``w_relax`` (1,) 0 (1: relaxed, :func:`relaxed`); the work array
    ``w_mx`` (3M, 2), no rows without terms (then the mount loop skips them)."""
    rows = []
    for s in maxwell:
        m = mount_names.index(s.mount)
        for d in range(3):
            for i in range(s.tau.size):
                if s.k[d, i] > 0.0:
                    rows.append((3 * m + d, s.k[d, i], 1.0 / s.tau[i]))
    rows.sort(key=lambda r: r[0])          # stable: a row's terms keep their order
    ints = np.zeros((len(rows), 2), dtype=np.int64)
    kt = np.zeros((len(rows), 2))
    for j, (row, k, rate) in enumerate(rows):
        ints[j] = (row, z0 + j)
        kt[j] = (k, rate)
    return dict(mx_ints=ints, mx_k=kt, w_relax=np.zeros(1),
                w_mx=np.zeros((3 * len(mount_names) if rows else 0, 2)))


@contextlib.contextmanager
def relaxed(system):
    """Within: the system's Maxwell terms are relaxed (z_i = d: no force, no
    rate), whatever the state holds: the static equilibrium and the
    stiffness at rest. Nothing happens without terms."""
    w = system.data.w_relax
    if not w.size or system.layout.n_internal == 0:
        yield
        return
    before = w[0]
    w[0] = 1.0
    try:
        yield
    finally:
        w[0] = before


def relax_states(system, y: np.ndarray) -> np.ndarray:
    """``y`` (ny,) with every Maxwell state at its relaxed value z_i = d
    (the mount's deflection in the configuration of y); y itself when the
    system has none."""
    lay = system.layout
    if lay.n_internal == 0:
        return y
    y = np.array(y, dtype=float)
    with relaxed(system):
        system.rhs_into(0.0, y, np.empty(y.size))
        dx = np.array(system.data.w_dx).reshape(-1)
    ints = system.data.mx_ints
    y[ints[:, 1]] = dx[ints[:, 0]]
    return y

"""Elastomer mounts in the frequency domain: the exact complex stiffness.

An elastomer direction's force under ``e^{iωt}`` is ``k(f)(1 + iη(f)) Δx``
(plus its viscous ``c Δẋ``), where the linearisation
(:mod:`flexbed.dynamics.frequency.mounted`) used the law's static ``k``.
The mount force's generalized force is ``−D_vᵀ f`` (virtual work over the
rate Jacobian ``D_v``), so a direction's spring puts ``k D_vᵀ D`` into
``K``; the preload's geometric stiffness depends on the static force alone.
Hence, exactly (the preload held, as the static equilibrium with ``k``
gives it),

    G(ω) = K − ω² M + iω C + Σ_r Δk_r(ω) D_v,rᵀ D_r,
    Δk_r(ω) = k_r(f)(1 + iη_r(f)) − k_r,

and a mount axis's force is ``F_q u + iω F_v u + Δk_r D_r u``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["ElastomerTable", "ComplexStiffness", "complex_stiffness"]


@dataclass(frozen=True)
class ElastomerTable:
    """One mount's elastomer, per direction.

    k_static : (3,) — the law's stiffness [N/m] (statics, preloads);
    frequency : (nf,) — strictly increasing [Hz] (> 0);
    stiffness : (nf, 3) — dynamic stiffness [N/m] (> 0);
    loss_factor : (nf, 3) — hysteretic loss factor η [-] (>= 0).

    The stiffness is interpolated log-log in frequency, the loss factor
    linearly in log f (it may be 0); both are held constant outside the
    table. A single row is a constant (frequency-independent) elastomer.
    """

    k_static: np.ndarray
    frequency: np.ndarray
    stiffness: np.ndarray
    loss_factor: np.ndarray

    def __post_init__(self):
        for name in ("k_static", "frequency", "stiffness", "loss_factor"):
            a = np.array(getattr(self, name), dtype=float)
            a.setflags(write=False)
            object.__setattr__(self, name, a)
        assert self.stiffness.shape == self.loss_factor.shape == (self.frequency.size, 3)
        assert np.all(np.diff(self.frequency) > 0) and np.all(self.stiffness > 0)

    def at(self, f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(k (m, 3) [N/m], η (m, 3))`` at the frequencies ``f`` (m,) [Hz] > 0."""
        lf = np.log(np.asarray(f, dtype=float).reshape(-1))
        lt = np.log(self.frequency)
        k = np.stack([np.exp(np.interp(lf, lt, np.log(self.stiffness[:, d])))
                      for d in range(3)], axis=1)
        eta = np.stack([np.interp(lf, lt, self.loss_factor[:, d]) for d in range(3)], axis=1)
        return k, eta

    def complex(self, f: np.ndarray) -> np.ndarray:
        """``k(f)(1 + iη(f))`` (m, 3) complex [N/m]."""
        k, eta = self.at(f)
        return k * (1.0 + 1j * eta)


@dataclass(frozen=True)
class ComplexStiffness:
    """The elastomer directions of a mounted system, compiled.

    rows : (r,) int — mount-axis rows (3 mount + direction, scene order);
    D, Dv : (r, n) — their deflection and rate Jacobians;
    tables : tuple of (mount index, ElastomerTable) per elastomer mount;
    base_axes : (3, r) — each row's axis in the inertial frame at the
    equilibrium, signed as its force acts on the base (0 for a mount that
    does not touch the base);
    n_mounts : int — mounts in the scene.
    """

    rows: np.ndarray
    D: np.ndarray
    Dv: np.ndarray
    tables: tuple
    base_axes: np.ndarray
    n_mounts: int

    def delta(self, w: np.ndarray) -> np.ndarray:
        """``Δk_r(ω) = k_r(f)(1 + iη_r(f)) − k_r`` (k, r) complex [N/m] at ω (k,) [rad/s]."""
        f = np.asarray(w, dtype=float).reshape(-1) / (2.0 * np.pi)
        return np.concatenate([t.complex(f) - t.k_static[None, :] for _, t in self.tables],
                              axis=1)

    def added(self, w: np.ndarray) -> np.ndarray:
        """``Σ_r Δk_r(ω) D_v,rᵀ D_r`` (k, n, n) complex [N/m, …]."""
        dk = self.delta(w)
        return np.einsum("ri,kr,rj->kij", self.Dv, dk, self.D)

    def force_rows(self, w: np.ndarray, u: np.ndarray) -> np.ndarray:
        """The elastomer's extra force ``Δk_r D_r u`` (k, r) along its rows for
        relative motions u (k, n) complex at ω (k,) [rad/s]."""
        return self.delta(w) * (u @ self.D.T)

    def force_map(self) -> np.ndarray:
        """(3 n_mounts + 3, r): how the mount-axis forces, then the total
        force on the base (the rows of
        :func:`flexbed.dynamics.frequency.frf.mount_outputs`), take the
        extra forces of :meth:`force_rows`."""
        out = np.zeros((3 * self.n_mounts + 3, self.rows.size))
        out[self.rows, np.arange(self.rows.size)] = 1.0
        out[3 * self.n_mounts:] = self.base_axes
        return out


def complex_stiffness(tables: dict, D: np.ndarray, Dv: np.ndarray, axes: np.ndarray,
                      base_sign: np.ndarray) -> ComplexStiffness | None:
    """Compile ``tables`` {mount index: ElastomerTable} against a mounted
    system's D and Dv (3 n_mounts, n), the mounts' axes in the inertial
    frame at the equilibrium ``axes`` (n_mounts, 3, 3) (rows u1, u2, u3)
    and ``base_sign`` (n_mounts,): +1 when the base is body i, −1 when it
    is body j, else 0. None when there are no tables."""
    if not tables:
        return None
    order = sorted(tables)
    rows = np.array([3 * m + d for m in order for d in range(3)], dtype=int)
    base = np.array([base_sign[m] * axes[m, d] for m in order for d in range(3)]).T
    return ComplexStiffness(rows, D[rows].copy(), Dv[rows].copy(),
                            tuple((m, tables[m]) for m in order), base, axes.shape[0])

"""Modes of a mounted system with elastomer mounts: each mode with the
elastomers' stiffness at its own frequency.

An elastomer's complex stiffness depends on frequency, so the modes are
those of a nonlinear eigenproblem. Mode j is found by fixed-point
iteration on its natural frequency f: the system at f has

    K(f) = K + Σ_r Re Δk_r(f) D_v,rᵀ D_r,
    C(f) = C + Σ_r Im Δk_r(f) / ω D_v,rᵀ D_r     (ω = 2π f),

(the hysteretic part as the viscous damper that dissipates as much per
cycle at f), its modes are solved (:func:`~flexbed.dynamics.frequency.modal.solve_modes`),
mode j is followed by its shape (largest |φ_prevᴴ M φ| / (‖φ_prev‖_M ‖φ‖_M)),
and f is replaced by its frequency until it moves by less than
:data:`FREQUENCY_TOL` relative. At the fixed point a single elastomer of
loss factor η on a mass has ωₙ² = k(fₙ)/m and ζ = η/2 exactly.

The undamped frequencies, shapes and effective masses are found alike on
K(f) alone, each at its own frequency; their sum over the modes is then the
moving mass only to the extent that k(f) varies between the modes'
frequencies. Overdamped rates are the static-stiffness system's.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .modal import Modes, solve_modes
from .mounted import MountedSystem

__all__ = ["elastomer_modes", "at_frequency", "FREQUENCY_TOL", "MAX_ITERATIONS"]

#: relative change of a mode's frequency that ends its iteration
FREQUENCY_TOL = 1e-12
#: iterations per mode before giving up (RuntimeError)
MAX_ITERATIONS = 100


def at_frequency(ms: MountedSystem, f: float, damped: bool = True) -> MountedSystem:
    """``ms`` with its elastomers' stiffness (and, if ``damped``, their
    hysteretic damping as a viscous equivalent) at the frequency f [Hz] > 0."""
    es = ms.elastomer
    w = 2.0 * np.pi * f
    dk = es.delta(np.array([w]))[0]                                      # (r,)
    K = ms.K + es.Dv.T @ (dk.real[:, None] * es.D)
    C = ms.C + es.Dv.T @ ((dk.imag / w)[:, None] * es.D) if damped else ms.C
    k_t = ms.k_tangent.copy()
    k_t[es.rows] += dk.real
    return replace(ms, K=K, C=C, k_tangent=k_t, elastomer=None)


def _follow(ms: MountedSystem, f0: float, phi0: np.ndarray, damped: bool, pick):
    """Iterate one mode from f0 [Hz] and shape phi0 (n,): (modes, index)."""
    f, phi = f0, phi0
    for _ in range(MAX_ITERATIONS):
        md = solve_modes(at_frequency(ms, f, damped))
        freq, shapes = pick(md)
        Mp = shapes @ ms.M.T                                              # (m, n): M φ
        mac = np.abs(Mp.conj() @ phi) / np.sqrt(
            np.abs(np.einsum("mi,mi->m", shapes.conj(), Mp)) * abs(phi.conj() @ ms.M @ phi))
        j = int(np.argmax(mac))
        if abs(freq[j] - f) <= FREQUENCY_TOL * freq[j]:
            return md, j
        f, phi = float(freq[j]), shapes[j]
    raise RuntimeError(f"an elastomer mode near {f:.6g} Hz: its frequency did not settle "
                       f"in {MAX_ITERATIONS} iterations")


def elastomer_modes(ms: MountedSystem) -> Modes:
    """:func:`~flexbed.dynamics.frequency.modal.solve_modes` of ``ms`` with its
    elastomers at each mode's own frequency (``ms`` without elastomers: the
    plain solution)."""
    base = solve_modes(ms)
    if ms.elastomer is None:
        return base
    damped_rows, undamped_rows = [], []
    for j in range(base.frequency.size):
        md, i = _follow(ms, float(base.frequency[j]), base.shapes[j], True,
                        lambda m: (m.frequency, m.shapes))
        damped_rows.append((md, i))
    for k in range(base.undamped_frequency.size):
        md, i = _follow(ms, float(base.undamped_frequency[k]), base.undamped_shapes[k] + 0j,
                        False, lambda m: (m.undamped_frequency, m.undamped_shapes + 0j))
        undamped_rows.append((md, i))

    def take(rows, name):
        return np.array([getattr(md, name)[i] for md, i in rows])

    order = np.argsort(take(damped_rows, "frequency"), kind="stable")
    damped_rows = [damped_rows[i] for i in order]
    order = np.argsort(take(undamped_rows, "undamped_frequency"), kind="stable")
    undamped_rows = [undamped_rows[i] for i in order]
    return Modes(frequency=take(damped_rows, "frequency"),
                 damping_ratio=take(damped_rows, "damping_ratio"),
                 damped_frequency=take(damped_rows, "damped_frequency"),
                 shapes=take(damped_rows, "shapes"),
                 undamped_frequency=take(undamped_rows, "undamped_frequency"),
                 undamped_shapes=take(undamped_rows, "undamped_shapes"),
                 energy=take(damped_rows, "energy"),
                 strain_mounts=take(damped_rows, "strain_mounts"),
                 strain_elastic=take(damped_rows, "strain_elastic"),
                 effective_mass=take(undamped_rows, "effective_mass"),
                 moving_mass=base.moving_mass, overdamped_rates=base.overdamped_rates)

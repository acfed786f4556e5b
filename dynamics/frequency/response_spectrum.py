"""The response-spectrum method: modal peaks from a design spectrum and their
combinations (NRL sum, SRSS, CQC, ABS).

The mounted system about its equilibrium, base held, moved by a base
acceleration d̈ along axis d, in the relative coordinates u = q − ι_d d
(:mod:`flexbed.dynamics.frequency.mounted`):

    M ü + C u̇ + K u = −M ι_d d̈.

With the undamped modes φ_k (rows, unit modal mass ψ_kᴴ M φ_l = δ_kl,
:class:`~flexbed.dynamics.frequency.modal.Modes`) u = Σ φ_k η_k and each
modal coordinate is an oscillator moved by −Γ_k d̈,

    η̈_k + 2ζω_k η̇_k + ω_k² η_k = −Γ_k d̈,   Γ_k = ψ_kᴴ M ι_d,

so its peak is |Γ_k| S(f_k)/ω_k², S the design spectrum's
pseudo-acceleration at ζ. Γ comes from expanding ι_d in the complete set
of modes, ι_d = Σ_k Γ_k φ_k (one solve with Φᵀ: the left vectors ψ are
not needed). Mode k's peak contribution to an output r = O u (mount
deflections and forces, a point's displacement relative to the base, the
mounts' force on the base) is O φ_k Γ_k S_k/ω_k²; to a point's absolute
acceleration, its pseudo-acceleration O φ_k Γ_k S_k (the modes' sum of
φ_k Γ_k is ι_d: a rigid item takes the zero-period acceleration). The
modal effective mass is m_k = Γ_k ι_dᵀ M φ_k; Σ_k m_k is the moving mass.

Combinations of the modal peaks r_k of one output (:func:`combine`):

- ``abs``: Σ |r_k|, an upper bound of the peak whatever the phases;
- ``srss``: √(Σ r_k²);
- ``cqc``: √(Σ_i Σ_j ρ_ij r_i r_j), with Der Kiureghian's (1981)
  correlation for equal damping ζ, β = ω_j/ω_i,
  ρ_ij = 8ζ² (1 + β) β^{3/2} / ((1 − β²)² + 4ζ² β (1 + β)²);
- ``nrl``: the Naval Research Laboratory sum of DDAM (NRL-1396): the
  largest modal peak plus the SRSS of the rest, |r|_max + √(Σ r_k² − r_max²),
  after closely spaced modes are grouped: modes sorted by frequency, a group
  opens at a mode and takes every following mode whose frequency is within
  ``gap`` (10 %) of the group's first; a group's peak is the absolute sum of
  its modes' peaks (NRL-1396 practice for modes within 10 %).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["RULES", "CLOSE_MODES", "ModalPeaks", "participation", "modal_peaks", "combine",
           "cqc_correlation", "nrl_groups"]

#: the combination rules, in the order they are reported
RULES = ("nrl", "srss", "cqc", "abs")
#: NRL: modes whose frequency is within this fraction of a group's first
#: mode are summed absolutely into that group
CLOSE_MODES = 0.10


@dataclass(frozen=True)
class ModalPeaks:
    """Each mode's peak response to a design spectrum along one axis.

    frequency : (m,) [Hz]; participation : (m,) Γ_k [kg^1/2];
    effective_mass : (m,) [kg]; spectral : (m,) S(f_k) [m/s²];
    displacement : (m, n) φ_k Γ_k S_k/ω_k² [m, rad, kg^1/2 m];
    acceleration : (m, n) φ_k Γ_k S_k [m/s², rad/s², …].
    """

    frequency: np.ndarray
    participation: np.ndarray
    effective_mass: np.ndarray
    spectral: np.ndarray
    displacement: np.ndarray
    acceleration: np.ndarray


def participation(phi: np.ndarray, iota: np.ndarray) -> np.ndarray:
    """Γ (n, 3) [kg^1/2] of the complete set of modes φ (n, n) (rows, unit
    modal mass) for base translations ι (n, 3): the solution of
    ``Φᵀ Γ = ι``."""
    return np.linalg.solve(phi.T, iota)


def modal_peaks(phi: np.ndarray, frequency: np.ndarray, M: np.ndarray, iota_d: np.ndarray,
                gamma_d: np.ndarray, spectral: np.ndarray) -> ModalPeaks:
    """The modal peaks for one axis.

    Parameters
    ----------
    phi : (m, n) undamped modes (rows, unit modal mass)
    frequency : (m,) their frequencies [Hz], > 0
    M : (n, n) mass matrix
    iota_d : (n,) the base translation along the axis
    gamma_d : (m,) their participation factors Γ_k (:func:`participation`)
    spectral : (m,) the spectrum's pseudo-acceleration at each f_k [m/s²]
    """
    w2 = (2.0 * np.pi * frequency) ** 2
    scale = gamma_d * spectral
    acc = phi * scale[:, None]
    return ModalPeaks(frequency=frequency, participation=gamma_d,
                      effective_mass=gamma_d * (phi @ (M @ iota_d)), spectral=spectral,
                      displacement=acc / w2[:, None], acceleration=acc)


def cqc_correlation(frequency: np.ndarray, zeta: float) -> np.ndarray:
    """ρ (m, m) of Der Kiureghian's CQC for modes at ``frequency`` (m,) [Hz]
    with equal damping ζ (module docstring); the identity for ζ = 0."""
    b = frequency[None, :] / frequency[:, None]
    num = 8.0 * zeta ** 2 * (1.0 + b) * b ** 1.5
    den = (1.0 - b ** 2) ** 2 + 4.0 * zeta ** 2 * b * (1.0 + b) ** 2
    rho = np.divide(num, den, out=np.zeros_like(b), where=den > 0.0)
    np.fill_diagonal(rho, 1.0)
    return rho


def nrl_groups(frequency: np.ndarray, gap: float = CLOSE_MODES) -> np.ndarray:
    """(m,) the group of each mode (0, 1, …) for the NRL sum: a group opens
    at the lowest mode not yet grouped and takes every mode whose frequency
    is at most (1 + gap) times that mode's."""
    order = np.argsort(frequency, kind="stable")
    group = np.empty(frequency.size, dtype=int)
    g, first = -1, -np.inf
    for k in order:
        if frequency[k] > (1.0 + gap) * first:
            g, first = g + 1, frequency[k]
        group[k] = g
    return group


def combine(r: np.ndarray, frequency: np.ndarray, zeta: float, rule: str,
            gap: float = CLOSE_MODES) -> np.ndarray:
    """Combined peak (k,) of modal peaks r (m, k) (mode k's signed
    contribution to each of k outputs) by ``rule`` (one of :data:`RULES`)."""
    if rule == "abs":
        return np.abs(r).sum(axis=0)
    if rule == "srss":
        return np.sqrt(np.sum(r * r, axis=0))
    if rule == "cqc":
        rho = cqc_correlation(frequency, zeta)
        return np.sqrt(np.maximum(np.einsum("ik,ij,jk->k", r, rho, r), 0.0))
    if rule == "nrl":
        group = nrl_groups(frequency, gap)
        g = np.zeros((group.max() + 1 if group.size else 0, r.shape[1]))
        np.add.at(g, group, np.abs(r))
        if not g.size:
            return np.zeros(r.shape[1])
        top = g.max(axis=0)
        return top + np.sqrt(np.maximum(np.sum(g * g, axis=0) - top * top, 0.0))
    raise ValueError(f"rule {rule!r} is not one of {', '.join(RULES)}")

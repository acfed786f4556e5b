"""The constants of Radau IIA of order 5, the compiled ``radau`` stepper's.

Hairer & Wanner's RADAU5 (Hairer & Wanner, *Solving Ordinary Differential
Equations II*, 2nd ed., Springer 1996, IV.5 and IV.8), in the form SciPy's
``Radau`` uses: the closed forms in √6 and 3^(1/3) written as SciPy writes
them (so evaluated by the same operations) and the same decimal literals for
the eigenvectors T and their inverse, hence the same float64 values bit for
bit (``tests/test_method_coefficients.py`` compares them with SciPy's). They
are flexbed's own data because SciPy keeps its copy in a private module
(``scipy.integrate._ivp.radau``) that may change in any release, and
importing it runs ``scipy.integrate``'s ``__init__`` (about 0.3 s of CPU).

The method's matrix A has one real eigenvalue and a complex pair; its
inverse is A⁻¹ = T Λ T⁻¹, Λ = [[μ_r, 0, 0], [0, α, −β], [0, β, α]] with
μ_c = α − iβ, so that the Newton iteration solves one real system in
μ_r/h I − J and one complex one in μ_c/h I − J. The stepper combines the
stages with T⁻¹'s first row (:attr:`RadauIIA5.TI_REAL`) and its second and
third rows as one complex row (:attr:`RadauIIA5.TI_COMPLEX`).

:data:`RADAU` holds them read-only, checked when this module is imported
(:class:`RadauIIA5`): shapes, C_i = Σ_j A_ij, the quadrature conditions
Σ_i b_i c_i^(k−1) = 1/k for k = 1 … 5 (b = A's last row: the method is
stiffly accurate), T T⁻¹ = I and T⁻¹ A⁻¹ T = Λ, an error estimate
h f_0 + Σ_i E_i Z_i that vanishes to O(h⁴), and a dense output that passes
through the stages.

Numba compiles these values into the stepper as constants: a change here
reaches the cached stepper through the stamp of
:mod:`flexbed.dynamics.jitcache`, which covers this file.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .tables import freeze_arrays

__all__ = ["RadauIIA5", "RADAU", "S6"]

S6 = 6 ** 0.5


@dataclass(frozen=True, slots=True)
class RadauIIA5:
    """The constants of Radau IIA of order 5 (3 stages).

    Arrays are copied, made read-only and checked (see the module
    docstring); a violation raises ValueError naming the entry.

    Parameters
    ----------
    A : (3, 3) float64
        The method's matrix (the stepper works with T, T⁻¹ and μ instead).
    C : (3,) float64
        Stage times as fractions of the step, C_i = Σ_j A_ij, C_2 = 1.
    E : (3,) float64
        Weights of the embedded 3rd-order error estimate over the stages
        Z_i = z(t + C_i h) − z(t): err = f(t, z) + Σ_i E_i Z_i / h, then
        filtered by (μ_r/h I − J)⁻¹.
    P : (3, 3) float64
        Collocation polynomial: z(t + x h) = z(t) + Σ_m Q_m x^(m+1), Q = Zᵀ P.
    T, TI : (3, 3) float64
        Eigenvectors of A⁻¹ (real form) and their inverse.
    MU_REAL : float
        Real eigenvalue μ_r of A⁻¹.
    MU_COMPLEX : complex
        Complex eigenvalue μ_c = α − iβ of A⁻¹ (its conjugate is the other).
    """

    A: np.ndarray
    C: np.ndarray
    E: np.ndarray
    P: np.ndarray
    T: np.ndarray
    TI: np.ndarray
    MU_REAL: float
    MU_COMPLEX: complex

    def __post_init__(self):
        freeze_arrays(self, "Radau", {"A": (3, 3), "C": (3,), "E": (3,), "P": (3, 3),
                                      "T": (3, 3), "TI": (3, 3)})
        object.__setattr__(self, "MU_REAL", float(self.MU_REAL))
        object.__setattr__(self, "MU_COMPLEX", complex(self.MU_COMPLEX))
        A, C, E, P, T, TI = self.A, self.C, self.E, self.P, self.T, self.TI
        _close("C", A.sum(axis=1), C, 1e-14)
        b = A[2]
        _close("A's last row", [b @ C ** (k - 1) for k in range(1, 6)],
               [1.0 / k for k in range(1, 6)], 1e-14)
        _close("T TI", T @ TI, np.eye(3), 1e-13)
        mu_r, mu_c = self.MU_REAL, self.MU_COMPLEX
        lam = [[mu_r, 0.0, 0.0], [0.0, mu_c.real, -mu_c.imag], [0.0, mu_c.imag, mu_c.real]]
        _close("TI A⁻¹ T (MU_REAL, MU_COMPLEX)", TI @ np.linalg.inv(A) @ T, lam, 1e-12)
        _close("E (h f + Σ E_i Z_i = O(h⁴))", [1.0 + E @ C, E @ C ** 2, E @ C ** 3],
               [0.0, 0.0, 0.0], 1e-13 * np.abs(E).sum())
        _close("P (the polynomial through the stages)",
               P @ (C[:, None] ** np.arange(1, 4)).T, np.eye(3), 1e-13)

    @property
    def TI_REAL(self) -> np.ndarray:
        """(3,) float64: T⁻¹'s first row (the real system's combination)."""
        return self.TI[0]

    @property
    def TI_COMPLEX(self) -> np.ndarray:
        """(3,) complex128: T⁻¹'s second and third rows as TI[1] + i TI[2]."""
        return self.TI[1] + 1j * self.TI[2]


def _close(what: str, value, expected, tol: float) -> None:
    """Raise ValueError unless value equals expected within tol (absolute)."""
    error = float(np.max(np.abs(np.asarray(value) - np.asarray(expected))))
    if not error <= tol:
        raise ValueError(f"Radau {what}: off by {error:.3g} (more than {tol:.3g})")


def _constants() -> RadauIIA5:
    a = np.array([[(88 - 7 * S6) / 360, (296 - 169 * S6) / 1800, (-2 + 3 * S6) / 225],
                  [(296 + 169 * S6) / 1800, (88 + 7 * S6) / 360, (-2 - 3 * S6) / 225],
                  [(16 - S6) / 36, (16 + S6) / 36, 1 / 9]])
    c = np.array([(4 - S6) / 10, (4 + S6) / 10, 1])
    e = np.array([-13 - 7 * S6, -13 + 7 * S6, -1]) / 3
    p = np.array([
        [13/3 + 7*S6/3, -23/3 - 22*S6/3, 10/3 + 5 * S6],
        [13/3 - 7*S6/3, -23/3 + 22*S6/3, 10/3 - 5 * S6],
        [1/3, -8/3, 10/3]])
    t = np.array([
        [0.09443876248897524, -0.14125529502095421, 0.03002919410514742],
        [0.25021312296533332, 0.20412935229379994, -0.38294211275726192],
        [1, 1, 0]])
    ti = np.array([
        [4.17871859155190428, 0.32768282076106237, 0.52337644549944951],
        [-4.17871859155190428, -0.32768282076106237, 0.47662355450055044],
        [0.50287263494578682, -2.57192694985560522, 0.59603920482822492]])
    mu_real = 3 + 3 ** (2 / 3) - 3 ** (1 / 3)
    mu_complex = (3 + 0.5 * (3 ** (1 / 3) - 3 ** (2 / 3))
                  - 0.5j * (3 ** (5 / 6) + 3 ** (7 / 6)))
    return RadauIIA5(A=a, C=c, E=e, P=p, T=t, TI=ti, MU_REAL=mu_real, MU_COMPLEX=mu_complex)


#: Radau IIA(5)'s constants, read-only and checked
RADAU = _constants()

"""Two-node beam elements in one bending plane, on (w_a, φ_a, w_b, φ_b):
the deflection w [m] and the section's rotation φ [rad] (the slope dw/ds
where the section stays normal) at the ends of an element of length L.

* :func:`hermite` — Euler–Bernoulli: cubic w whose slope is φ, bending
  energy ½ EI ∫ (w'')² ds; the section stays normal to the axis (no shear
  strain).
* :func:`timoshenko` — Timoshenko: w and φ linear, bending
  ½ EI ∫ (φ')² ds, shear ½ κGA ∫ (w' − φ)² ds integrated at the mid-point
  (the shear strain tied there, as the MITC4 shell ties its transverse
  shear at the edge mid-points, so the element does not lock when κGA L²
  ≫ EI).

Pure NumPy.
"""

from __future__ import annotations

import numpy as np


def hermite(EI: float, L: float) -> np.ndarray:
    """Euler–Bernoulli stiffness (4, 4) [N/m, N, N m] of flexural rigidity
    EI [N m²] over length L [m]."""
    return EI / L ** 3 * np.array([[12, 6 * L, -12, 6 * L],
                                   [6 * L, 4 * L * L, -6 * L, 2 * L * L],
                                   [-12, -6 * L, 12, -6 * L],
                                   [6 * L, 2 * L * L, -6 * L, 4 * L * L]])


def timoshenko(EI: float, kGA: float, L: float) -> np.ndarray:
    """Timoshenko stiffness (4, 4) of flexural rigidity EI [N m²] and shear
    rigidity κGA [N] over length L [m], shear at the mid-point.

    >>> K = timoshenko(2.0, 5.0, 0.5)
    >>> bool(np.allclose(K @ [1.0, 0.0, 1.0, 0.0], 0))    # translation
    True
    >>> bool(np.allclose(K @ [-0.25, 1.0, 0.25, 1.0], 0))  # rotation, no shear
    True
    """
    bend = np.array([0.0, -1.0, 0.0, 1.0]) / L
    shear = np.array([-1.0 / L, -0.5, 1.0 / L, -0.5])
    return EI * L * np.outer(bend, bend) + kGA * L * np.outer(shear, shear)


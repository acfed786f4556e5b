"""Is a static equilibrium stable? The stiffness at rest, from the one
linearisation (:func:`flexbed.dynamics.linear.model.linearise`).

About the equilibrium the linearised motion of the free coordinates
(bodies' translations and small rotations, modal coordinates; the base is
held) is ``δq̈ = −M⁻¹K δq + …``. With M positive definite, the equilibrium
is unstable when M⁻¹K has a negative eigenvalue λ: that shape grows as
exp(√−λ · t) (a mount of negative stiffness that nothing else outweighs).
The eigenvector's largest component names the body and the direction
(x, y, z [m]; roll, pitch, yaw [rad] about the body axes; or a modal
coordinate [kg^1/2 m]: components of different units compare as they
are, which picks the motion that dominates the shape at the SI scale).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .linear.model import linearise
from .system import System

__all__ = ["Instability", "instability", "DIRECTIONS"]

DIRECTIONS = ("x", "y", "z", "roll", "pitch", "yaw")

#: eigenvalues below −RELATIVE_TOL · max |λ| count as negative (the
#: linearisation's central differences carry errors of ~1e-6 relative)
RELATIVE_TOL = 1e-6


@dataclass(frozen=True)
class Instability:
    """The most negative eigenvalue of M⁻¹K at an equilibrium.

    eigenvalue : float [1/s²] (< 0); rate : float [1/s], √−eigenvalue, the
    growth rate of that shape; body : str; direction : str (x, y, z, roll,
    pitch, yaw, or "modal coordinate k").
    """

    eigenvalue: float
    rate: float
    body: str
    direction: str

    def line(self) -> str:
        """One line for the user."""
        return (f"unstable equilibrium: the stiffness at rest has a negative eigenvalue "
                f"({self.eigenvalue:.4g} 1/s², growing as exp({self.rate:.4g} t)), mostly "
                f"body {self.body!r} in {self.direction}")


def instability(system: System, y_eq: np.ndarray) -> Instability | None:
    """The unstable direction of the equilibrium ``y_eq`` (ny,), or None when
    every eigenvalue of M⁻¹K is ≥ 0 (to the linearisation's accuracy)."""
    lin = linearise(system, y_eq)
    c = lin.coords
    free = np.setdiff1d(np.arange(c.n_pos), c.base_index)      # the base is held
    if free.size == 0:
        return None
    K = -lin.A[c.n_pos:, :c.n_pos][np.ix_(free, free)]        # M⁻¹K (n_free, n_free)
    vals, vecs = np.linalg.eig(K)
    lam = vals.real
    scale = float(np.max(np.abs(lam))) if lam.size else 0.0
    i = int(np.argmin(lam))
    if not (scale > 0 and lam[i] < -RELATIVE_TOL * scale):
        return None
    j = int(free[np.argmax(np.abs(vecs[:, i].real))])
    names = [system.scene.bodies[b].name for b in system.layout.rigid]
    if j < c.base_index.size + 6 * c.n_rigid:
        b, k = divmod(j - c.base_index.size, 6)
        body, direction = names[b], DIRECTIONS[k]
    else:
        m = j - c.base_index.size - 6 * c.n_rigid
        body, direction = _modal_owner(system, m)
    return Instability(float(lam[i]), math.sqrt(-float(lam[i])), body, direction)


def _modal_owner(system: System, m: int) -> tuple[str, str]:
    """(body name, "modal coordinate k") of the m-th modal coordinate."""
    for fc in system.flex_compiled:
        n = fc.eom.n
        if m < n:
            return system.scene.bodies[fc.body].name, f"modal coordinate {m + 1}"
        m -= n
    return "?", f"modal coordinate {m + 1}"

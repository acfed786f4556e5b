"""Is a static equilibrium stable? The stiffness at rest, from the one
right-hand side's linearisation.

About the equilibrium the linearised motion of the free coordinates
(bodies' translations and small rotations, modal coordinates; the base is
held) is ``δq̈ = −M⁻¹K δq + …``. With M positive definite, the equilibrium
is unstable when M⁻¹K has a negative eigenvalue λ: that shape grows as
exp(√−λ · t) (a mount of negative stiffness that nothing else outweighs).
The eigenvector's largest component names the body and the direction
(x, y, z [m]; roll, pitch, yaw [rad] about the body axes; or a modal
coordinate [kg^1/2 m]: components of different units compare as they
are, which picks the motion that dominates the shape at the SI scale).

Two paths, the same criterion (an eigenvalue below −RELATIVE_TOL · max|λ|)
and the same steps of the central differences
(:func:`flexbed.dynamics.linear.model.difference_steps`):

- up to :data:`DENSE_LIMIT` free coordinates of rigid bodies, when the
  statics hand over their exact tangent stiffness at rest (the last
  Newton Jacobian, :attr:`flexbed.dynamics.statics.Equilibrium.jacobian`),
  M⁻¹K from it (M: m I₃ and J per body) and every eigenvalue (dense): no
  second linearisation;
- otherwise up to :data:`DENSE_LIMIT` free coordinates, M⁻¹K from the linearisation
  of the linear model (:func:`flexbed.dynamics.linear.model.linearise`, one
  column at a time) and every eigenvalue (dense);
- above, M⁻¹K = −M⁻¹Kq from the block linearisation
  (:func:`flexbed.dynamics.block_linearisation.linearised`: block-diagonal M
  and its block inverse, block-sparse Kq by colour classes of the mount
  graph, O(N) right-hand sides), max|λ| by Arnoldi iterations (ARPACK,
  the eigenvalue of largest modulus) and the :data:`LEFTMOST_COUNT`
  eigenvalues of smallest real part by Arnoldi iterations too; the most
  negative of those and its eigenvector decide. Kq is not symmetric in
  general (0.02–0.3 % on the tiled scenes), so the inertia of a symmetric
  factorisation would not answer; ARPACK does not need the symmetry.
  Should the iterations not converge, the dense path answers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.sparse.linalg import ArpackNoConvergence, eigs

from .block_linearisation import block_inverse, linearised
from .jacobian import mount_graph
from .linear.model import Coordinates, difference_steps, linearise
from .maxwell_terms import relaxed
from .system import System

__all__ = ["Instability", "instability", "DIRECTIONS", "DENSE_LIMIT", "LEFTMOST_COUNT"]

DIRECTIONS = ("x", "y", "z", "roll", "pitch", "yaw")

#: eigenvalues below −RELATIVE_TOL · max |λ| count as negative (the
#: linearisation's central differences carry errors of ~1e-6 relative)
RELATIVE_TOL = 1e-6
#: up to this many free coordinates (6 per body, then the modal ones) the
#: dense path answers (the reference scene: 18 rigid, 18 + modes flexible)
DENSE_LIMIT = 100
#: how many eigenvalues of smallest real part the sparse path finds
LEFTMOST_COUNT = 4
#: ARPACK's relative tolerance of the eigenvalues of the sparse path
_ARNOLDI_TOL = 1e-12


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


def instability(system: System, y_eq: np.ndarray, dense_limit: int = DENSE_LIMIT,
                jacobian=None) -> Instability | None:
    """The unstable direction of the equilibrium ``y_eq`` (ny,), or None when
    every eigenvalue of M⁻¹K is ≥ 0 (to the linearisation's accuracy).

    ``dense_limit``: the most free coordinates answered by the dense path
    (above it, the sparse path of the module docstring). ``jacobian``: the
    statics' exact tangent stiffness at ``y_eq``
    (:attr:`flexbed.dynamics.statics.Equilibrium.jacobian`), which the
    dense path of a scene of rigid bodies takes as K (−∂(M v̇)/∂q: the
    same matrix as the linearisation's, to its central differences'
    accuracy) instead of linearising again. Elastomer mounts' Maxwell
    terms are relaxed (the static stiffness k∞ = k:
    :mod:`flexbed.dynamics.maxwell_terms`)."""
    y_eq = np.asarray(y_eq, dtype=float)
    n_free = 6 * system.n_rigid
    if (jacobian is not None and not system.layout.n_modal and 0 < n_free <= dense_limit
            and jacobian.shape == (n_free, n_free)):
        return _from_tangent(system, jacobian)
    with relaxed(system):
        if mount_graph(system, True).n > dense_limit:
            found = _sparse(system, y_eq)
            if found is not _UNANSWERED:
                return found
        return _dense(system, y_eq)


def _dense(system: System, y_eq: np.ndarray) -> Instability | None:
    """Every eigenvalue of M⁻¹K from :func:`linearise` (n_free³)."""
    lin = linearise(system, y_eq)
    c = lin.coords
    free = np.setdiff1d(np.arange(c.n_pos), c.base_index)      # the base is held
    if free.size == 0:
        return None
    K = -lin.A[c.n_pos:, :c.n_pos][np.ix_(free, free)]        # M⁻¹K (n_free, n_free)
    return _decide(system, K)


def _from_tangent(system: System, jacobian) -> Instability | None:
    """Every eigenvalue of M⁻¹K with K = −``jacobian`` (6 n_rigid, 6
    n_rigid), the tangent stiffness at rest of rigid bodies, whose M is
    m I₃ and the body-frame inertia J per body (n_free³)."""
    Kq = jacobian.toarray() if hasattr(jacobian, "toarray") else np.asarray(jacobian)
    n = system.n_rigid
    Jinv = np.einsum("bij,bj,bkj->bik", system.J_vec, 1.0 / system.J_eig, system.J_vec)
    K = np.empty_like(Kq)
    for b in range(n):
        t, r = slice(6 * b, 6 * b + 3), slice(6 * b + 3, 6 * b + 6)
        K[t] = -Kq[t] / system.m_r[b, 0]
        K[r] = -Jinv[b] @ Kq[r]
    return _decide(system, K)


def _decide(system: System, K: np.ndarray) -> Instability | None:
    """The criterion of the module docstring on M⁻¹K (n_free, n_free): the
    eigenvalues alone first (two thirds of the cost), the vectors only for
    an unstable equilibrium (its direction)."""
    if _stable(np.linalg.eigvals(K).real):
        return None
    vals, vecs = np.linalg.eig(K)
    lam = vals.real
    scale = float(np.max(np.abs(lam))) if lam.size else 0.0
    i = int(np.argmin(lam))
    if not (scale > 0 and lam[i] < -RELATIVE_TOL * scale):
        return None
    return _found(system, float(lam[i]), int(np.argmax(np.abs(vecs[:, i].real))))


def _stable(lam: np.ndarray) -> bool:
    """No eigenvalue below −RELATIVE_TOL times the largest magnitude."""
    scale = float(np.max(np.abs(lam))) if lam.size else 0.0
    return not (scale > 0 and float(np.min(lam)) < -RELATIVE_TOL * scale)


_UNANSWERED = object()


def _sparse(system: System, y_eq: np.ndarray):
    """M⁻¹K block-sparse, its extreme eigenvalues by ARPACK: an
    :class:`Instability`, None, or ``_UNANSWERED`` (not converged, or too
    few coordinates for ARPACK: the dense path answers)."""
    g = mount_graph(system, True)
    n = g.n
    if n < 4:                    # ARPACK's eigs needs k < n − 1
        return _UNANSWERED
    coords = Coordinates(system, y_eq)
    step = difference_steps(system, coords)
    nb3 = coords.base_index.size
    q_steps = step[nb3:coords.n_pos]                           # the free positions, as the dense
    v_steps = step[coords.n_pos + nb3:]
    lin = linearised(system, y_eq, q_steps, v_steps)
    S = -(block_inverse(system, lin.M) @ lin.Kq).tocsr()      # M⁻¹K (n, n)
    if not np.all(np.isfinite(S.data)):
        return _UNANSWERED
    v0 = np.cos(np.arange(n) + 0.5)
    try:
        big = eigs(S, k=1, which="LM", tol=_ARNOLDI_TOL, maxiter=100 * n, v0=v0,
                   return_eigenvectors=False)
        vals, vecs = eigs(S, k=min(LEFTMOST_COUNT, n - 2), which="SR", tol=_ARNOLDI_TOL,
                          maxiter=100 * n, v0=v0)
    except ArpackNoConvergence:
        return _UNANSWERED      # the dense path: slower, but it always answers
    lam = vals.real
    scale = max(float(np.abs(big[0])), float(np.max(np.abs(lam))))
    i = int(np.argmin(lam))
    if not (scale > 0 and lam[i] < -RELATIVE_TOL * scale):
        return None
    # a real eigenvalue's vector comes with an arbitrary complex phase: its moduli
    return _found(system, float(lam[i]), int(np.argmax(np.abs(vecs[:, i]))))


def _found(system: System, lam: float, j: int) -> Instability:
    """The :class:`Instability` of the eigenvalue lam < 0 whose eigenvector's
    largest component is the free coordinate j (6 per body, then the modal
    coordinates)."""
    n_rigid = len(system.layout.rigid)
    if j < 6 * n_rigid:
        b, k = divmod(j, 6)
        body = system.scene.bodies[system.layout.rigid[b]].name
        direction = DIRECTIONS[k]
    else:
        body, direction = _modal_owner(system, j - 6 * n_rigid)
    return Instability(lam, math.sqrt(-lam), body, direction)


def _modal_owner(system: System, m: int) -> tuple[str, str]:
    """(body name, "modal coordinate k") of the m-th modal coordinate."""
    for fc in system.flex_compiled:
        n = fc.eom.n
        if m < n:
            return system.scene.bodies[fc.body].name, f"modal coordinate {m + 1}"
        m -= n
    return "?", f"modal coordinate {m + 1}"

"""Modal invariants of the plate for the floating frame of reference.

A material point of the bed, at ū0 = (x, y, z) in the bed frame (origin at
the undeformed centre of mass), moves to ū0 + Φ(ū0) a, with modal
coordinates a (n,) and, by Kirchhoff kinematics, for mode k

    Φ_k(x, y, z) = (-z ∂w_k/∂x, -z ∂w_k/∂y, w_k(x, y)).

Everything the equations of motion need is an integral over the solid,
computed here once (Shabana's numbering in brackets; ~ is the cross-product
matrix, ρ the density):

================================  ==========================  =============
quantity                          definition                  shape
================================  ==========================  =============
``mass``                 [I1]     ∫ρ dV                       ()
``first_moment``         [I2]     ∫ρ ū0 dV                    (3,)
``phi_integral``         [I3]     ∫ρ Φ dV                     (3, n)
``u_cross_phi``          [I4]     ∫ρ ũ0 Φ dV                  (3, n)
``phi_cross_phi``        [I5]     ∫ρ Φ̃_k Φ_l dV, [k, :, l]    (n, 3, n)
``modal_mass``           [I6]     ∫ρ Φᵀ Φ dV                  (n, n)
``inertia``              [I7]     ∫ρ ũ0ᵀ ũ0 dV                (3, 3)
``inertia_first_order``  [I8]     ∫ρ ũ0ᵀ Φ̃_k dV, [k]          (n, 3, 3)
``inertia_second_order`` [I9]     ∫ρ Φ̃_kᵀ Φ̃_l dV, [k, l]      (n, n, 3, 3)
``modal_stiffness``               Φᵀ K Φ                      (n, n)
================================  ==========================  =============

With them the inertia tensor at configuration a is
J(a) = I7 + Σ_k a_k (I8_k + I8_kᵀ) + Σ_kl a_k a_l I9_kl, and the
rotation–deformation coupling is ∫ρ ũ Φ = I4 + Σ_k a_k I5[k].

Where each comes from: ``mass``, ``first_moment`` and ``inertia`` are those of
the solid rectangular plate (exact geometry; a bending model has no in-plane
inertia). Every term with Φ is integrated exactly over the discrete
Kirchhoff field through the thickness, with the same mass forms as the FE
mass matrix (the rotary-inertia part only if the model has it), so that
free–free modes make I3 and I4 vanish to round-off.

The names, shapes and units are the modes file's, defined once in
:data:`flexbed.files.modes.INVARIANTS`: the contract with
:mod:`flexbed.dynamics` (which takes them as
:class:`~flexbed.dynamics.flexible.FlexibleBody`), checked against both
sides by a test.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from .fixed_masses import moments as fixed_moments

if TYPE_CHECKING:       # annotations only: reading invariants needs no FE code
    from .modes import ModeSet
    from .plate import PlateModel

# Levi-Civita symbol: (a × b)_i = ε_ijk a_j b_k
_EPS = np.zeros((3, 3, 3))
_EPS[0, 1, 2] = _EPS[1, 2, 0] = _EPS[2, 0, 1] = 1.0
_EPS[0, 2, 1] = _EPS[2, 1, 0] = _EPS[1, 0, 2] = -1.0

SOURCE_SOLID = "solid plate, exact geometry"
SOURCE_FE = "FE mass forms with the kept modes (Kirchhoff field through the thickness)"
SOURCE_SHELL = ("FE consistent mass of the Mindlin shell (u + z theta_y, v - z theta_x, w "
                "through the thickness), exact for its mesh")


@dataclass(frozen=True)
class Invariants:
    """The invariant set of the module docstring (units: kg, m, and
    mass-normalised modes of unit kg^-1/2)."""

    mass: float
    first_moment: np.ndarray
    inertia: np.ndarray
    phi_integral: np.ndarray
    u_cross_phi: np.ndarray
    phi_cross_phi: np.ndarray
    modal_mass: np.ndarray
    inertia_first_order: np.ndarray
    inertia_second_order: np.ndarray
    modal_stiffness: np.ndarray
    model_mass: bool = False
    """True when mass, first moment and inertia come from the FE mass
    matrix (Mindlin shell: exact for the discretised geometry)."""

    SOURCES = {
        "mass": SOURCE_SOLID, "first_moment": SOURCE_SOLID, "inertia": SOURCE_SOLID,
        "phi_integral": SOURCE_FE, "u_cross_phi": SOURCE_FE, "phi_cross_phi": SOURCE_FE,
        "modal_mass": SOURCE_FE, "inertia_first_order": SOURCE_FE,
        "inertia_second_order": SOURCE_FE, "modal_stiffness": "FE stiffness with the kept modes",
    }

    def source(self, key: str) -> str:
        """Where invariant ``key`` comes from (one line)."""
        if self.model_mass:
            return SOURCE_SHELL
        return self.SOURCES[key]


def second_moments(model: PlateModel, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray,
                                                                 np.ndarray]:
    """Primitive integrals from which every modal invariant follows.

    Parameters
    ----------
    model : PlateModel
    phi : ndarray (ndof, n)
        Mode DOF vectors.

    Returns
    -------
    S : ndarray (3, n)
        ∫ρ Φ_k dV.
    Q : ndarray (n, 3, 3)
        ∫ρ ū0 Φ_kᵀ dV.
    P : ndarray (n, n, 3, 3)
        ∫ρ Φ_k Φ_lᵀ dV.
    """
    n = phi.shape[1]
    R = model.rigid_vectors()                  # functions 1, y, -x
    e1, ey, ex = R[:, 0], R[:, 1], -R[:, 2]
    Mw_phi = model.M_w @ phi
    S = np.zeros((3, n))
    S[2] = e1 @ Mw_phi
    Q = np.zeros((n, 3, 3))
    Q[:, 0, 2] = ex @ Mw_phi                   # ∫ρ x w
    Q[:, 1, 2] = ey @ Mw_phi                   # ∫ρ y w
    Q[:, 2, 0] = -(ex @ (model.G_xx @ phi))    # ∫ρ z (-z w_x)
    Q[:, 2, 1] = -(ey @ (model.G_yy @ phi))    # ∫ρ z (-z w_y)
    P = np.zeros((n, n, 3, 3))
    P[:, :, 0, 0] = phi.T @ (model.G_xx @ phi)
    # scikit-fem's matrix is A[test, trial]: φ_kᵀ G_xy φ_l = ρt³/12 ∫ ∂y w_k ∂x w_l
    Gyx = phi.T @ (model.G_xy @ phi)
    P[:, :, 1, 0] = Gyx
    P[:, :, 0, 1] = Gyx.T
    P[:, :, 1, 1] = phi.T @ (model.G_yy @ phi)
    P[:, :, 2, 2] = phi.T @ Mw_phi
    return S, Q, P


def modal_invariants(model: PlateModel, modes: ModeSet) -> Invariants:
    """Invariants of the plate with the given elastic modes.

    Parameters
    ----------
    model : PlateModel
    modes : ModeSet

    Returns
    -------
    Invariants
    """
    phi = modes.vectors
    S, Q, P = second_moments(model, phi)
    spec = model.spec
    modal_stiffness = phi.T @ (model.K @ phi)
    return _assemble(S, Q, P, modal_stiffness, mass=spec.mass, first_moment=np.zeros(3),
                     inertia=np.diag(spec.inertia))


def _assemble(S, Q, P, modal_stiffness, *, mass, first_moment, inertia,
              model_mass=False) -> Invariants:
    """The invariants from the primitive integrals of :func:`second_moments`."""
    eye = np.eye(3)
    trQ = np.trace(Q, axis1=1, axis2=2)
    trP = np.trace(P, axis1=2, axis2=3)
    # ũᵀṽ = (u·v) I - v uᵀ
    inertia_first = trQ[:, None, None] * eye - np.transpose(Q, (0, 2, 1))
    inertia_second = trP[:, :, None, None] * eye - np.transpose(P, (1, 0, 2, 3))
    u_cross_phi = np.einsum("ijm,kjm->ik", _EPS, Q)           # (3, n)
    phi_cross_phi = np.einsum("ijm,kljm->kil", _EPS, P)       # (n, 3, n)
    return Invariants(
        mass=mass,
        first_moment=first_moment,
        inertia=inertia,
        phi_integral=S,
        u_cross_phi=u_cross_phi,
        phi_cross_phi=phi_cross_phi,
        modal_mass=trP,
        inertia_first_order=inertia_first,
        inertia_second_order=inertia_second,
        modal_stiffness=0.5 * (modal_stiffness + modal_stiffness.T),
        model_mass=model_mass,
    )


def shell_second_moments(model, phi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`second_moments` for the Mindlin shell (:mod:`flexbed.fem.shell`).

    Φ_k(x, y, z) = (u_k + z θy_k, v_k − z θx_k, w_k) with bilinear nodal
    fields; ∫ρ z dz = 0 over the symmetric thickness, ∫ρ z² dz = ρt³/12,
    so every integral is a product with the nodal mass M0 (ρt) or M2
    (ρt³/12), exactly the blocks of the FE mass matrix. Positions x, y
    are bilinear fields too, so the moments with ū0 are exact as well.
    """
    d = model.node_dofs
    u, v, w, tx, ty = (phi[d[i]] for i in range(5))             # (N, n) each
    M0, M2 = model.M0, model.M2
    one = np.ones(model.nodes.shape[0])
    x, y = model.nodes.T
    n = phi.shape[1]
    comps0 = (u, v, w)
    M0c = [M0 @ c for c in comps0]
    S = np.array([one @ m for m in M0c])                        # (3, n)
    Q = np.zeros((n, 3, 3))
    for j in range(3):
        Q[:, 0, j] = x @ M0c[j]
        Q[:, 1, j] = y @ M0c[j]
    Q[:, 2, 0] = one @ (M2 @ ty)                                # ∫ρ z (z θy)
    Q[:, 2, 1] = -(one @ (M2 @ tx))                             # ∫ρ z (−z θx)
    P = np.zeros((n, n, 3, 3))
    M2tx, M2ty = M2 @ tx, M2 @ ty
    for i in range(3):
        for j in range(3):
            P[:, :, i, j] = comps0[i].T @ M0c[j]
    # rotation parts: Φx ∋ z θy, Φy ∋ −z θx
    P[:, :, 0, 0] += ty.T @ M2ty
    P[:, :, 1, 1] += tx.T @ M2tx
    P[:, :, 0, 1] -= ty.T @ M2tx
    P[:, :, 1, 0] -= tx.T @ M2ty
    for item, where, dofs, T, R in model.fixed:       # rigid items (fixed_masses)
        s_, q_, p_ = fixed_moments(item, where, T @ phi[dofs], R @ phi[dofs])
        S += s_
        Q += q_
        P += p_
    # so far about the mid-surface; the frame's origin is mid_z below it
    Q[:, 2, :] += model.mid_z * S.T
    return S, Q, P


def shell_mass_properties(model) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass [kg], first moment about the origin (3,) [kg m] and inertia
    tensor about the origin (3, 3) [kg m²] of the shell and its fixed
    masses, from the mass matrix's blocks (exact for the mesh's geometry and
    thickness)."""
    M0, M2 = model.M0, model.M2
    one = np.ones(model.nodes.shape[0])
    x, y = model.nodes.T
    z0 = model.mid_z
    m = float(one @ (M0 @ one))
    first = np.array([one @ (M0 @ x), one @ (M0 @ y), m * z0])
    xx, yy, xy = x @ (M0 @ x), y @ (M0 @ y), x @ (M0 @ y)
    zz = float(one @ (M2 @ one)) + m * z0 * z0                  # ∫ρ z² dV
    xz, yz = first[0] * z0, first[1] * z0
    J = np.array([[yy + zz, -xy, -xz], [-xy, xx + zz, -yz], [-xz, -yz, xx + yy]])
    for item, where, _, _, _ in model.fixed:
        p = np.array([where[0], where[1], where[2] + z0])
        m += item.mass
        first = first + item.mass * p
        J = J + np.array(item.inertia) + item.mass * (p @ p * np.eye(3) - np.outer(p, p))
    return m, first, J


def shell_invariants(model, modes: ModeSet) -> Invariants:
    """Invariants of the Mindlin shell with the given elastic modes: every
    one, mass properties included, from the model's consistent mass."""
    phi = modes.vectors
    S, Q, P = shell_second_moments(model, phi)
    mass, first, inertia = shell_mass_properties(model)
    k = phi.T @ (model.K @ phi)
    return _assemble(S, Q, P, k, mass=mass, first_moment=first, inertia=inertia,
                     model_mass=True)

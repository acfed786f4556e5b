"""Kirchhoff plate assembled with scikit-fem: stiffness, mass, and the
auxiliary matrices the modal invariants are integrated with.

The plate occupies [-a/2, a/2] × [-b/2, b/2] × [-t/2, t/2] in the bed frame
(origin at the undeformed centre of mass). Kirchhoff kinematics: a point at
height z above the mid-surface point (x, y) moves by

    u = (-z ∂w/∂x, -z ∂w/∂y, w(x, y)).

Integrating the kinetic energy through the thickness gives the consistent
mass ρt ∫ w v dA plus the rotary inertia ρt³/12 ∫ ∇w·∇v dA (kept by
default, see :class:`fem.spec.PlateSpec`). The degrees of freedom are those
of the Bogner–Fox–Schmit element: w, ∂w/∂x, ∂w/∂y, ∂²w/∂x∂y at each node.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
from skfem import Basis, BilinearForm, MeshQuad
from skfem.helpers import dd, ddot, grad, trace

from .element import ElementQuadBFSLocal
from .spec import PlateSpec

DOF_NAMES = ("u", "u_x", "u_y", "u_xy")


@BilinearForm
def _bending(u, v, w):
    U, V = dd(u), dd(v)
    return w["D"] * ((1.0 - w["nu"]) * ddot(U, V) + w["nu"] * trace(U) * trace(V))


@BilinearForm
def _curvature_xx(u, v, w):
    return w["D"] * dd(u)[0, 0] * dd(v)[0, 0]


@BilinearForm
def _curvature_yy(u, v, w):
    return w["D"] * dd(u)[1, 1] * dd(v)[1, 1]


@BilinearForm
def _twist(u, v, w):
    return 2.0 * w["D"] * (1.0 - w["nu"]) * dd(u)[0, 1] * dd(v)[0, 1]


@BilinearForm
def _value(u, v, w):
    return u * v


@BilinearForm
def _slope_xx(u, v, w):
    return grad(u)[0] * grad(v)[0]


@BilinearForm
def _slope_xy(u, v, w):
    return grad(u)[0] * grad(v)[1]


@BilinearForm
def _slope_yy(u, v, w):
    return grad(u)[1] * grad(v)[1]


@dataclass(frozen=True)
class PlateModel:
    """Assembled plate. Matrices are (ndof, ndof) CSR, ndof = 4 × nodes.

    Attributes
    ----------
    spec : PlateSpec
        Inputs.
    mesh : skfem.MeshQuad
        Rectangular mesh, nodes (nx+1)(ny+1).
    basis : skfem.Basis
        BFS basis on the mesh.
    K : sparse (ndof, ndof)
        Bending stiffness [N·m per unit DOF²].
    M : sparse (ndof, ndof)
        Mass: ``M_w + (G_xx + G_yy)`` when rotary inertia is on [kg].
    M_w : sparse (ndof, ndof)
        Translational mass ρt ∫ w v dA.
    G_xx, G_xy, G_yy : sparse (ndof, ndof)
        Rotary-inertia forms ρt³/12 ∫ ∂_i w ∂_j v dA (zero matrices when
        rotary inertia is off, so that every invariant stays consistent
        with ``M``).
    K_xx, K_yy, K_twist : sparse (ndof, ndof)
        Parts of the bending energy from w_xx², w_yy² and the twist w_xy²
        (used to tell bending about y, bending about x and torsion apart).
    """

    spec: PlateSpec
    mesh: MeshQuad
    basis: Basis
    K: sp.csr_matrix
    M: sp.csr_matrix
    M_w: sp.csr_matrix
    G_xx: sp.csr_matrix
    G_xy: sp.csr_matrix
    G_yy: sp.csr_matrix
    K_xx: sp.csr_matrix
    K_yy: sp.csr_matrix
    K_twist: sp.csr_matrix

    @property
    def nodes(self) -> np.ndarray:
        """Node coordinates (N, 2) [m]."""
        return self.mesh.p.T

    @property
    def node_dofs(self) -> np.ndarray:
        """Global DOF index (4, N): rows w, ∂w/∂x, ∂w/∂y, ∂²w/∂x∂y."""
        return self.basis.nodal_dofs

    def dof_vector(self, w, w_x, w_y, w_xy=0.0) -> np.ndarray:
        """DOF vector (ndof,) from nodal values of w and its derivatives."""
        n = self.nodes.shape[0]
        out = np.zeros(self.basis.N)
        for row, values in enumerate((w, w_x, w_y, w_xy)):
            out[self.node_dofs[row]] = np.broadcast_to(values, (n,))
        return out

    def band_order(self) -> np.ndarray:
        """DOF ordering (ndof,) row by row along the plate's shorter side,
        which keeps the matrices' band narrow (≈ 4 × nodes across)."""
        x, y = self.nodes.T
        fast, slow = (x, y) if self.spec.nx <= self.spec.ny else (y, x)
        node_order = np.lexsort((fast, slow))
        return self.node_dofs[:, node_order].T.ravel()

    def rigid_vectors(self) -> np.ndarray:
        """DOF vectors (ndof, 3) of the plate's rigid motions: translation
        along z (w = 1), rotation about x (w = y), rotation about y (w = -x)."""
        x, y = self.nodes.T
        return np.column_stack([self.dof_vector(1.0, 0.0, 0.0),
                                self.dof_vector(y, 0.0, 1.0),
                                self.dof_vector(-x, -1.0, 0.0)])


def assemble_plate(spec: PlateSpec) -> PlateModel:
    """Build the mesh and assemble every matrix of the plate.

    Parameters
    ----------
    spec : PlateSpec
        Geometry, material, mesh.

    Returns
    -------
    PlateModel
    """
    a, b = spec.length_x, spec.length_y
    mesh = MeshQuad.init_tensor(np.linspace(-a / 2, a / 2, spec.nx + 1),
                                np.linspace(-b / 2, b / 2, spec.ny + 1))
    # Products of two bicubics (and of their derivatives) are at most degree 6
    # in each variable: 4 × 4 Gauss points (exact to degree 7) integrate every
    # form exactly, at a third of the cost of scikit-fem's default rule.
    basis = Basis(mesh, ElementQuadBFSLocal(), intorder=6)
    D, nu = spec.rigidity, spec.poisson
    rho_t = spec.density * spec.thickness
    rot = spec.density * spec.thickness ** 3 / 12.0 if spec.rotary_inertia else 0.0
    K = _bending.assemble(basis, D=D, nu=nu)
    M_w = rho_t * _value.assemble(basis)
    G_xx = rot * _slope_xx.assemble(basis)
    G_xy = rot * _slope_xy.assemble(basis)
    G_yy = rot * _slope_yy.assemble(basis)
    M = (M_w + G_xx + G_yy).tocsr()
    return PlateModel(spec=spec, mesh=mesh, basis=basis, K=K.tocsr(), M=M, M_w=M_w.tocsr(),
                      G_xx=G_xx.tocsr(), G_xy=G_xy.tocsr(), G_yy=G_yy.tocsr(),
                      K_xx=_curvature_xx.assemble(basis, D=D).tocsr(),
                      K_yy=_curvature_yy.assemble(basis, D=D).tocsr(),
                      K_twist=_twist.assemble(basis, D=D, nu=nu).tocsr())

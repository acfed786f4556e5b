"""Bogner–Fox–Schmit element evaluated in local coordinates.

scikit-fem's :class:`skfem.ElementQuadBFS` builds each element's basis as a
combination of global monomials x^i y^j (degree ≤ 3 in each variable) through
an inverted Vandermonde matrix. On small elements far from the origin that
matrix is badly conditioned: at 80 × 80 elements on the reference bed the
element matrices lose about five digits, and a symmetric static solution
comes out visibly asymmetric.

:class:`ElementQuadBFSLocal` has the same degrees of freedom (u, u_x, u_y,
u_xy at each vertex, in global derivatives, same order), so it is a drop-in
replacement, but it evaluates the basis as products of cubic Hermite
polynomials in the element's own coordinates ξ = (x - x0)/hx,
η = (y - y0)/hy ∈ [0, 1]. The basis is then exact to round-off on any mesh
of axis-aligned rectangles (which is all it accepts).
"""

from __future__ import annotations

import numpy as np
from skfem import ElementQuadBFS
from skfem.element.discrete_field import DiscreteField

from .hermite import hermite_1d


class ElementQuadBFSLocal(ElementQuadBFS):
    """BFS element, tensor-product Hermite basis in element coordinates.

    Degrees of freedom per vertex, in this order: u, ∂u/∂x, ∂u/∂y,
    ∂²u/∂x∂y (global derivatives), as in :class:`skfem.ElementQuadBFS`.
    Only meshes of axis-aligned rectangles are accepted.
    """

    def gbasis(self, mapping, X, i, tind=None):
        mesh = mapping.mesh
        if tind is None:
            tind = np.arange(mesh.t.shape[1])
        if i < 0 or i >= 16:
            self._index_error()
        corners = mesh.p[:, mesh.t[:, tind]]            # (2, 4, ne)
        lo = corners.min(axis=1)                       # (2, ne)
        hi = corners.max(axis=1)
        h = hi - lo
        on_lo = np.isclose(corners, lo[:, None, :], rtol=0, atol=1e-9 * h[:, None, :])
        on_hi = np.isclose(corners, hi[:, None, :], rtol=0, atol=1e-9 * h[:, None, :])
        if not np.all(on_lo | on_hi):
            raise ValueError("ElementQuadBFSLocal needs axis-aligned rectangular elements")
        vertex, kind = divmod(i, 4)
        at_end = on_hi[:, vertex, :]                   # (2, ne): vertex on the high side
        x = mapping.F(X, tind=tind)                    # (2, ne, nqp)
        s = (x - lo[:, :, None]) / h[:, :, None]
        fx, dfx, ddfx = hermite_1d(s[0], at_end[0][:, None], slope=kind in (1, 3))
        fy, dfy, ddfy = hermite_1d(s[1], at_end[1][:, None], slope=kind in (2, 3))
        hx = h[0][:, None]
        hy = h[1][:, None]
        if kind in (1, 3):                             # slope DOF in x: scale by hx
            fx, dfx, ddfx = fx * hx, dfx * hx, ddfx * hx
        if kind in (2, 3):
            fy, dfy, ddfy = fy * hy, dfy * hy, ddfy * hy
        dfx, ddfx = dfx / hx, ddfx / (hx * hx)         # d/dx = (1/hx) d/dξ
        dfy, ddfy = dfy / hy, ddfy / (hy * hy)
        value = fx * fy
        grad = np.array([dfx * fy, fx * dfy])
        dxy = dfx * dfy
        hess = np.array([[ddfx * fy, dxy], [dxy, fx * ddfy]])
        return (DiscreteField(value=value, grad=grad, hess=hess),)

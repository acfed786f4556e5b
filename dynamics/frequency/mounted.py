"""The mounted system as second-order matrices, from the one linearisation.

About the static equilibrium, with the base held (the ground the mounts
attach to; a free base is held too), the linearisation of
:mod:`flexbed.dynamics.linear.model` gives ``ż = A z`` in the deviations
``z = [q; q̇]``, ``q`` = δr (3), θ (3) of every body 2… and the modal
deviations δa. Its kinematic rows are exactly ``q̇ = v`` at rest
(θ̇ = ω̄ + O(θ ω̄)), so the dynamic rows are ``v̇ = A_qv q + A_vv v`` and, with
the mass matrix ``M`` of the same right-hand side at rest (m I and the body
inertia J of each rigid body; a flexible body's :meth:`FlexibleEOM.mass_matrix`),

    M q̈ + C q̇ + K q = 0,   K = −M A_qv,   C = −M A_vv.

Kinetic energy is ``½ q̇ᵀ M q̇`` in these coordinates (ṙ inertial, ω̄ body
frame, ȧ). Mounts: central differences of the right-hand side's own mount
outputs (the kernel's work arrays) give the deflections ``D q``, rates
``D_v q̇`` and forces ``F_q q + F_v q̇`` along each mount's axes and the
inertial force the mounts put on the base, ``B_q q + B_v q̇``.

Translating the base by ``d`` is translating every other body by ``−d``
(mount forces see relative positions only, gravity is uniform), so a
base motion enters through the relative coordinates ``q − ι d`` with
``ι`` (n, 3) the rigid translation of every moving body (:attr:`iota`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from ..block_linearisation import linearised
from ..linear.model import Coordinates, difference_steps, linearise
from ..rotation import A as rotation_matrix
from ..system import System
from ..tangent import Tangent, tangent
from .elastomer import ComplexStiffness

__all__ = ["MountedSystem", "mounted_system", "DOF_NAMES"]

#: central-difference step in the rates [m/s, rad/s] and translations [m]:
#: at rest the forces are at most quadratic in the rates and (linear laws)
#: linear in the translations, so central differences are exact there but
#: for round-off, which a larger step keeps small against the preloads and
#: the positions (a nonlinear law's curvature costs O(1e-8) relative)
RATE_STEP = 1e-4

#: above this many coordinates :func:`mounted_system` takes its columns by
#: colour classes of the mount graph (the reference scene has 18)
DENSE_LIMIT = 100

#: the six coordinates of a body's frame, in the order of q
DOF_NAMES = ("x", "y", "z", "roll", "pitch", "yaw")


class _MountMatrix:
    """A dense mount-matrix field of :class:`MountedSystem` (a dataclass
    field with a descriptor, as :mod:`dataclasses` documents them): the
    array given, or, given None, ``mount_rows[k]`` made dense on first use
    and kept in the instance."""

    def __init__(self, k: int):
        self.k = k

    def __set_name__(self, owner, name: str):
        self.key = "_" + name

    def __get__(self, obj, objtype=None):
        if obj is None:                  # no default: the field must be given
            raise AttributeError(self.key[1:])
        got = obj.__dict__[self.key]
        if got is None:
            got = obj.__dict__[self.key] = obj.mount_rows[self.k].toarray()
        return got

    def __set__(self, obj, value):       # __init__'s, once (the class is frozen)
        obj.__dict__[self.key] = value


@dataclass(frozen=True)
class MountedSystem:
    """``M q̈ + C q̇ + K q = f`` about the equilibrium, base held.

    Attributes
    ----------
    labels : tuple of str (n,)
        What each coordinate is: ``"<body> x"`` … ``"<body> yaw"`` (δr [m]
        inertial, θ [rad] body frame), ``"<body> mode k"`` [kg^1/2 m].
    body : (n,) int
        Scene index of the body each coordinate belongs to.
    M, K, C : (n, n) arrays
        Mass [kg, kg m², …], stiffness [N/m, …], damping [N s/m, …].
    K_elastic : (n, n) array
        The flexible bodies' modal stiffness alone (strain energy of the bed).
    D, Dv : (3 n_mounts, n) arrays
        Mount deflections [m] per unit q, rates [m/s] per unit q̇, rows
        (mount, axis) in scene order.
    Fq, Fv : (3 n_mounts, n) arrays
        Mount forces along their axes [N] per unit q and q̇. D, Dv, Fq and
        Fv may be given as None with ``mount_rows`` (the large systems'
        path): then made dense from those on first use and kept
        (:class:`_MountMatrix`; the modes need none of them dense, 4 × 14 MB
        at 128 pieces of equipment).
    k_tangent, c_tangent : (3 n_mounts,) arrays
        ∂f/∂Δx [N/m] and ∂f/∂Δẋ [N s/m] of each mount axis at rest.
    Bq, Bv : (3, n) arrays
        Total force of the mounts on the base [N], inertial, per unit q, q̇.
    iota : (n, 3) array
        Rigid translation of all moving bodies along X, Y, Z [m per m].
    moving_mass : float
        ``ι_Xᵀ M ι_X``: the mass of everything but the base [kg].
    y_eq : (ny,) array
        The equilibrium.
    evaluations : int
        Right-hand sides it took.
    sparse : (M, K, C) of scipy.sparse CSR matrices, or None
        The same matrices, sparse (block-sparse by the mount graph), for
        the analyses of large systems.
    mount_rows : (D, Dv, Fq, Fv) of scipy.sparse CSR matrices, or None
        The mount outputs, sparse (each row touches the two bodies of its
        mount), from the large systems' linearisation; None on the dense path.
    elastomer : ComplexStiffness or None
        Elastomer mount directions, whose complex stiffness the frequency
        analyses add to ``K`` (:mod:`flexbed.dynamics.frequency.elastomer`);
        ``K`` itself holds their static stiffness.
    """

    labels: tuple
    body: np.ndarray
    M: np.ndarray
    K: np.ndarray
    C: np.ndarray
    K_elastic: np.ndarray
    D: np.ndarray = _MountMatrix(0)
    Dv: np.ndarray = _MountMatrix(1)
    Fq: np.ndarray = _MountMatrix(2)
    Fv: np.ndarray = _MountMatrix(3)
    k_tangent: np.ndarray
    c_tangent: np.ndarray
    Bq: np.ndarray
    Bv: np.ndarray
    iota: np.ndarray
    moving_mass: float
    y_eq: np.ndarray
    coords: Coordinates
    evaluations: int
    sparse: tuple | None = None
    elastomer: ComplexStiffness | None = None
    mount_rows: tuple | None = None

    @property
    def n(self) -> int:
        return self.M.shape[0]

    @property
    def damped(self) -> bool:
        return bool(np.any(self.C != 0.0))

    def state(self, q: np.ndarray, qd: np.ndarray | None = None) -> np.ndarray:
        """The system's state y (ny,) for deviations q (n,) and rates q̇ (n,)
        from the equilibrium (base at rest)."""
        z = np.zeros(self.coords.nz)
        nb3 = self.coords.base_index.size
        z[nb3:self.coords.n_pos] = q
        if qd is not None:
            z[self.coords.n_pos + nb3:] = qd
        return self.coords.to_y(z)

    def states(self, Q: np.ndarray) -> np.ndarray:
        """The states (k, ny) of the deviations Q (k, n), rates zero: each
        row's :meth:`state` (the same numbers), in one pass."""
        Q = np.asarray(Q, dtype=float)
        Z = np.zeros((Q.shape[0], self.coords.nz))
        Z[:, self.coords.base_index.size:self.coords.n_pos] = Q
        return self.coords.to_y(Z)


def _labels(system: System, coords: Coordinates) -> tuple[tuple, np.ndarray]:
    bodies = system.scene.bodies
    labels, owner = [], []
    for s in range(coords.n_rigid):
        labels += [f"{bodies[s + 1].name} {d}" for d in DOF_NAMES]
        owner += [s + 1] * 6
    for fc in system.flex_compiled:
        labels += [f"{bodies[fc.body].name} mode {k + 1}" for k in range(fc.eom.n)]
        owner += [fc.body] * fc.eom.n
    return tuple(labels), np.array(owner, dtype=int)


def _mass_matrix(system: System, coords: Coordinates, y_eq: np.ndarray) -> np.ndarray:
    """M (n, n) at rest over q = [δr, θ per body 2…, δa], base excluded."""
    nb3 = coords.base_index.size
    n = coords.n_pos - nb3
    M = np.zeros((n, n))
    for s in range(coords.n_rigid):
        r = coords.r_index[s] - nb3
        t = coords.th_index[s] - nb3
        M[r, r] = system.m_r[s, 0]
        M[np.ix_(t, t)] = system.J[s]
    p = coords.p_eq
    for fc in system.flex_compiled:
        a = y_eq[fc.qa]
        A = rotation_matrix(p[fc.slot])
        blk = np.concatenate([coords.r_index[fc.slot], coords.th_index[fc.slot],
                              coords.a_index[fc.qa.start - coords.y_a[0]:
                                             fc.qa.stop - coords.y_a[0]]]) - nb3
        M[np.ix_(blk, blk)] = fc.eom.mass_matrix(A, a)
    return M


def _exact_parts(system: System, coords: Coordinates, tg: Tangent):
    """The same from the exact tangent at rest (:func:`flexbed.dynamics.tangent.tangent`,
    dense: one right-hand side)."""
    M = _mass_matrix(system, coords, coords.y_eq)
    sign = (system.body_i == 0).astype(float) - (system.body_j == 0).astype(float)
    oq, ov = tg.outputs_q, tg.outputs_v
    Bq, Bv = (np.einsum("m,mkc->kc", sign, o["w_F"].reshape(system.M, 3, -1)) for o in (oq, ov))
    return (M, -tg.Kq, -tg.Kv, oq["w_dx"], ov["w_dxd"], oq["w_f"], ov["w_f"], Bq, Bv,
            (sp.csr_matrix(M), sp.csr_matrix(-tg.Kq), sp.csr_matrix(-tg.Kv)), None)


def _dense_parts(system: System, coords: Coordinates):
    """M, K, C and the mount outputs, dense, by the one linearisation
    (:func:`flexbed.dynamics.linear.model.linearise`: every column) and one
    batch of the right-hand side for the mounts' outputs (the path of small
    systems; 2n + 1 and 4n right-hand sides)."""
    lin = linearise(system, coords.y_eq, rate_step=RATE_STEP, translation_step=RATE_STEP)
    nb3 = coords.base_index.size
    npos = coords.n_pos
    keep = np.arange(nb3, npos)
    n = keep.size
    A_qv = lin.A[np.ix_(npos + keep, keep)]
    A_vv = lin.A[np.ix_(npos + keep, npos + keep)]
    M = _mass_matrix(system, coords, coords.y_eq)
    K = -M @ A_qv
    C = -M @ A_vv
    # the mounts' outputs: one batch at ±h in each kept coordinate and rate
    step = difference_steps(system, coords, RATE_STEP, RATE_STEP)
    cols = np.concatenate([keep, npos + keep])
    Z = np.zeros((2 * cols.size, coords.nz))
    Z[np.arange(cols.size), cols] = step[cols]
    Z[cols.size + np.arange(cols.size), cols] = -step[cols]
    _, cap = system.rhs_batch(np.zeros(Z.shape[0]), coords.to_y(Z),
                              capture=("w_dx", "w_dxd", "w_f", "w_F"))
    h2 = 2.0 * step[cols]
    m = system.M

    def jac(name):
        v = cap[name].reshape(Z.shape[0], -1)
        return ((v[:cols.size] - v[cols.size:]) / h2[:, None]).T       # (rows, 2n)

    dx, dxd, f = jac("w_dx"), jac("w_dxd"), jac("w_f")
    sign = (system.body_i == 0).astype(float) - (system.body_j == 0).astype(float)
    Fbase = np.einsum("m,mkc->kc", sign, jac("w_F").reshape(m, 3, 2 * n))
    return (M, K, C, dx[:, :n], dxd[:, n:], f[:, :n], f[:, n:], Fbase[:, :n], Fbase[:, n:],
            (sp.csr_matrix(M), sp.csr_matrix(K), sp.csr_matrix(C)), None)


def _sparse_parts(system: System, coords: Coordinates, exact: bool = False):
    """The same by colour classes of the mount graph
    (:func:`flexbed.dynamics.block_linearisation.linearised`: O(N) right-hand sides,
    block-sparse M, K, C; the path of large systems): the states are the
    linearisation's coordinates at the same steps, so the entries are the
    dense path's up to round-off."""
    nb3 = coords.base_index.size
    npos = coords.n_pos
    keep = np.arange(nb3, npos)
    step = difference_steps(system, coords, RATE_STEP, RATE_STEP)

    def states(rates: bool):
        def make(DU):
            Z = np.zeros((DU.shape[0], coords.nz))
            Z[:, (npos if rates else 0) + keep] = DU
            return coords.to_y(Z)
        return make

    lin = linearised(system, coords.y_eq, step[keep], step[npos + keep],
                     capture=("w_dx", "w_dxd", "w_f", "w_F"), position_states=states(False),
                     rate_states=states(True), exact=exact)
    Ms, Ks, Cs = lin.M, (-lin.Kq).tocsr(), (-lin.Kv).tocsr()
    sign = (system.body_i == 0).astype(float) - (system.body_j == 0).astype(float)
    to_base = sp.kron(sp.csr_matrix(sign[None, :]), sp.identity(3), format="csr")   # (3, 3M)
    rows = tuple(sp.csr_matrix(m) for m in (lin.outputs_q["w_dx"], lin.outputs_v["w_dxd"],
                                            lin.outputs_q["w_f"], lin.outputs_v["w_f"]))
    return (Ms.toarray(), Ks.toarray(), Cs.toarray(), None, None, None, None,
            (to_base @ lin.outputs_q["w_F"]).toarray(), (to_base @ lin.outputs_v["w_F"]).toarray(),
            (Ms, Ks, Cs), rows)


def mounted_system(system: System, y_eq: np.ndarray, sparse: bool | None = None,
                   exact: bool = True) -> MountedSystem:
    """The mounted system about the equilibrium ``y_eq`` (ny,), base held.

    Central differences of the right-hand side at ±1e-6 in each rotation
    and modal coordinate and ±1e-4 in each translation and rate (modal ones
    scaled as :func:`flexbed.dynamics.linear.model.difference_steps` scales
    them), the states those of the linearisation's coordinates
    (:class:`~flexbed.dynamics.linear.model.Coordinates`); exact for linear
    mounts up to round-off and O(1e-12) relative for the rotations'
    geometry. ``sparse`` (default: above :data:`DENSE_LIMIT` coordinates):
    the columns by colour classes of the mount graph
    (:func:`_sparse_parts`, O(N) right-hand sides, block-sparse matrices)
    rather than one by one (:func:`_dense_parts`, today's path, cheaper on
    small systems); both give the same matrices to round-off. ``exact``
    (default): K, C and the mount outputs written out analytically where
    :func:`flexbed.dynamics.tangent.tangent` applies (one right-hand side,
    round-off only; sparse or dense as ``sparse`` says); elsewhere the differences.
    """
    nfev0 = system.nfev
    coords = Coordinates(system, y_eq)
    nb3 = coords.base_index.size
    n = coords.n_pos - nb3
    if sparse is None:
        sparse = n > DENSE_LIMIT
    tg = None if sparse or not exact else tangent(system, coords.y_eq, dense=True,
                                                  capture=("w_dx", "w_dxd", "w_f", "w_F"))
    if tg is not None:
        parts = _exact_parts(system, coords, tg)
    else:
        parts = _sparse_parts(system, coords, exact) if sparse else _dense_parts(system, coords)
    M, K, C, D, Dv, Fq, Fv, Bq, Bv, mats, rows = parts
    k_t = _tangent(Fq, D) if rows is None else _tangent(rows[2], rows[0])
    c_t = _tangent(Fv, Dv) if rows is None else _tangent(rows[3], rows[1])
    K_el = np.zeros((n, n))
    for fc in system.flex_compiled:
        ia = coords.a_index[fc.qa.start - coords.y_a[0]:fc.qa.stop - coords.y_a[0]] - nb3
        K_el[np.ix_(ia, ia)] = fc.eom.K
    iota = np.zeros((n, 3))
    for s in range(coords.n_rigid):
        iota[coords.r_index[s] - nb3, np.arange(3)] = 1.0
    labels, owner = _labels(system, coords)
    return MountedSystem(labels=labels, body=owner, M=M, K=K, C=C, K_elastic=K_el,
                         D=D, Dv=Dv, Fq=Fq, Fv=Fv, k_tangent=k_t, c_tangent=c_t,
                         Bq=Bq, Bv=Bv, iota=iota,
                         moving_mass=float(iota[:, 0] @ M @ iota[:, 0]),
                         y_eq=coords.y_eq, coords=coords, evaluations=system.nfev - nfev0,
                         sparse=mats, mount_rows=rows)


def _tangent(F, D) -> np.ndarray:
    """Per row, the factor k with F_row = k D_row (a mount axis's force
    depends on that axis's deflection alone): least squares over the row.
    F, D (rows, n) dense, or sparse (the sums over their nonzeros)."""
    if sp.issparse(D):
        dd = np.asarray(D.multiply(D).sum(axis=1)).ravel()
        fd = np.asarray(F.multiply(D).sum(axis=1)).ravel()
    else:
        dd = np.einsum("rc,rc->r", D, D)
        fd = None
    out = np.zeros(D.shape[0])
    ok = dd > 0.0
    if fd is not None:
        out[ok] = fd[ok] / dd[ok]
    elif D.shape[1] > DENSE_LIMIT:           # every row, no copies of the selected ones
        out[ok] = np.einsum("rc,rc->r", F, D)[ok] / dd[ok]
    else:
        out[ok] = np.einsum("rc,rc->r", F[ok], D[ok]) / dd[ok]
    return out

"""The motion linearised by blocks of bodies: block-diagonal mass,
block-sparse stiffness and damping, from the colour-class differences of
:func:`flexbed.dynamics.jacobian.force_jacobian`.

``v̇ ≈ M⁻¹ (Kq δq + Kv δv)`` about a state, q the bodies' positions (δr,
small rotations δθ, modal δa), v their rates (ṙ, ω̄, ȧ); what the stiffness
check (:mod:`flexbed.dynamics.stiffness`) and the mounted system of large
scenes (:mod:`flexbed.dynamics.frequency.mounted`) are made of.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .jacobian import force_jacobian, mount_graph, perturbed_positions, perturbed_rates
from .rotation import A as rotation_matrix
from .system import System
from .tangent import tangent

__all__ = ["mass_blocks", "block_inverse", "acceleration_rows", "Linearised", "linearised"]


def mass_blocks(system: System, y: np.ndarray, modal: bool = True) -> sp.csr_matrix:
    """The mass matrix (n, n) at the state y for the rates [ṙ, ω̄ per body
    2…, ȧ] (m I and J of each rigid body, a flexible body's
    :meth:`~flexbed.dynamics.flexible.FlexibleEOM.mass_matrix`; without
    ``modal`` only its frame block), block-diagonal, sparse."""
    g = mount_graph(system, modal)
    lay = system.layout
    n_slots = len(lay.rigid)
    blocks = np.zeros((n_slots, 6, 6))
    blocks[:, :3, :3] = system.m_r[:, 0, None, None] * np.eye(3)
    blocks[:, 3:, 3:] = system.J
    rows = [np.repeat(np.arange(6 * n_slots).reshape(n_slots, 6), 6, axis=1).ravel()]
    cols = [np.tile(np.arange(6 * n_slots).reshape(n_slots, 6), (1, 6)).ravel()]
    flex_slots = {fc.slot for fc in system.flex_compiled}
    keep = np.array([s not in flex_slots for s in range(n_slots)], dtype=bool)
    vals = [np.where(keep[:, None, None], blocks, 0.0).ravel()]
    p = lay.split(y)["p"]
    for fc in system.flex_compiled:
        Mf = fc.eom.mass_matrix(rotation_matrix(p[fc.slot]), y[fc.qa])
        blk = g.blocks[fc.slot]
        Mf = Mf[:blk.size, :blk.size]
        rows.append(np.repeat(blk, blk.size))
        cols.append(np.tile(blk, blk.size))
        vals.append(np.array(Mf).ravel())
    return sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(g.n, g.n)).tocsr()


def block_inverse(system: System, M: sp.spmatrix, modal: bool = True) -> sp.csr_matrix:
    """The inverse of a block-diagonal matrix (n, n) whose blocks are the
    bodies' (the graph's blocks), block by block (batched dense inverses)."""
    g = mount_graph(system, modal)
    W = g.width
    n_slots = len(g.blocks)
    slot = np.zeros(g.n, dtype=np.intp)
    local = np.zeros(g.n, dtype=np.intp)
    for s, blk in enumerate(g.blocks):
        slot[blk] = s
        local[blk] = np.arange(blk.size)
    D = np.zeros((n_slots, W, W))
    D[:, np.arange(W), np.arange(W)] = 1.0            # padding: identity
    for s, blk in enumerate(g.blocks):
        D[s, np.arange(blk.size), np.arange(blk.size)] = 0.0
    c = M.tocoo()
    assert np.all(slot[c.row] == slot[c.col]), "not block-diagonal by the bodies"
    np.add.at(D, (slot[c.row], local[c.row], local[c.col]), c.data)
    Dinv = np.linalg.inv(D)
    rows, cols, vals = [], [], []
    for size in np.unique([b.size for b in g.blocks]):
        ss = np.array([s for s, b in enumerate(g.blocks) if b.size == size], dtype=np.intp)
        idx = np.stack([g.blocks[s] for s in ss])                       # (k, size)
        rows.append(np.repeat(idx, size, axis=1).ravel())
        cols.append(np.tile(idx, (1, size)).ravel())
        vals.append(Dinv[ss][:, :size, :size].ravel())
    return sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=(g.n, g.n)).tocsr()


def acceleration_rows(system: System, dY: np.ndarray, modal: bool = True) -> np.ndarray:
    """[r̈, ω̄̇ per body 2…, ä] (k, n) of rates dY (k, ny)."""
    lay = system.layout
    out = dY[:, lay.v_rigid]
    if modal and lay.n_modal:
        out = np.concatenate([out, dY[:, lay.v_modal]], axis=1)
    return out


@dataclass(frozen=True)
class Linearised:
    """The generalized forces linearised at a state.

    M : (n, n) sparse — mass matrix at the state (:func:`mass_blocks`);
    Kq, Kv : (n, n) sparse — ∂(M v̇)/∂q and ∂(M v̇)/∂v [N/m …, N s/m …]
    (M held at the state), q the positions of :func:`perturbed_positions`,
    v the rates of :func:`perturbed_rates`; outputs_q, outputs_v : dict of
    the mount fields' derivatives (3M, n); evaluations : int.
    """

    M: sp.csr_matrix
    Kq: sp.csr_matrix
    Kv: sp.csr_matrix
    outputs_q: dict
    outputs_v: dict
    evaluations: int


def linearised(system: System, y: np.ndarray, q_steps: np.ndarray, v_steps: np.ndarray, *,
               t: float = 0.0, seg_end: float = math.inf, capture: tuple = (),
               modal: bool = True, position_states=None, rate_states=None,
               exact: bool = False) -> Linearised:
    """:class:`Linearised` at the state y (ny,) by :func:`force_jacobian`,
    central steps ``q_steps`` (n,) and ``v_steps`` (n,); then ``v̇ ≈ M⁻¹
    (Kq δq + Kv δv)`` about y (exactly the right-hand side's derivative for
    rigid bodies; a flexible body's M(q) varies too, by (∂M/∂q) v̇, nil at an
    equilibrium). ``position_states`` and ``rate_states`` (callables DU (k,
    n) → states (k, ny)) replace :func:`perturbed_positions` and
    :func:`perturbed_rates` (another parametrisation of the rotations, the
    same to first order).

    ``exact``: at a state at rest, Kq, Kv and the mount fields' derivatives
    written out analytically (:func:`flexbed.dynamics.tangent.tangent`: one
    right-hand side, round-off only; the steps and state maps are then not
    used); where that does not apply (:func:`flexbed.dynamics.tangent.uncovered`:
    motion, loads on bodies, …) the central differences above."""
    Mb = mass_blocks(system, y, modal)
    if exact:
        tg = tangent(system, y, t=t, seg_end=seg_end, modal=modal, capture=capture)
        if tg is not None:
            return Linearised(Mb, tg.Kq, tg.Kv, tg.outputs_q, tg.outputs_v, tg.evaluations)
    if position_states is None:
        def position_states(DU):
            return perturbed_positions(system, y, DU)
    if rate_states is None:
        def rate_states(DV):
            return perturbed_rates(system, y, DV)

    def residual(dY, Y):
        return (Mb @ acceleration_rows(system, dY, modal).T).T

    fq = force_jacobian(system, y, residual, position_states, q_steps, modal=modal,
                        capture=capture, t=t, seg_end=seg_end)
    fv = force_jacobian(system, y, residual, rate_states, v_steps, modal=modal,
                        capture=capture, t=t, seg_end=seg_end)
    return Linearised(Mb, fq.R, fv.R, fq.outputs, fv.outputs, fq.evaluations + fv.evaluations)

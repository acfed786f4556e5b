"""Jacobians of the generalized forces, block-sparse by the mount graph.

Bodies interact only through mounts (the paper's point, eq. 10–15): the
generalized force on body b (6 rows: force [N] inertial and moment [N m]
body frame; then, for a flexible body, its modal forces) is

    R_b = L_b(q_b, v_b) + Σ_{mounts m at b} G_{m,b}(q_b) F_m(q_i, q_j, v_i, v_j)

with L_b the body's own terms (gravity, inertia, its elastic forces), F_m
the mount's inertial force on its end P_i (−F_m on P_j; the kernel's
``w_F``) and ``G_{m,b} = ±[I; ū_e~ A_bᵀ; Φ_eᵀ A_bᵀ]`` ((6 + n_modes) × 3,
ū_e the end's body-frame point, Φ_e the mode shapes there). Hence:

- perturbing at once the same coordinate of every body of an *independent
  set* S of the mount graph (no mount joins two of them), the change of
  R_b for b in S is ∂R_b/∂q_b alone (its neighbours did not move), and
  the change of each mount's F_m is due to its one perturbed end;
- so central differences over one colour class of a colouring of that
  graph give every diagonal block (from R_b, the one right-hand side's
  output) and every off-diagonal block (``G_{m,o} ΔF_m`` for the other end
  o of each mount), together with the derivatives of every mount output
  (deflections, rates, forces).

A greedy colouring (bodies by falling degree) of the reference scene's
graph has 2 classes (the bed; the two pieces of equipment), of the tiled
scenes too: 2 × 2 × (6 + modes) evaluations of the right-hand side, in one
compiled batch, whatever the number of bodies. Each evaluation is O(N),
so the Jacobian is O(N). The physics stays the kernel's
(:func:`flexbed.dynamics.kernel.evaluate`): this module only perturbs
states and attributes the captured differences.

:mod:`flexbed.dynamics.block_linearisation` builds on it the linearised
motion (block-diagonal mass, block-sparse stiffness and damping).

Coordinates: per body 2… δr (3) [m] and a small rotation δθ (3) [rad] about
the body axes, then the modal coordinates δa [kg^1/2 m] of each flexible
body (when included), as in :mod:`flexbed.dynamics.statics` and the
mounted system of :mod:`flexbed.dynamics.frequency.mounted`; rates ṙ,
ω̄, ȧ alike.
"""

from __future__ import annotations

import math
import weakref
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .bounded_cache import BoundedCache
from .rotation import A as rotation_matrix
from .rotation import quat_mul
from .system import System

__all__ = ["MountGraph", "mount_graph", "ForceJacobian", "force_jacobian",
           "rotvec_rows", "perturbed_positions", "perturbed_rates"]


@dataclass(frozen=True)
class MountGraph:
    """The unknowns of the bodies 2… and the colouring of their mount graph.

    n : int — unknowns (6 per body, then the included modal coordinates);
    blocks : tuple of (k_s,) int arrays — the unknowns of each body slot s
    (its 6, then its modal ones); colour : (n_slots,) int — a proper
    colouring (no mount joins two slots of one colour); classes : tuple of
    int arrays — the slots of each colour; end_slot : (M, 2) int — the slot
    of each mount's ends i, j (−1 for the base); width : int — the largest
    block.
    """

    n: int
    blocks: tuple
    colour: np.ndarray
    classes: tuple
    end_slot: np.ndarray
    width: int
    modal: bool


def _colouring(n_slots: int, edges: np.ndarray) -> np.ndarray:
    """Greedy proper colouring, slots by falling degree (then by index)."""
    nbrs = [set() for _ in range(n_slots)]
    for a, b in edges:
        if a != b:
            nbrs[a].add(b)
            nbrs[b].add(a)
    order = sorted(range(n_slots), key=lambda s: (-len(nbrs[s]), s))
    colour = np.full(n_slots, -1, dtype=int)
    for s in order:
        used = {colour[t] for t in nbrs[s]}
        c = 0
        while c in used:
            c += 1
        colour[s] = c
    return colour


def _graph(system: System, modal: bool) -> MountGraph:
    lay = system.layout
    n_slots = len(lay.rigid)
    blocks = [list(range(6 * s, 6 * s + 6)) for s in range(n_slots)]
    n = 6 * n_slots
    if modal:
        for fc in system.flex_compiled:
            k = fc.eom.n
            blocks[fc.slot] += list(range(n, n + k))
            n += k
    end_slot = np.stack([np.asarray(system.body_i) - 1, np.asarray(system.body_j) - 1], axis=1)
    inner = end_slot[(end_slot >= 0).all(axis=1)]
    colour = _colouring(n_slots, inner)
    classes = tuple(np.flatnonzero(colour == c) for c in range(int(colour.max(initial=-1)) + 1))
    blocks = tuple(np.array(b, dtype=np.intp) for b in blocks)
    for b in blocks:
        b.setflags(write=False)
    return MountGraph(n, blocks, colour, classes, end_slot,
                      max((b.size for b in blocks), default=0), modal)


_GRAPHS: "weakref.WeakKeyDictionary[System, dict]" = weakref.WeakKeyDictionary()
#: what depends on the topology alone (:func:`by_topology`): a study's variants share it
_BY_TOPOLOGY = BoundedCache(8)
_TOPOLOGIES: "weakref.WeakKeyDictionary[System, tuple]" = weakref.WeakKeyDictionary()


def topology(system: System) -> tuple:
    """A hashable key equal for systems whose mount graph and sparsity
    patterns are the same: the state's layout, the mounts' bodies and
    ends, the flexible bodies' slots and modes, the inputs' table (which
    bodies carry loads). Variants of a scene that change numbers only
    (stiffnesses, masses, positions) share it."""
    key = _TOPOLOGIES.get(system)
    if key is None:
        d = system.data
        key = (system.layout, np.asarray(system.body_i).tobytes(),
               np.asarray(system.body_j).tobytes(), np.asarray(d.end_flex).tobytes(),
               tuple((fc.slot, fc.eom.n) for fc in system.flex_compiled),
               np.asarray(d.in_ints).tobytes(), np.asarray(d.in_ints).shape)
        _TOPOLOGIES[system] = key
    return key


def by_topology(system: System, name: str, make):
    """``make()`` once per :func:`topology` of ``system`` and ``name`` (a
    few kept): what depends on the topology alone (read only)."""
    return _BY_TOPOLOGY.get((name, topology(system)), make)


def mount_graph(system: System, modal: bool = True) -> MountGraph:
    """The :class:`MountGraph` of a system (made once per topology and
    ``modal``: :func:`by_topology`)."""
    per = _GRAPHS.setdefault(system, {})
    if modal not in per:
        per[modal] = by_topology(system, f"graph-{modal}", lambda: _graph(system, modal))
    return per[modal]


def rotvec_rows(theta: np.ndarray) -> np.ndarray:
    """Euler parameters (..., 4) of the rotations by the vectors theta (..., 3) [rad]."""
    angle = np.sqrt(np.sum(theta * theta, axis=-1, keepdims=True))
    half = 0.5 * angle
    small = angle < 1e-300
    safe = np.where(small, 1.0, angle)
    p = np.concatenate([np.cos(half), np.sin(half) / safe * theta], axis=-1)
    p[..., 0] = np.where(small[..., 0], 1.0, p[..., 0])
    p[..., 1:] = np.where(small, 0.0, p[..., 1:])
    return p


def perturbed_positions(system: System, y: np.ndarray, DU: np.ndarray) -> np.ndarray:
    """States (k, ny) for position steps DU (k, n) from y: translations added,
    rotations composed ``p ← p ⊗ p(δθ)`` (then normalised), modal
    coordinates added (DU: 6 per body 2…, then the modal ones if n says so)."""
    lay = system.layout
    n = system.n_rigid
    k = DU.shape[0]
    Y = np.repeat(np.asarray(y, dtype=float)[None, :], k, axis=0)
    q = Y[:, lay.q_rigid].reshape(k, n, 7)
    body = DU[:, :6 * n].reshape(k, n, 6)
    q[:, :, :3] += body[:, :, :3]
    p = quat_mul(q[:, :, 3:], rotvec_rows(body[:, :, 3:]))    # broadcasts over rows
    q[:, :, 3:] = p / np.sqrt(np.sum(p * p, axis=-1, keepdims=True))
    Y[:, lay.q_rigid] = q.reshape(k, 7 * n)
    if DU.shape[1] > 6 * n:
        Y[:, lay.q_modal] += DU[:, 6 * n:]
    return Y


def perturbed_rates(system: System, y: np.ndarray, DV: np.ndarray) -> np.ndarray:
    """States (k, ny) for rate steps DV (k, n) added to ṙ, ω̄ (6 per body 2…)
    and ȧ (if n says so)."""
    lay = system.layout
    n = system.n_rigid
    Y = np.repeat(np.asarray(y, dtype=float)[None, :], DV.shape[0], axis=0)
    Y[:, lay.v_rigid] += DV[:, :6 * n]
    if DV.shape[1] > 6 * n:
        Y[:, lay.v_modal] += DV[:, 6 * n:]
    return Y


@dataclass(frozen=True)
class ForceJacobian:
    """Derivatives of the generalized forces and of the mount outputs.

    R : (n, n) sparse CSR — ∂R/∂(columns) [N per m, N per rad, …];
    outputs : dict name → (M·3, n) sparse CSR of the captured mount fields
    (``w_dx``, ``w_dxd``, ``w_f``, ``w_F``) per column; evaluations : int.
    """

    R: sp.csr_matrix
    outputs: dict
    evaluations: int


def _end_maps(system: System, y: np.ndarray, graph: MountGraph) -> np.ndarray:
    """G of every mount end at the state y: (2M, width, 3), the map from the
    mount's inertial force F_m [N] to the generalized force on the end's
    body (sign included; rows past the body's block and ends on the base
    are zero)."""
    lay = system.layout
    M = system.M
    p = lay.split(y)["p"]
    A = rotation_matrix(p) if p.shape[0] else np.zeros((0, 3, 3))
    slot = np.concatenate([graph.end_slot[:, 0], graph.end_slot[:, 1]])       # (2M,)
    on = slot >= 0
    ub = np.array(system.S, dtype=float)                                       # (2M, 3)
    end_flex = np.asarray(system.data.end_flex)
    end_phi = np.asarray(system.data.end_phi)                                  # (2M, 3, nm)
    flex = system.flex_compiled
    for k, fc in enumerate(flex):
        ends = np.flatnonzero(end_flex == k)
        ub[ends] += end_phi[ends, :, :fc.eom.n] @ y[fc.qa]
    sg = np.where(np.arange(2 * M) < M, 1.0, -1.0)
    At = np.where(on[:, None, None], np.swapaxes(A[np.maximum(slot, 0)], 1, 2), 0.0) \
        if A.shape[0] else np.zeros((2 * M, 3, 3))
    G = np.zeros((2 * M, graph.width, 3))
    G[:, :3] = sg[:, None, None] * np.eye(3) * on[:, None, None]
    G[:, 3:6] = sg[:, None, None] * np.cross(ub[:, None, :], np.swapaxes(At, 1, 2)[:, :, :],
                                             axis=-1).transpose(0, 2, 1)
    if graph.modal:
        for k, fc in enumerate(flex):
            ends = np.flatnonzero((end_flex == k) & on)
            G[ends, 6:6 + fc.eom.n] = sg[ends, None, None] * np.einsum(
                "ecj,ecd->ejd", end_phi[ends, :, :fc.eom.n], At[ends])
    return G


def force_jacobian(system: System, y: np.ndarray, residual, states, steps: np.ndarray, *,
                   modal: bool = True, capture: tuple = ("w_F",), t: float = 0.0,
                   seg_end: float = math.inf) -> ForceJacobian:
    """Central differences of the generalized forces by colour classes.

    Parameters
    ----------
    system : System
    y : (ny,) array
        The state differentiated about.
    residual : callable
        ``residual(dY, Y)`` → (k, n) generalized forces of the rows of a
        batch (states Y (k, ny), their rates dY from the right-hand side).
    states : callable
        ``states(DU)`` → (k, ny) states for deviations DU (k, n) of the
        columns (a position or rate per unknown of the graph).
    steps : (n,) array
        The central-difference step of each column.
    modal : bool
        The flexible bodies' modal coordinates are unknowns.
    capture : tuple of str
        Mount fields (M, 3) to differentiate too (``w_dx``, ``w_dxd``,
        ``w_f``, ``w_F``).
    t, seg_end : float
        Time [s] and segment end of the evaluations (as for ``System.rhs``).

    Returns
    -------
    ForceJacobian
    """
    g = mount_graph(system, modal)
    n = g.n
    M = system.M
    W = g.width
    fields = tuple(dict.fromkeys(("w_F",) + tuple(capture)))
    table = np.full((len(g.blocks), W), -1, dtype=np.intp)     # slot → its unknowns, padded
    for s, blk in enumerate(g.blocks):
        table[s, :blk.size] = blk
    # perturbations: per colour class and local index j, the j-th unknown of
    # every body of the class that has one (central: + then −)
    pert = []
    for cls in g.classes:
        for j in range(W):
            slots = cls[table[cls, j] >= 0]
            if slots.size:
                pert.append((j, slots))
    P = len(pert)
    DU = np.zeros((2 * P, n))
    for p, (j, slots) in enumerate(pert):
        cols = table[slots, j]
        DU[p, cols] = steps[cols]
        DU[P + p, cols] = -steps[cols]
    Y = states(DU)
    dY, cap = system.rhs_batch(np.full(2 * P, float(t)), Y, capture=fields, seg_end=seg_end)
    R = residual(dY, Y)                                          # (2P, n)
    dR = R[:P] - R[P:]
    G = _end_maps(system, y, g)                                  # (2M, W, 3)
    ends = np.concatenate([g.end_slot[:, 0], g.end_slot[:, 1]])  # (2M,)
    rows, cols_out, vals = [], [], []
    out_r = {f: [] for f in capture}
    out_c = {f: [] for f in capture}
    out_v = {f: [] for f in capture}
    slot_col = np.full(len(g.blocks) + 1, -1, dtype=np.intp)   # last: the base, never perturbed
    for p, (j, slots) in enumerate(pert):
        cols = table[slots, j]
        h2 = 2.0 * steps[cols]
        # diagonal blocks: the perturbed bodies' own rows
        blk = table[slots]                                       # (k, W)
        ok = blk >= 0
        rows.append(blk[ok])
        cols_out.append(np.broadcast_to(cols[:, None], blk.shape)[ok])
        vals.append((dR[p][np.maximum(blk, 0)] / h2[:, None])[ok])
        # mounts with a perturbed end: their outputs, and the other end's rows
        slot_col[:] = -1
        slot_col[slots] = cols
        ci, cj = slot_col[g.end_slot[:, 0]], slot_col[g.end_slot[:, 1]]
        hit = np.flatnonzero((ci >= 0) | (cj >= 0))
        if not hit.size:
            continue
        col_m = np.where(ci[hit] >= 0, ci[hit], cj[hit])
        h_m = 2.0 * steps[col_m]
        dF = (cap["w_F"][p, hit] - cap["w_F"][P + p, hit]) / h_m[:, None]     # (h, 3)
        other = np.where(ci[hit] >= 0, hit + M, hit)               # the unmoved end
        o_slot = ends[other]
        # the other end's rows, unless it is the base or moved too (a mount on one body)
        keep = (o_slot >= 0) & ((ci[hit] >= 0) ^ (cj[hit] >= 0))
        ob = table[o_slot[keep]]                                    # (h', W)
        v = np.einsum("hwc,hc->hw", G[other[keep]], dF[keep])
        ok = ob >= 0
        rows.append(ob[ok])
        cols_out.append(np.broadcast_to(col_m[keep][:, None], ob.shape)[ok])
        vals.append(v[ok])
        for f in capture:
            d = (cap[f][p, hit] - cap[f][P + p, hit]) / h_m[:, None]          # (h, 3)
            out_r[f].append((3 * hit[:, None] + np.arange(3)[None, :]).ravel())
            out_c[f].append(np.repeat(col_m, 3))
            out_v[f].append(d.ravel())
    Rj = _coo(rows, cols_out, vals, (n, n))
    outputs = {f: _coo(out_r[f], out_c[f], out_v[f], (3 * M, n)) for f in capture}
    return ForceJacobian(Rj, outputs, 2 * P)


def _coo(rows, cols, vals, shape) -> sp.csr_matrix:
    if not rows:
        return sp.csr_matrix(shape)
    return sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                         shape=shape).tocsr()


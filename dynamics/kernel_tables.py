"""A compiled system's scene as the kernel's flat arrays.

:func:`kernel_storage` builds every field of
:data:`flexbed.dynamics.kernel.FIELDS` once, from the Python-side arrays of
a :class:`flexbed.dynamics.system.System` (bodies, mounts, laws, flexible
bodies, the base's inputs), and packs them into the two arrays the
compiled right-hand side takes (:func:`flexbed.dynamics.kernel.pack`).
The tables of each kind of thing are built by a function of their own:
:func:`law_tables`, :func:`flexible_tables`, :func:`input_tables`,
:func:`work_arrays`. The views of the fields that describe the scene are
read-only; the work arrays (``w_*``) are the kernel's to write.
"""

from __future__ import annotations

import math

import numpy as np

from .kernel import Compiled, pack
from .laws import LawBank
from .maxwell_terms import maxwell_tables
from .shared_parts import tables_of
from .time_functions import Sinusoid

__all__ = ["kernel_storage", "law_tables", "flexible_tables", "input_tables", "load_points",
           "work_arrays",
           "stack_tables"]


def stack_tables(rows: list, n_missing_cols: int):
    """Piecewise polynomials padded into the kernel's arrays.

    Parameters
    ----------
    rows : list of lists of equal length
        PiecewisePolynomial or None (the zero function).
    n_missing_cols : int
        The number of columns when there are no rows.

    Returns
    -------
    breaks : (r, c, nb) array
        +inf padded.
    origins : (r, c, nb + 1) array
    coeffs : (r, c, nb + 1, d + 1) array
        Ascending, zero padded; beyond the last break the right tail.
    """
    cols = len(rows[0]) if rows else n_missing_cols
    funcs = [f for r in rows for f in r if f is not None]
    nbk = max([f.breaks.size for f in funcs], default=1)
    deg = max([f.degree for f in funcs], default=0)
    b = np.full((len(rows), cols, nbk), np.inf)
    o = np.zeros((len(rows), cols, nbk + 1))
    c = np.zeros((len(rows), cols, nbk + 1, deg + 1))
    for i, r in enumerate(rows):
        for j, f in enumerate(r):
            if f is None:
                continue
            n = f.breaks.size
            b[i, j, :n] = f.breaks
            o[i, j, :n + 1] = f.origins
            o[i, j, n + 1:] = f.origins[-1]
            c[i, j, :n + 1, :f.degree + 1] = f.coeffs
            # beyond the last break the padding keeps the right tail
            c[i, j, n + 1:, :f.degree + 1] = f.coeffs[-1]
    return b, o, c


def law_tables(bank: LawBank, M: int) -> dict:
    """The mount laws, one per (mount, direction) = 3 M entries: ``law_kind``
    (0 linear, 1 polynomial, 2 curve) and ``law_row`` (3M,), and one table
    per kind in law order: ``lin_kc`` (·, 2) k [N/m] and c [N s/m];
    ``poly_k``, ``poly_c`` (·, 9) ascending coefficients; ``crv_b``,
    ``crv_o``, ``crv_c`` the spring's and the damper's curves
    (:func:`stack_tables`); the bump stops ``stop_gap``, ``stop_kc`` (3M,
    2), with their work arrays ``w_contact`` (3M,) and ``w_hold`` (1,),
    all with no rows when no mount has a stop."""
    if bank.lin.size == 3 * M and not bank.stopped.size:
        # linear laws alone, no stop: only k and c differ between such banks
        fixed = tables_of(None, ("linear laws", M), lambda: _law_tables(bank, M))
        return dict(fixed, lin_kc=np.stack([bank.k, bank.c], axis=1))
    return _law_tables(bank, M)


def _law_tables(bank: LawBank, M: int) -> dict:
    """:func:`law_tables`, made."""
    kind = np.zeros(3 * M, dtype=np.int64)
    row = np.zeros(3 * M, dtype=np.int64)
    for code, idx in ((0, bank.lin), (1, bank.poly), (2, bank.curve)):
        kind[idx] = code
        row[idx] = np.arange(idx.size)
    lin_kc = np.stack([bank.k, bank.c], axis=1) if bank.lin.size else np.zeros((0, 2))
    poly_k = np.zeros((bank.poly.size, 9))
    poly_c = np.zeros((bank.poly.size, 9))
    poly_k[:, :bank.pk.shape[1]] = bank.pk
    poly_c[:, :bank.pc.shape[1]] = bank.pc
    crv_b, crv_o, crv_c = stack_tables([[fs, fd] for fs, fd in zip(bank.curve_springs,
                                                                 bank.curve_dampers)], 2)
    rows = 3 * M if bank.stopped.size else 0          # no stop anywhere: empty tables
    return dict(law_kind=kind, law_row=row, lin_kc=np.ascontiguousarray(lin_kc, dtype=float),
                poly_k=poly_k, poly_c=poly_c, crv_b=crv_b, crv_o=crv_o, crv_c=crv_c,
                stop_gap=bank.stop_gap[:rows].copy(), stop_kc=bank.stop_kc[:rows].copy(),
                w_contact=np.zeros(rows), w_hold=np.zeros(1))


def flexible_tables(flex: tuple, nb: int, end_body: np.ndarray, S: np.ndarray) -> dict:
    """The flexible bodies, padded to the most modes nm.

    Parameters
    ----------
    flex : tuple of FlexCompiled
        The system's flexible bodies
        (:attr:`flexbed.dynamics.system.System.flex_compiled`); their
        models give the mode shapes at the mount ends.
    nb : int
        Number of bodies.
    end_body : (E,) int array
        Body of each mount end.
    S : (E, 3) array [m]
        The ends in their body's frame.

    Returns
    -------
    dict
        ``body_flex`` (nb,) and ``end_flex`` (E,): flexible body index or
        −1; ``end_phi`` (E, 3, nm) mode shapes at the ends [kg^-1/2];
        ``fx_ints`` (nf, 4) body, modes, offsets of a and ȧ in y; the
        invariants ``fx_m`` … ``fx_I9``, ``fx_K``, ``fx_C``.
    """
    nf = len(flex)
    nm = max((fc.eom.n for fc in flex), default=0)
    fx_ints = np.zeros((nf, 4), dtype=np.int64)
    fx = {key: np.zeros((nf,) + shape) for key, shape in (
        ("m", ()), ("I2", (3,)), ("I3", (3, nm)), ("I4", (3, nm)), ("I5", (nm, 3, nm)),
        ("I6", (nm, nm)), ("K", (nm, nm)), ("C", (nm, nm)), ("I7", (3, 3)),
        ("I8", (nm, 3, 3)), ("I9", (nm, nm, 3, 3)))}
    body_flex = np.full(nb, -1, dtype=np.int64)
    end_flex = np.full(end_body.size, -1, dtype=np.int64)
    end_phi = np.zeros((end_body.size, 3, nm))
    for k, fc in enumerate(flex):
        e = fc.eom
        fb = e.body
        n = e.n
        body_flex[fc.body] = k
        fx_ints[k] = (fc.body, n, fc.qa.start, fc.va.start)
        fx["m"][k] = e.m
        fx["I2"][k] = e.I2
        fx["I3"][k][:, :n] = e.I3
        fx["I4"][k][:, :n] = e.I4
        fx["I5"][k][:n, :, :n] = e.I5
        fx["I6"][k][:n, :n] = e.I6
        fx["K"][k][:n, :n] = e.K
        fx["C"][k][:n, :n] = e.C
        fx["I7"][k] = e.I7
        fx["I8"][k][:n] = e.I8
        fx["I9"][k][:n, :n] = e.I9
        for end in np.flatnonzero(end_body == fc.body):
            end_flex[end] = k
            end_phi[end, :, :n] = fb.point_shapes[fb.point_index(S[end])]
    return dict(body_flex=body_flex, end_flex=end_flex, end_phi=end_phi, fx_ints=fx_ints,
                **{"fx_" + key: v for key, v in fx.items()})


def input_tables(items: tuple, roles: tuple, compiled: tuple, body_index=None) -> dict:
    """The inputs, one row each (see :mod:`flexbed.dynamics.kernel`).

    Parameters
    ----------
    items : tuple of Drive, Load and BodyLoad
        The scene's drives, its loads on the base, its loads on bodies
        (:attr:`flexbed.dynamics.base_inputs.BaseInputs.items`).
    roles : tuple of int
        0 for a drive, 1 for a load on the base, 2 on a body, per item.
    compiled : tuple of TimeFunction
        Their compiled shapes, in the same order.
    body_index : callable, optional
        Body name → index (needed when there are loads on bodies).

    Returns
    -------
    dict
        ``in_ints`` (ni, 6) kind (0 piecewise, 1 sinusoid), direction,
        role, body, frame (0 inertial, 1 body), quantity (0 force, 1
        moment); ``in_sin`` (ni, 5) amplitude, ω [rad/s], phase [rad],
        start, end [s]; ``in_b``, ``in_o``, ``in_c`` the value, first and
        second integral of a piecewise input (:func:`stack_tables`).
    """
    in_ints = np.zeros((len(items), 6), dtype=np.int64)
    in_sin = np.zeros((len(items), 5))
    tables = []
    for i, (item, role) in enumerate(zip(items, roles)):
        sh = item.shape
        in_ints[i, :3] = (1 if isinstance(sh, Sinusoid) else 0, item.direction, role)
        if role == 2:
            in_ints[i, 3:] = (body_index(item.body), item.frame == "body",
                              item.quantity == "moment")
        if isinstance(sh, Sinusoid):
            in_sin[i] = (sh.amplitude, 2.0 * math.pi * sh.frequency, sh.phase, sh.start,
                         sh.start + sh.duration)
            tables.append([None, None, None])
        else:
            f = compiled[i]
            tables.append([f.value, f.first, f.second])
    in_b, in_o, in_c = stack_tables(tables, 3)
    return dict(in_ints=in_ints, in_sin=in_sin, in_b=in_b, in_o=in_o, in_c=in_c)


def load_points(items: tuple, roles: tuple, flex: tuple, body_index) -> dict:
    """The loads on bodies' points: ``in_pt`` (ni, 3) [m] in the body frame
    and ``in_phi`` (ni, 3, nm) the mode shapes there [kg^-1/2] on a
    flexible body (zero rows for the base's inputs and rigid bodies)."""
    nm = max((fc.eom.n for fc in flex), default=0)
    pt = np.zeros((len(items), 3))
    phi = np.zeros((len(items), 3, nm))
    by_body = {fc.body: fc for fc in flex}
    for i, (item, role) in enumerate(zip(items, roles)):
        if role != 2:
            continue
        pt[i] = item.point
        fc = by_body.get(body_index(item.body))
        if fc is not None:
            fb = fc.eom.body
            phi[i, :, :fc.eom.n] = fb.point_shapes[fb.point_index(item.point)]
    return dict(in_pt=pt, in_phi=phi)


def work_arrays(nb: int, M: int, nf: int, nm: int) -> dict:
    """The kernel's work arrays (``w_*`` of :data:`flexbed.dynamics.kernel.FIELDS`),
    zero, for nb bodies, M mounts, nf flexible bodies of at most nm modes."""
    N = 6 + nm
    return dict(
        w_A=np.zeros((nb, 3, 3)), w_P=np.zeros((2 * M, 3)), w_Pd=np.zeros((2 * M, 3)),
        w_ub=np.zeros((2 * M, 3)), w_dx=np.zeros((M, 3)), w_dxd=np.zeros((M, 3)),
        w_f=np.zeros((M, 3)), w_F=np.zeros((M, 3)), w_force=np.zeros((nb, 3)),
        w_torque=np.zeros((nb, 3)), w_flexQ=np.zeros((nf, N)), w_acc=np.zeros((nb, 6)),
        w_base=np.zeros((3, 3)), w_M=np.zeros((nf, N, N)), w_Q=np.zeros(N + nm),
        w_T=np.zeros((nm, 3, 3)), w_gb=np.zeros(3))


def kernel_storage(system) -> tuple[tuple[np.ndarray, np.ndarray], Compiled]:
    """The scene of ``system`` as the kernel's packed storage.

    Parameters
    ----------
    system : System
        Read, once its Python-side arrays are built (it calls this last in
        its constructor): ``layout``, ``nb``, ``M``, ``base_motion``, ``g``,
        ``mass``, ``J``, ``J_vec``, ``J_eig``, ``inputs``, ``body_i``,
        ``body_j``, ``end_body``, ``S``, ``U``, ``d0``, ``laws`` and
        ``flex_compiled``.

    Returns
    -------
    storage : tuple (F, I)
        The float64 and int64 arrays of :func:`flexbed.dynamics.kernel.pack`.
    views : Compiled
        Views of every field into them; those of the scene read-only.
    """
    nb, M, lay = system.nb, system.M, system.layout
    flex = system.flex_compiled
    nf = len(flex)
    nm = max((fc.eom.n for fc in flex), default=0)
    mode = {"fixed": 0, "driven": 1, "free": 2}[system.base_motion]
    ints = np.array([nb, M, nf, mode, lay.q_rigid.start, lay.v_rigid.start,
                     lay.q_base.start, lay.v_base.start, lay.work.start,
                     lay.q_modal.start, lay.v_modal.start, 0], dtype=np.int64)
    J = np.zeros((nb, 3, 3))
    J[1:] = system.J
    Jinv = np.zeros((nb, 3, 3))
    Jinv[1:] = np.einsum("bij,bj,bkj->bik", system.J_vec, 1.0 / system.J_eig, system.J_vec)
    inputs = system.inputs
    scene = system.scene
    names = tuple(b.name for b in scene.bodies)
    E = system.end_body.size
    if nf:
        flexible = flexible_tables(flex, nb, system.end_body, system.S)
        points = load_points(inputs.items, inputs.roles, flex, scene.body_index)
    else:                               # what they are without flexible bodies
        flexible = tables_of(None, ("flexible", nb, E),
                             lambda: flexible_tables(flex, nb, system.end_body, system.S))
        points = tables_of(inputs.compiled, ("points", inputs.roles, names), lambda: load_points(
            inputs.items, inputs.roles, flex, scene.body_index))
    maxwell = (tables_of(None, ("maxwell", M), lambda: maxwell_tables((), [""] * M, 0))
               if not scene.maxwell else
               maxwell_tables(scene.maxwell, [m.name for m in scene.mounts], lay.internal.start))
    storage, views = pack(dict(
        ints=ints, gravity=system.g, mass=system.mass, J=J, Jinv=Jinv,
        r0_base=inputs.r0, support=inputs.support,
        body_i=system.body_i, body_j=system.body_j, S=system.S, U=system.U, d0=system.d0,
        **law_tables(system.laws, M),
        **flexible,
        **tables_of(inputs.compiled, ("inputs", inputs.roles, names), lambda: input_tables(
            inputs.items, inputs.roles, inputs.compiled, scene.body_index)),
        **points,
        **maxwell,
        **tables_of(None, ("work", nb, M, nf, nm), lambda: work_arrays(nb, M, nf, nm))), lay.ny,
        frozen=True)
    return storage, views

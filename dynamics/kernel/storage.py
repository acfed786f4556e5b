"""The kernel's scene storage: the arrays of :class:`Compiled`, packed into
one float64 and one int64 array (:func:`pack`), and their views rebuilt
inside compiled code (``view1`` … ``view5``)."""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np
from numba import carray, njit, types
from numba.extending import intrinsic

from ..bounded_cache import BoundedCache

__all__ = ["Compiled", "FIELDS", "KINDS", "HEADER", "pack",
           "view1", "view2", "view3", "view4", "view5"]

#: The kernel's fields, in the order of the storage's table (nb bodies, M mounts, E = 2 M
#: ends, nf flexible bodies of at most nm modes, ni inputs; each built by
#: flexbed.dynamics.kernel_tables.kernel_storage).
FIELDS = (
    # sizes and layout: [nb, M, nf, base_mode (0 fixed, 1 driven, 2 free), qr, vr, qb, vb,
    #                    w0, qm, vm, through (0 the whole right-hand side; 1 up to the
    #                    mount forces, sections 1-4: dy is then not written in full)]
    "ints",
    "gravity",          # (3,) [m/s²]
    "mass",             # (nb,) [kg]
    "J", "Jinv",        # (nb, 3, 3) [kg m², 1/(kg m²)] (row 0 unused)
    "body_flex",        # (nb,) int: flexible body index, or -1
    "r0_base",          # (3,) [m]
    "support",          # (3,) [N]
    # mounts
    "body_i", "body_j",  # (M,) int
    "S",                # (E, 3) [m] ends in their body's frame, i ends first
    "U",                # (M, 3, 3) rows u_k in body i's frame
    "d0",               # (M, 3) [m] U (A_iᵀ l0)
    "end_flex",         # (E,) int: flexible body index of the end's body, or -1
    "end_phi",          # (E, 3, nm) mode shapes at the ends [kg^-1/2]
    # laws, one per (mount, direction) = 3 M entries
    "law_kind",         # (3M,) int: 0 linear, 1 polynomial, 2 curve
    "law_row",          # (3M,) int: row in the kind's table
    "lin_kc",           # (·, 2) k [N/m], c [N s/m]
    "poly_k", "poly_c",  # (·, 9) ascending coefficients
    "crv_b", "crv_o", "crv_c",   # (·, 2, nbk), (·, 2, nbk + 1), (·, 2, nbk + 1, 4) spring, damper
    # flexible bodies
    "fx_ints",          # (nf, 4): body, n modes, offset of a in y, offset of ȧ in y
    "fx_m",             # (nf,) [kg]
    "fx_I2",            # (nf, 3)
    "fx_I3", "fx_I4",   # (nf, 3, nm)
    "fx_I5",            # (nf, nm, 3, nm)
    "fx_I6", "fx_K", "fx_C",   # (nf, nm, nm)
    "fx_I7",            # (nf, 3, 3)
    "fx_I8",            # (nf, nm, 3, 3)
    "fx_I9",            # (nf, nm, nm, 3, 3)
    # inputs: drives and loads of the base, loads on bodies
    "in_ints",          # (ni, 6): kind, direction, role (0 drive, 1 load on the base, 2 load
                        # on a body), body, frame (0 inertial, 1 body), quantity (0 force,
                        # 1 moment)
    "in_sin",           # (ni, 5): amplitude, ω [rad/s], phase [rad], start, end [s]
    "in_b",             # (ni, 3, nbi) breaks of value, first, second integral (+inf padded)
    "in_o",             # (ni, 3, nbi + 1) origins
    "in_c",             # (ni, 3, nbi + 1, dmax + 1) ascending coefficients
    # work arrays
    "w_A",              # (nb, 3, 3)
    "w_P", "w_Pd",      # (E, 3) end positions, velocities [m, m/s]
    "w_ub",             # (E, 3) ū of each end in its body frame [m]
    "w_dx", "w_dxd", "w_f",    # (M, 3) [m, m/s, N]
    "w_F",              # (M, 3) [N] inertial force on P_i
    "w_force", "w_torque",     # (nb, 3) [N] inertial; [N m] body frame (rigid bodies)
    "w_flexQ",          # (nf, 6 + nm) body-frame generalized mount forces
    "w_acc",            # (nb, 6): r̈ [m/s²] inertial, ω̄̇ [rad/s²] body frame
    "w_base",           # (3, 3): base r, ṙ, r̈
    "w_M",              # (nf, 6 + nm, 6 + nm) M̄(a) of each flexible body, then its
                        # Cholesky factor L (lower triangle; the upper keeps M̄)
    "w_Q",              # (6 + nm + nm,) Q̄ then C ȧ
    "w_T",              # (nm, 3, 3) T_k = I8_k + Σ_l a_l I9_kl
    "w_gb",             # (3,) Aᵀ g
    # bump stops, one row per (mount, direction) with a stop or none at all
    "stop_gap",         # (3M or 0, 2) [m] compression and extension gaps (inf: no stop)
    "stop_kc",          # (3M or 0, 2) contact stiffness [N/m] and damping [N s/m]
    "w_contact",        # (3M or 0,) contact held by an integrator: −1 compression, 0 none,
                        # +1 extension (read only while w_hold[0] = 1)
    "w_hold",           # (1,) 1: the contacts of w_contact hold; 0: decided by Δx
    # loads on bodies, one row per input (zero for the base's)
    "in_pt",            # (ni, 3) [m] point of application in the body frame
    "in_phi",           # (ni, 3, nm) mode shapes at the point [kg^-1/2] (flexible body)
    # the elastomer mounts' Maxwell terms (flexbed.dynamics.maxwell_terms), sorted by row
    "mx_ints",          # (nt, 2) int: row 3 m + direction, offset of the term's state z in y
    "mx_k",             # (nt, 2) k_i [N/m], 1/τ_i [1/s]
    "w_relax",          # (1,) 1: the terms relaxed (z = Δx: no force, no rate; statics)
    "w_mx",             # (3M or 0, 2) per row Σ k_i [N/m], Σ k_i z_i [N] (no terms: no rows)
)

Compiled = namedtuple("Compiled", FIELDS)

#: Storage of each field: 'f' float64 or 'i' int64, and its number of dimensions.
KINDS = {
    "ints": ("i", 1), "gravity": ("f", 1), "mass": ("f", 1), "J": ("f", 3), "Jinv": ("f", 3),
    "body_flex": ("i", 1), "r0_base": ("f", 1), "support": ("f", 1), "body_i": ("i", 1),
    "body_j": ("i", 1), "S": ("f", 2), "U": ("f", 3), "d0": ("f", 2), "end_flex": ("i", 1),
    "end_phi": ("f", 3), "law_kind": ("i", 1), "law_row": ("i", 1), "lin_kc": ("f", 2),
    "poly_k": ("f", 2), "poly_c": ("f", 2), "crv_b": ("f", 3), "crv_o": ("f", 3),
    "crv_c": ("f", 4), "fx_ints": ("i", 2), "fx_m": ("f", 1), "fx_I2": ("f", 2),
    "fx_I3": ("f", 3), "fx_I4": ("f", 3), "fx_I5": ("f", 4), "fx_I6": ("f", 3),
    "fx_K": ("f", 3), "fx_C": ("f", 3), "fx_I7": ("f", 3), "fx_I8": ("f", 4), "fx_I9": ("f", 5),
    "in_ints": ("i", 2), "in_sin": ("f", 2), "in_b": ("f", 3), "in_o": ("f", 3),
    "in_c": ("f", 4), "w_A": ("f", 3), "w_P": ("f", 2), "w_Pd": ("f", 2), "w_ub": ("f", 2),
    "w_dx": ("f", 2), "w_dxd": ("f", 2), "w_f": ("f", 2), "w_F": ("f", 2), "w_force": ("f", 2),
    "w_torque": ("f", 2), "w_flexQ": ("f", 2), "w_acc": ("f", 2), "w_base": ("f", 2),
    "w_M": ("f", 3), "w_Q": ("f", 1), "w_T": ("f", 3), "w_gb": ("f", 1),
    "stop_gap": ("f", 2), "stop_kc": ("f", 2), "w_contact": ("f", 1), "w_hold": ("f", 1),
    "in_pt": ("f", 2), "in_phi": ("f", 3), "mx_ints": ("i", 2), "mx_k": ("f", 2),
    "w_relax": ("f", 1), "w_mx": ("f", 2),
}


#: Entries of the header at the start of the int64 storage I: the state's
#: size ny, the sizes of F and I, the number of fields; the fields' table
#: (offset and shape of each) follows it, then the integer fields.
HEADER = 4


@intrinsic
def _advance(typingctx, address, nbytes):
    """The address ``address`` (void *) advanced by ``nbytes`` bytes."""
    def codegen(context, builder, signature, args):
        return builder.gep(args[0], [args[1]])
    return types.voidptr(types.voidptr, types.int64), codegen


# The view of one field in its storage at address a (F: float64, I: int64)
# from its row m of the fields' table (offset, shape padded with 1), for 1
# to 5 dimensions; no checks (pack wrote a consistent table).

@njit(cache=True, no_cpython_wrapper=True)
def view1(a, m, dtype):
    return carray(_advance(a, 8 * m[0]), m[1], dtype)


@njit(cache=True, no_cpython_wrapper=True)
def view2(a, m, dtype):
    return carray(_advance(a, 8 * m[0]), (m[1], m[2]), dtype)


@njit(cache=True, no_cpython_wrapper=True)
def view3(a, m, dtype):
    return carray(_advance(a, 8 * m[0]), (m[1], m[2], m[3]), dtype)


@njit(cache=True, no_cpython_wrapper=True)
def view4(a, m, dtype):
    return carray(_advance(a, 8 * m[0]), (m[1], m[2], m[3], m[4]), dtype)


@njit(cache=True, no_cpython_wrapper=True)
def view5(a, m, dtype):
    return carray(_advance(a, 8 * m[0]), (m[1], m[2], m[3], m[4], m[5]), dtype)


def pack(fields: dict, ny: int, *, frozen: bool = False):
    """Pack a scene's arrays into one float64 and one int64 array.

    The compiled right-hand side (:func:`flexbed.dynamics.kernel.rhs.evaluate`)
    is called with the state, its derivative and these two arrays only; it
    rebuilds the views of every field inside compiled code (``view1`` …
    ``view5``). Where each field goes (the offsets, the header and the
    fields' table of I) is worked out once per set of shapes and kept
    (:class:`_Layout`): a study's variants share it and only copy their
    values.

    Parameters
    ----------
    fields : dict
        Every name of :data:`FIELDS` → array (any shape of the declared
        number of dimensions, :data:`KINDS`).
    ny : int
        Size of the state.
    frozen : bool
        The views of the fields that describe the scene (all but the work
        arrays, ``w_*``) read-only.

    Returns
    -------
    storage : tuple (F, I)
        F (·,) float64; I (·,) int64: the header (:data:`HEADER` entries:
        ny, F.size, I.size, len(FIELDS)), the fields' table (len(FIELDS), 6)
        (offset into F or I, then the shape padded with 1), the integer
        fields.
    views : Compiled
        NumPy views of every field into F and I (writes go to the storage;
        with ``frozen``, to the work arrays' alone).
    """
    arrays = []
    for name, _, dtype, ndim in _ORDER:
        a = fields[name]
        if type(a) is not np.ndarray or a.dtype != dtype:
            a = np.asarray(a, dtype=dtype)
        if a.ndim != ndim:
            raise ValueError(f"kernel field {name}: {a.ndim} dimensions, expected {ndim}")
        arrays.append(a)
    key = (ny,) + tuple(a.shape for a in arrays)
    lay = _LAYOUTS.get(key, lambda: _Layout(key))
    F = np.zeros(1) if lay.nF == 0 else np.empty(lay.nF)
    if lay.nF:
        np.concatenate([arrays[i].reshape(-1) for i in lay.float_fields], out=F)
    I = lay.header.copy()
    if lay.int_fields:
        np.concatenate([arrays[i].reshape(-1) for i in lay.int_fields], out=I[lay.i0:])
    if frozen:                          # views of read-only views are read-only
        Fr, Ir = F.view(), I.view()
        Fr.flags.writeable = False
        Ir.flags.writeable = False
        bases, which = (F, I, Fr, Ir), lay.frozen
    else:
        bases, which = (F, I), lay.plain
    views = [bases[b][o:e] if shape is None else
             bases[b][o:e].reshape(shape) if o != e else shape   # an empty field: its array
             for b, o, e, shape in which]
    return (F, I), Compiled._make(views)


class _Layout:
    """Where the fields of a given set of shapes go in (F, I), computed once
    per set (:data:`_LAYOUTS`): the sizes, the header and fields' table of I,
    and each field's storage, start, end and shape."""

    __slots__ = ("nF", "i0", "header", "rows", "plain", "frozen", "float_fields", "int_fields")

    def __init__(self, key: tuple):
        ny, shapes = key[0], key[1:]
        n = len(FIELDS)
        offsets = {"f": 0, "i": HEADER + 6 * n}
        rows = []
        for (_, kind, _, _), shape in zip(_ORDER, shapes):
            size = math.prod(shape)
            rows.append((kind, offsets[kind], offsets[kind] + size, shape))
            offsets[kind] += size
        self.nF = offsets["f"]
        self.i0 = HEADER + 6 * n
        header = np.empty(offsets["i"], dtype=np.int64)
        header[:HEADER] = (ny, max(self.nF, 1), offsets["i"], n)
        header[HEADER:self.i0] = [v for _, o, _, shape in rows
                                  for v in (o,) + shape + (1,) * (5 - len(shape))]
        header[self.i0:] = 0
        header.flags.writeable = False
        self.header = header
        self.rows = tuple(rows)
        # (storage: 0 F, 1 I, 2 F read-only, 3 I read-only; start; end; shape or
        # None for one dimension) without and with pack's ``frozen``; an empty
        # field (nothing to copy, nothing to write) is one array made here
        self.plain = tuple((kind == "i", o, e, _empty(kind, shape, True) if o == e else
                            shape if len(shape) > 1 else None) for kind, o, e, shape in rows)
        self.frozen = tuple((b + 2 * (not work), o, e,
                             _empty(kind, shape, work) if o == e else view)
                            for (kind, _, _, shape), (b, o, e, view), work
                            in zip(rows, self.plain, _WORK))
        self.float_fields = tuple(i for i, r in enumerate(rows) if r[0] == "f" and r[1] != r[2])
        self.int_fields = tuple(i for i, r in enumerate(rows) if r[0] == "i" and r[1] != r[2])


def _empty(kind: str, shape: tuple, writeable: bool) -> np.ndarray:
    """An array of no entries of ``shape`` for storage ``kind`` ('f' or 'i')."""
    a = np.zeros(shape, dtype=np.float64 if kind == "f" else np.int64)
    a.flags.writeable = writeable
    return a


#: The fields in order: name, storage ('f' or 'i'), dtype, number of dimensions.
_ORDER = tuple((name, KINDS[name][0], np.dtype(np.float64 if KINDS[name][0] == "f" else np.int64),
                KINDS[name][1]) for name in FIELDS)

#: Per field: a work array (``w_*``), the kernel's to write.
_WORK = tuple(name.startswith("w_") for name in FIELDS)

#: The layouts of the sets of shapes met lately (a study's variants share one).
_LAYOUTS = BoundedCache(16)

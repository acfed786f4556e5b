"""The kernel's scene storage: the arrays of :class:`Compiled`, packed into
one float64 and one int64 array for cheap calls from Python (:func:`pack`),
and their views rebuilt inside compiled code (:func:`unpack`)."""

from __future__ import annotations

from collections import namedtuple

import numpy as np
from numba import njit

__all__ = ["Compiled", "FIELDS", "KINDS", "pack", "unpack"]

#: at most nm modes, ni inputs; see System._compile for every entry).
FIELDS = (
    # sizes and layout: [nb, M, nf, base_mode (0 fixed, 1 driven, 2 free), qr, vr, qb, vb,
    #                    w0, qm, vm]
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
    # inputs of the base
    "in_ints",          # (ni, 3): kind, direction, role (0 drive, 1 load)
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
    "w_M",              # (6 + nm, 6 + nm)
    "w_Q",              # (6 + nm + nm,) Q̄ then C ȧ
    "w_T",              # (nm, 3, 3) T_k = I8_k + Σ_l a_l I9_kl
    "w_gb",             # (3,) Aᵀ g
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
    "w_M": ("f", 2), "w_Q": ("f", 1), "w_T": ("f", 3), "w_gb": ("f", 1),
}


@njit(cache=True)
def _v1(a, meta, k):
    o = meta[k, 0]
    return a[o:o + meta[k, 1]]


@njit(cache=True)
def _v2(a, meta, k):
    o = meta[k, 0]
    return a[o:o + meta[k, 1] * meta[k, 2]].reshape((meta[k, 1], meta[k, 2]))


@njit(cache=True)
def _v3(a, meta, k):
    o = meta[k, 0]
    s = (meta[k, 1], meta[k, 2], meta[k, 3])
    return a[o:o + s[0] * s[1] * s[2]].reshape(s)


@njit(cache=True)
def _v4(a, meta, k):
    o = meta[k, 0]
    s = (meta[k, 1], meta[k, 2], meta[k, 3], meta[k, 4])
    return a[o:o + s[0] * s[1] * s[2] * s[3]].reshape(s)


@njit(cache=True)
def _v5(a, meta, k):
    o = meta[k, 0]
    s = (meta[k, 1], meta[k, 2], meta[k, 3], meta[k, 4], meta[k, 5])
    return a[o:o + s[0] * s[1] * s[2] * s[3] * s[4]].reshape(s)


@njit(cache=True)
def unpack(F, I, meta):
    """The :class:`Compiled` views of the packed storage (see :func:`pack`)."""
    return Compiled(
        _v1(I, meta, 0),
        _v1(F, meta, 1),
        _v1(F, meta, 2),
        _v3(F, meta, 3),
        _v3(F, meta, 4),
        _v1(I, meta, 5),
        _v1(F, meta, 6),
        _v1(F, meta, 7),
        _v1(I, meta, 8),
        _v1(I, meta, 9),
        _v2(F, meta, 10),
        _v3(F, meta, 11),
        _v2(F, meta, 12),
        _v1(I, meta, 13),
        _v3(F, meta, 14),
        _v1(I, meta, 15),
        _v1(I, meta, 16),
        _v2(F, meta, 17),
        _v2(F, meta, 18),
        _v2(F, meta, 19),
        _v3(F, meta, 20),
        _v3(F, meta, 21),
        _v4(F, meta, 22),
        _v2(I, meta, 23),
        _v1(F, meta, 24),
        _v2(F, meta, 25),
        _v3(F, meta, 26),
        _v3(F, meta, 27),
        _v4(F, meta, 28),
        _v3(F, meta, 29),
        _v3(F, meta, 30),
        _v3(F, meta, 31),
        _v3(F, meta, 32),
        _v4(F, meta, 33),
        _v5(F, meta, 34),
        _v2(I, meta, 35),
        _v2(F, meta, 36),
        _v3(F, meta, 37),
        _v3(F, meta, 38),
        _v4(F, meta, 39),
        _v3(F, meta, 40),
        _v2(F, meta, 41),
        _v2(F, meta, 42),
        _v2(F, meta, 43),
        _v2(F, meta, 44),
        _v2(F, meta, 45),
        _v2(F, meta, 46),
        _v2(F, meta, 47),
        _v2(F, meta, 48),
        _v2(F, meta, 49),
        _v2(F, meta, 50),
        _v2(F, meta, 51),
        _v2(F, meta, 52),
        _v2(F, meta, 53),
        _v1(F, meta, 54),
        _v3(F, meta, 55),
        _v1(F, meta, 56))


def pack(fields: dict):
    """Pack a scene's arrays into one float64 and one int64 array.

    Calling compiled code with two arrays costs a microsecond; with the
    ~60 arrays of :class:`Compiled` it costs tens. The kernel's entry point
    from Python, :func:`evaluate_packed`, rebuilds the views inside
    compiled code.

    Parameters
    ----------
    fields : dict
        Every name of :data:`FIELDS` → array (any shape of the declared
        number of dimensions, :data:`KINDS`).

    Returns
    -------
    packed : tuple (F, I, meta)
        F (·,) float64, I (·,) int64 storage; meta (len(FIELDS), 6) int64:
        offset, then the shape padded with 1.
    views : Compiled
        NumPy views of every field into F and I (writes go to the storage).
    """
    meta = np.zeros((len(FIELDS), 6), dtype=np.int64)
    offsets = {"f": 0, "i": 0}
    arrays = []
    for k, name in enumerate(FIELDS):
        kind, ndim = KINDS[name]
        a = np.asarray(fields[name], dtype=np.float64 if kind == "f" else np.int64)
        if a.ndim != ndim:
            raise ValueError(f"kernel field {name}: {a.ndim} dimensions, expected {ndim}")
        meta[k, 0] = offsets[kind]
        meta[k, 1:1 + ndim] = a.shape
        meta[k, 1 + ndim:] = 1
        offsets[kind] += a.size
        arrays.append(a)
    F = np.zeros(max(offsets["f"], 1))
    I = np.zeros(max(offsets["i"], 1), dtype=np.int64)
    views = {}
    for k, name in enumerate(FIELDS):
        kind, ndim = KINDS[name]
        store = F if kind == "f" else I
        o = int(meta[k, 0])
        shape = tuple(int(v) for v in meta[k, 1:1 + ndim])
        v = store[o:o + int(np.prod(shape))].reshape(shape)
        v[...] = arrays[k]
        views[name] = v
    return (F, I, meta), Compiled(**views)



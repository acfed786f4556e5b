"""The mount laws in compiled code: linear, polynomial and curve data, one
force per (mount, direction)."""

from __future__ import annotations

import numpy as np
from numba import njit

from .inputs import piecewise_value

__all__ = ["law_force"]


@njit(cache=True, no_cpython_wrapper=True)
def _horner(c, x):
    acc = 0.0
    for j in range(c.shape[0] - 1, -1, -1):
        acc = acc * x + c[j]
    return acc


@njit(cache=True, no_cpython_wrapper=True, inline="always")
def law_force(kind, row, lin_kc, poly_k, poly_c, crv_b, crv_o, crv_c, x, v):
    """Force [N] of a law (``kind``, its ``row`` in that kind's table) at
    Δx [m], Δẋ [m/s]."""
    if kind == 0:
        return lin_kc[row, 0] * x + lin_kc[row, 1] * v
    if kind == 1:
        return _horner(poly_k[row], x) + _horner(poly_c[row], v)
    inf = np.inf
    return (piecewise_value(crv_b[row, 0], crv_o[row, 0], crv_c[row, 0], x, inf)
            + piecewise_value(crv_b[row, 1], crv_o[row, 1], crv_c[row, 1], v, inf))


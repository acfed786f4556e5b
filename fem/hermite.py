"""Cubic Hermite functions: the 1-D factors of the Bogner–Fox–Schmit basis.

Pure NumPy, so that mode shapes can be evaluated anywhere on the plate from
the modes file alone, without scikit-fem.
"""

from __future__ import annotations

import numpy as np


def hermite_1d(s: np.ndarray, at_end: np.ndarray, slope: bool):
    """Cubic Hermite shape function on [0, 1] and its first two derivatives.

    Parameters
    ----------
    s : ndarray
        Local coordinate in [0, 1], any shape.
    at_end : ndarray of bool
        Broadcastable to ``s``: True for the function attached to s = 1,
        False for the one attached to s = 0.
    slope : bool
        The slope function (unit derivative at its node) rather than the
        value function (unit value at its node).

    Returns
    -------
    f, df, ddf : ndarray
        Values and derivatives with respect to ``s``.
    """
    s2 = s * s
    s3 = s2 * s
    if not slope:
        f0, d0, dd0 = 1 - 3 * s2 + 2 * s3, -6 * s + 6 * s2, -6 + 12 * s
        f1, d1, dd1 = 3 * s2 - 2 * s3, 6 * s - 6 * s2, 6 - 12 * s
    else:
        f0, d0, dd0 = s - 2 * s2 + s3, 1 - 4 * s + 3 * s2, -4 + 6 * s
        f1, d1, dd1 = -s2 + s3, -2 * s + 3 * s2, -2 + 6 * s
    return (np.where(at_end, f1, f0), np.where(at_end, d1, d0), np.where(at_end, dd1, dd0))

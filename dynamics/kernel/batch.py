"""The right-hand side at many states in one compiled call: the history of
a run (every stored sample) and the forward-difference Jacobians."""

from __future__ import annotations

from numba import njit

__all__ = ["evaluate_batch"]


@njit(cache=True)
def evaluate_batch(kernel, seg_end, t, Y, dY, capture, C):
    """dY[i] = f(t[i], Y[i]) for every row i, and after each evaluation
    C[i] = F[capture]: the values the kernel left in its work arrays at
    that state (mount deflections, forces, accelerations, …).

    Parameters
    ----------
    kernel : tuple (function, F, I)
        The compiled right-hand side and the scene's storage
        (:attr:`flexbed.dynamics.system.System.kernel`).
    seg_end : float [s]
        As for the right-hand side (inf: right-continuous inputs).
    t : (k,) float64 [s]
    Y, dY : (k, ny) float64, C-contiguous
        States; their derivatives (written).
    capture : (c,) int64
        Indices into F.
    C : (k, c) float64
        Written.
    """
    fn, F, I = kernel
    for i in range(t.size):
        fn(t[i], seg_end, Y[i].ctypes, dY[i].ctypes, F.ctypes, I.ctypes)
        for j in range(capture.size):
            C[i, j] = F[capture[j]]

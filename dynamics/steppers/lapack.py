"""LAPACK's LU factorisation and solves (real and complex) for compiled code.

LAPACK
------
radau factors with LAPACK ``dgetrf``/``zgetrf`` and solves with
``dgetrs``/``zgetrs`` (no inverse): their C entry points in
``scipy.linalg.cython_lapack`` are found by numba's
:func:`numba.extending.get_cython_function_address` and wrapped as
``ctypes.CFUNCTYPE`` objects with all-pointer arguments. These ctypes
objects travel in the workspace tuple, i.e. as *arguments*: numba calls
ctypes function pointers in nopython mode, but one referenced as a global
has its address frozen into the machine code and cannot be cached (“uses
dynamic globals”), while an argument is read at run time and caches.
Matrices are stored so that their C order is the Fortran order LAPACK
expects: the Jacobian is kept transposed, ``JT[j, i] = ∂f_i/∂z_j`` (a
difference column is then a contiguous row), and
``LU[j, i] = M δ_ij − JT[j, i]`` is M I − J in Fortran order; the solves
use trans = 'N'. Scalars go as 1-element int32 arrays (LAPACK's int is
32-bit here).

"""

from __future__ import annotations

import ctypes

from numba.extending import get_cython_function_address

__all__ = ["LAPACK"]


def lapack_function(name: str):
    """ctypes function for scipy.linalg.cython_lapack's ``name`` (all arguments pointers)."""
    address = get_cython_function_address("scipy.linalg.cython_lapack", name)
    n_args = {"dgetrf": 6, "zgetrf": 6, "dgetrs": 9, "zgetrs": 9}[name]
    return ctypes.CFUNCTYPE(None, *([ctypes.c_void_p] * n_args))(address)


# (dgetrf, dgetrs, zgetrf, zgetrs): getrf(m, n, a, lda, ipiv, info);
# getrs(trans, n, nrhs, a, lda, ipiv, b, ldb, info)
LAPACK = tuple(lapack_function(n) for n in ("dgetrf", "dgetrs", "zgetrf", "zgetrs"))


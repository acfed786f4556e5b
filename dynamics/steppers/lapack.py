"""LAPACK's LU factorisation and solves (real and complex) for compiled code.

LAPACK
------
radau factors with LAPACK ``dgetrf``/``zgetrf`` and solves with
``dgetrs``/``zgetrs`` (no inverse): their C entry points are taken from
``scipy.linalg.cython_lapack.__pyx_capi__`` (PyCapsule → address with
``ctypes.pythonapi.PyCapsule_GetPointer``) and wrapped as ``ctypes.CFUNCTYPE``
objects with all-pointer arguments. These ctypes objects travel in the
workspace tuple, i.e. as *arguments*: numba calls ctypes function pointers
in nopython mode, but one referenced as a global has its address frozen
into the machine code and cannot be cached (“uses dynamic globals”), while
an argument is read at run time and caches. Matrices are stored so that
their C order is the Fortran order LAPACK expects: the Jacobian is kept
transposed, ``JT[j, i] = ∂f_i/∂z_j`` (a difference column is then a
contiguous row), and ``LU[j, i] = M δ_ij − JT[j, i]`` is M I − J in
Fortran order; the solves use trans = 'N'. Scalars go as 1-element int32
arrays (LAPACK's int is 32-bit here).

"""

from __future__ import annotations

import ctypes

from scipy.linalg import cython_lapack

__all__ = ["LAPACK"]


def lapack_function(name: str):
    """ctypes function for scipy.linalg.cython_lapack's ``name`` (all arguments pointers)."""
    capsule = cython_lapack.__pyx_capi__[name]
    get_name = ctypes.pythonapi.PyCapsule_GetName
    get_name.restype = ctypes.c_char_p
    get_name.argtypes = [ctypes.py_object]
    get_pointer = ctypes.pythonapi.PyCapsule_GetPointer
    get_pointer.restype = ctypes.c_void_p
    get_pointer.argtypes = [ctypes.py_object, ctypes.c_char_p]
    address = get_pointer(capsule, get_name(capsule))
    n_args = {"dgetrf": 6, "zgetrf": 6, "dgetrs": 9, "zgetrs": 9}[name]
    return ctypes.CFUNCTYPE(None, *([ctypes.c_void_p] * n_args))(address)


# (dgetrf, dgetrs, zgetrf, zgetrs): getrf(m, n, a, lda, ipiv, info);
# getrs(trans, n, nrhs, a, lda, ipiv, b, ldb, info)
LAPACK = tuple(lapack_function(n) for n in ("dgetrf", "dgetrs", "zgetrf", "zgetrs"))


"""SciPy's DOP853 coefficients, without importing ``scipy.integrate``.

The compiled dop853 stepper (:mod:`flexbed.dynamics.steppers.dop853`) and
the stiffness check (:mod:`flexbed.dynamics.stiffness`) use the Butcher
tableau of SciPy's ``DOP853``, which lives in the file
``scipy/integrate/_ivp/dop853_coefficients.py``. Importing that module by
name runs ``scipy.integrate``'s package ``__init__`` first, which pulls in
scipy.special, scipy.optimize and the rest of scipy.integrate: about 0.3 s
of CPU on every run for a file of constants. So the one file is loaded
here on its own, from its place beside SciPy's files, under a private
module name; it imports NumPy only.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path
from types import ModuleType

__all__ = ["dop853_coefficients"]

_SCIPY_NAME = "scipy.integrate._ivp.dop853_coefficients"
_PRIVATE_NAME = "flexbed.dynamics._scipy_dop853_coefficients"


def dop853_coefficients() -> ModuleType:
    """SciPy's ``dop853_coefficients`` module (A (16, 16), B (12,), C (16,),
    E3, E5 (13,), D (4, 16), N_STAGES = 12, ...), loaded once per process:
    SciPy's own if ``scipy.integrate`` is already imported, otherwise the
    file alone."""
    module = sys.modules.get(_SCIPY_NAME) or sys.modules.get(_PRIVATE_NAME)
    if module is not None:
        return module
    import scipy
    path = Path(scipy.__file__).parent / "integrate" / "_ivp" / "dop853_coefficients.py"
    spec = importlib.util.spec_from_file_location(_PRIVATE_NAME, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    sys.modules[_PRIVATE_NAME] = module
    return module

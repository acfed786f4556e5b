"""The integrators' coefficients (flexbed.dynamics.steppers.dop853_coefficients
and .radau_coefficients) are flexbed's own data, read-only, checked when
imported, and bit for bit the values SciPy's DOP853 and Radau use. SciPy's
copies live in private modules (scipy.integrate._ivp), imported here only;
where they are gone the comparisons are skipped, saying why."""

import dataclasses
import importlib

import numpy as np
import pytest

from flexbed.dynamics.steppers.dop853_coefficients import DOP853, DOP853Tableau
from flexbed.dynamics.steppers.radau_coefficients import RADAU, RadauIIA5


def _scipy_private(name):
    """SciPy's private module ``scipy.integrate._ivp.<name>``, or a skip."""
    try:
        return importlib.import_module(f"scipy.integrate._ivp.{name}")
    except ImportError as exc:
        pytest.skip(f"SciPy's private module scipy.integrate._ivp.{name} is not importable "
                    f"in this SciPy ({exc}): nothing to compare with")


def _same_bits(ours, theirs):
    ours, theirs = np.asarray(ours), np.asarray(theirs)
    return (ours.shape == theirs.shape and ours.dtype == theirs.dtype
            and ours.tobytes() == theirs.tobytes())


@pytest.mark.parametrize("name", ["A", "B", "C", "E3", "E5", "D"])
def test_dop853_equals_scipys_bit_for_bit(name):
    scipy_dop = _scipy_private("dop853_coefficients")
    assert _same_bits(getattr(DOP853, name), getattr(scipy_dop, name)), name


@pytest.mark.parametrize("name", ["C", "E", "P", "T", "TI", "TI_REAL", "TI_COMPLEX",
                                  "MU_REAL", "MU_COMPLEX"])
def test_radau_equals_scipys_bit_for_bit(name):
    scipy_radau = _scipy_private("radau")
    assert _same_bits(getattr(RADAU, name), getattr(scipy_radau, name)), name


def test_coefficients_are_read_only_and_frozen():
    for table in (DOP853, RADAU):
        for field in dataclasses.fields(table):
            value = getattr(table, field.name)
            if isinstance(value, np.ndarray):
                assert not value.flags.writeable, field.name
                with pytest.raises(ValueError):
                    value[(0,) * value.ndim] = 1.0
        with pytest.raises(dataclasses.FrozenInstanceError):
            table.C = np.zeros(3)
    assert not DOP853.B.flags.writeable


def test_a_broken_tableau_is_refused_naming_the_entry():
    fields = {f.name: getattr(DOP853, f.name) for f in dataclasses.fields(DOP853)}
    bad_c = np.array(DOP853.C)
    bad_c[5] += 1e-6
    with pytest.raises(ValueError, match=r"C\[5\]"):
        DOP853Tableau(**{**fields, "C": bad_c})
    bad_a = np.array(DOP853.A)
    bad_a[12, 5] += 1e-6               # a weight of B: the order conditions fail (and C[12])
    with pytest.raises(ValueError, match="DOP853"):
        DOP853Tableau(**{**fields, "A": bad_a})
    with pytest.raises(ValueError, match="shape"):
        DOP853Tableau(**{**fields, "D": DOP853.D[:3]})
    fields = {f.name: getattr(RADAU, f.name) for f in dataclasses.fields(RADAU)}
    with pytest.raises(ValueError, match="MU_REAL"):
        RadauIIA5(**{**fields, "MU_REAL": RADAU.MU_REAL * (1 + 1e-9)})
    bad_p = np.array(RADAU.P)
    bad_p[0, 0] += 1e-9
    with pytest.raises(ValueError, match="P"):
        RadauIIA5(**{**fields, "P": bad_p})


def test_the_steppers_use_these_coefficients():
    from flexbed.dynamics.steppers import dop853, radau
    assert dop853._DA is DOP853.A and dop853._DD is DOP853.D
    assert radau._RT is RADAU.T and radau._MU_COMPLEX == RADAU.MU_COMPLEX
    assert [radau._TIC0, radau._TIC1, radau._TIC2] == [complex(RADAU.TI[1, k], RADAU.TI[2, k])
                                                      for k in range(3)]

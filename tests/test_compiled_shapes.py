"""A scene input's shape is compiled once for equal contents
(:func:`flexbed.dynamics.base_inputs.compiled_shape`): a study's variants
share their inputs, and a sampled curve's spline is the costly part of
building a System. Equal contents give the very object; any difference
(a sample, the sign of a zero, the type) gives its own."""

import numpy as np

from flexbed.dynamics.base_inputs import compiled_shape
from flexbed.dynamics.time_functions import Curve, Sinusoid


def test_equal_contents_share_one_compiled_function():
    t = np.linspace(0.0, 1.0, 1001)
    a = Curve(t, np.sin(20.0 * t))
    b = Curve(t.copy(), np.sin(20.0 * t))          # other arrays, the same numbers
    fa, fb = compiled_shape(a), compiled_shape(b)
    assert fa is fb
    # the shared function is the curve's own: the same values as compiling it afresh
    fresh = a.compile()
    x = np.linspace(-0.1, 1.2, 777)
    assert np.array_equal(fa.values(x), fresh.values(x))
    assert np.array_equal(fa.seconds(x), fresh.seconds(x))


def test_any_difference_compiles_its_own():
    t = np.linspace(0.0, 1.0, 101)
    v = np.cos(3.0 * t)
    base = compiled_shape(Curve(t, v))
    w = v.copy()
    w[50] = np.nextafter(w[50], 2.0)                # one sample, one unit in the last place
    assert compiled_shape(Curve(t, w)) is not base
    s0 = compiled_shape(Sinusoid(1.0, 5.0, phase=0.0))
    assert compiled_shape(Sinusoid(1.0, 5.0, phase=-0.0)) is not s0
    assert compiled_shape(Sinusoid(1.0, 5.0, phase=0.0)) is s0
    assert compiled_shape(Sinusoid(1.0, 6.0)) is not s0

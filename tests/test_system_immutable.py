"""A compiled System does not change: nothing is set on it between calls,
and the end of the segment being integrated is an argument of every
evaluation (``seg_end``), not a state of the system."""

from pathlib import Path

import numpy as np
import pytest

from flexbed.dynamics.system import System
from flexbed.files.scene import builtin_scene_text, parse_scene


@pytest.fixture(scope="module")
def system():
    """The reference scene (a free base) with its load 1e4 sin(2π 0.25 t) N
    on 0–1 s, not sampled: it ends at its peak, a jump of 1e4 N at t = 1 s."""
    text = builtin_scene_text().replace("amplitude = 1.0e6", "amplitude = 1.0e4")
    text = text.replace("frequency = 5.0", "frequency = 0.25").replace("sample = 1.0e-3", "")
    return System(parse_scene(text, Path("jump.toml")).scene)


def test_a_system_cannot_be_changed(system):
    with pytest.raises(AttributeError, match="immutable"):
        system.nb = 1
    with pytest.raises(AttributeError, match="immutable"):
        del system.nb
    assert system.nb == 4                          # base, bed and two pieces of equipment
    assert not hasattr(system, "set_segment")
    for a in (system.mass, system.J, system.S, system.U, system.d0, system.data.S,
              system.data.lin_kc, system.inputs.support):
        with pytest.raises(ValueError):
            a[...] = 0.0


def test_the_segment_end_is_an_argument(system):
    y = system.initial_state()
    z = system.layout.v_base.start + 2             # the base's vertical acceleration
    right = system.rhs(1.0, y)
    left = system.rhs(1.0, y, seg_end=1.0)
    np.testing.assert_array_equal(system.rhs(1.0, y), right)        # nothing remembered
    assert np.flatnonzero(left != right).tolist() == [z]
    assert (left - right)[z] * system.m_base == pytest.approx(1e4, rel=1e-9)
    dY, _ = system.rhs_batch(np.array([1.0, 1.0]), np.stack([y, y]), seg_end=1.0)
    np.testing.assert_array_equal(dY, [left, left])
    np.testing.assert_array_equal(system.observe(1.0, y, seg_end=1.0).rdd[0], left[z - 2:z + 1])
    np.testing.assert_array_equal(system.inputs.load_at(1.0, seg_end=1.0)
                                  - system.inputs.load_at(1.0), [0.0, 0.0, 1e4])


def test_evaluations_are_counted(system):
    y = system.initial_state()
    n0 = system.nfev
    system.rhs(0.0, y)
    system.rhs_batch(np.zeros(3), np.stack([y, y, y]))
    system.observe(0.0, y)
    assert system.nfev - n0 == 4

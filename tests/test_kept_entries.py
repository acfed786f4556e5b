"""What is kept from call to call must give what a fresh computation gives:
the TOML writer's kept tables (:data:`flexbed.files.toml_text._WRITTEN`,
keyed by :func:`~flexbed.files.scene_text.table_key`), the kept entries'
size, and a study run's kept checked points
(:data:`flexbed.study.outputs._CHECKED_POINTS`)."""

from __future__ import annotations

import math
import threading

import pytest

import flexbed
from flexbed.errors import InputError


@pytest.mark.parametrize("value", [lambda: 1.0, threading.Lock()],
                         ids=["function", "lock"])
def test_vary_names_a_value_toml_cannot_hold(value):
    """A value TOML cannot hold (a function, a lock) given to vary: the
    writer says so ("cannot write function … as TOML"), not the key of the
    kept text (pickle's "Can't pickle <function …>", "cannot pickle
    '_thread.lock' object")."""
    base = flexbed.load_scene()
    with pytest.raises((TypeError, InputError), match=r"as TOML"):
        flexbed.vary(base, {"mount.M5.k": value})


def test_a_kept_point_keeps_its_signed_zero(monkeypatch):
    """A point at x = -0.0 asked after one at x = 0.0 is its own (the kept
    points' keys hold each coordinate's type and repr; ``-0.0 == 0.0``)."""
    from flexbed.dynamics.bounded_cache import BoundedCache
    from flexbed.study import outputs
    from flexbed.study.outputs import PointRun

    monkeypatch.setattr(outputs, "_CHECKED_POINTS", BoundedCache(64))
    PointRun._point(None, "equipment A", [0.0, 0.0, 0.15], "p")
    pt = PointRun._point(None, "equipment A", [-0.0, 0.0, 0.15], "p")
    assert math.copysign(1.0, pt.position[0]) == -1.0, pt.position


def test_a_kept_point_cannot_be_changed_for_the_next_run(monkeypatch):
    """A kept Point is shared by every later run in the process (every
    point of a study's batches): its position must be read-only, as the
    scene's arrays are, or a metric writing into it would move the point
    of every run after."""
    from flexbed.dynamics.bounded_cache import BoundedCache
    from flexbed.study import outputs
    from flexbed.study.outputs import PointRun

    monkeypatch.setattr(outputs, "_CHECKED_POINTS", BoundedCache(64))
    pt = PointRun._point(None, "equipment A", [0.0, 0.0, 0.15], "p")
    assert not pt.position.flags.writeable


def test_a_long_table_is_read_again_rather_than_kept():
    """A table past KEY_BYTES (a long inline curve) has no key: the reader
    and writer check and write it every time, so what they keep stays
    small whatever a study varies; the variant is the same."""
    from flexbed.files.scene_text import KEY_BYTES, table_key
    long = {"shape": "curve", "time": [i * 1e-3 for i in range(5000)],
            "value": [0.0] * 5000}
    assert len(table_key({"k": [1.0] * 10})) < KEY_BYTES
    assert table_key(long) is None

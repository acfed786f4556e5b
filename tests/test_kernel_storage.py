"""The kernel's packed storage: pack() lays out every field, and the
compiled right-hand side reads each field with the view its table says."""

import inspect
import re

import numpy as np

from flexbed.dynamics.kernel import FIELDS, HEADER, KINDS, pack
from flexbed.dynamics.kernel import rhs as rhs_module


def test_the_right_hand_side_reads_every_field_in_table_order():
    src = inspect.getsource(rhs_module.evaluate)
    found = re.findall(r"^    (\w+) = _v(\d)\((F|I)_ptr, meta\[(\d+)\], np\.(float64|int64)\)$",
                       src, flags=re.M)
    assert len(found) == len(FIELDS)
    for name, ndim, store, k, dtype in found:
        kind, nd = KINDS[name]
        assert FIELDS[int(k)] == name
        assert int(ndim) == nd
        assert store == ("F" if kind == "f" else "I")
        assert dtype == ("float64" if kind == "f" else "int64")


def test_pack_round_trip():
    rng = np.random.default_rng(1)
    fields = {}
    for name in FIELDS:
        kind, ndim = KINDS[name]
        shape = tuple(int(s) for s in rng.integers(0, 4, size=ndim))
        a = rng.normal(size=shape) if kind == "f" else rng.integers(-5, 5, size=shape)
        fields[name] = a
    (F, I), views = pack(fields, ny=17)
    n = len(FIELDS)
    assert tuple(I[:HEADER]) == (17, F.size, I.size, n)
    meta = I[HEADER:HEADER + 6 * n].reshape(n, 6)
    for k, name in enumerate(FIELDS):
        kind, ndim = KINDS[name]
        v = getattr(views, name)
        np.testing.assert_array_equal(v, fields[name])
        store = F if kind == "f" else I
        o, shape = meta[k, 0], tuple(meta[k, 1:1 + ndim])
        assert shape == fields[name].shape and np.all(meta[k, 1 + ndim:] == 1)
        np.testing.assert_array_equal(store[o:o + v.size].reshape(shape), fields[name])
        assert np.shares_memory(v, store) or v.size == 0

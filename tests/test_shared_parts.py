"""The Systems of a study's variants share the parts that come out the same
(:mod:`flexbed.dynamics.shared_parts`): each must equal, bit for bit, the
System built from nothing kept, whether its parts were shared (a changed
stiffness, a changed bed thickness: mass and inertia) or not (a changed
topology: other law kinds, a load fewer)."""

import dataclasses

import numpy as np
import pytest

from flexbed import load_scene, vary
from flexbed.dynamics import shared_parts, system as system_module
from flexbed.dynamics.bounded_cache import BoundedCache
from flexbed.dynamics.kernel import storage
from flexbed.dynamics.laws import PolynomialLaw
from flexbed.dynamics.system import System

ARRAYS = ("mass", "g", "m_r", "J", "J_eig", "J_vec", "end_body", "body_i", "body_j", "S",
          "U", "d0", "initial_r", "initial_p")


@pytest.fixture(scope="module")
def base():
    return load_scene()


def fresh(scene, monkeypatch) -> System:
    """The System of ``scene`` built with every cache of shared parts empty."""
    with monkeypatch.context() as m:
        m.setattr(shared_parts, "_INPUTS", BoundedCache(16))
        m.setattr(shared_parts, "_TABLES", BoundedCache(32))
        m.setattr(storage, "_LAYOUTS", BoundedCache(16))
        m.setattr(system_module, "_FRAMES", BoundedCache(16))
        m.setattr(system_module, "_STATE_LAYOUTS", BoundedCache(16))
        return System(scene)


def same(a: System, b: System) -> None:
    """a and b equal in every array, bit for bit, and in their arrays' flags."""
    for F, G in zip(a.kernel[1:], b.kernel[1:]):
        assert F.dtype == G.dtype and F.tobytes() == G.tobytes()
    for name, u, v in zip(a.data._fields, a.data, b.data):
        assert (u.shape, u.flags.writeable, u.tobytes()) == (v.shape, v.flags.writeable,
                                                             v.tobytes()), name
        assert u.flags.writeable == name.startswith("w_"), name
    for name in ARRAYS:
        u, v = getattr(a, name), getattr(b, name)
        assert (u.dtype, u.shape, u.tobytes()) == (v.dtype, v.shape, v.tobytes()), name
    assert a.layout == b.layout and a.ny == b.ny
    for name in ("lin", "k", "c", "poly", "pk", "pc", "curve", "stop_gap", "stop_kc",
                 "stopped"):
        assert getattr(a.laws, name).tobytes() == getattr(b.laws, name).tobytes(), name
    ia, ib = a.inputs, b.inputs
    assert ia.r0.tobytes() == ib.r0.tobytes() and ia.support.tobytes() == ib.support.tobytes()
    assert ia.roles == ib.roles and ia.breakpoints == ib.breakpoints
    y = a.initial_state()
    y[: a.layout.nq] += 1e-3 * np.sin(np.arange(a.layout.nq))     # mounts deflected
    assert a.rhs(0.37, y).tobytes() == b.rhs(0.37, y).tobytes()


@pytest.mark.parametrize("changes", [{"mount.M5.k": [2.0e5, 1.5e5, 7.5e4]},
                                     {"bed.thickness": 0.11},
                                     {"mount.M9.k": [6.0e4, 6.0e4, 6.0e4],
                                      "bed.thickness": 0.09}],
                         ids=["stiffness", "thickness", "both"])
def test_a_variant_equals_its_system_built_afresh(base, changes, monkeypatch):
    template = System(base.scene)
    variant = vary(base, changes)
    shared = System(variant.scene)
    same(shared, fresh(variant.scene, monkeypatch))
    # it did share: the compiled inputs are the template's, the values its own
    assert shared.inputs.compiled is template.inputs.compiled
    assert shared.kernel[1] is not template.kernel[1]
    if "bed.thickness" in changes:
        assert shared.mass[1] != template.mass[1]
        assert shared.inputs.support[2] != template.inputs.support[2]   # −(total mass) g
        assert not np.array_equal(shared.J, template.J)
    else:
        assert shared.data.lin_kc.tobytes() != template.data.lin_kc.tobytes()
    same(template, fresh(base.scene, monkeypatch))     # the template is unchanged


def test_a_changed_topology_shares_nothing_it_should_not(base, monkeypatch):
    template = System(base.scene)
    scene = base.scene
    m5 = next(i for i, m in enumerate(scene.mounts) if m.name == "M5")
    poly = tuple(PolynomialLaw(stiffness=(0.0, law.k, 0.0, 3.0e9), damping=(0.0, law.c))
                 for law in scene.mounts[m5].laws)
    mounts = list(scene.mounts)
    mounts[m5] = dataclasses.replace(mounts[m5], laws=poly)
    changed = dataclasses.replace(scene, mounts=tuple(mounts),
                                  base=dataclasses.replace(scene.base, loads=()))
    shared = System(changed)
    same(shared, fresh(changed, monkeypatch))
    assert shared.inputs.compiled == () and template.inputs.compiled != ()
    assert shared.data.in_ints.shape[0] == 0 and template.data.in_ints.shape[0] == 1
    assert list(shared.data.law_kind[3 * m5:3 * m5 + 3]) == [1, 1, 1]
    assert shared.data.lin_kc.shape[0] == template.data.lin_kc.shape[0] - 3
    assert shared.data.poly_k[:, 3].tolist() == [3.0e9] * 3      # a cubic hardening
    assert not shared.laws.all_linear and template.laws.all_linear
    same(template, fresh(base.scene, monkeypatch))


def test_the_cache_drops_the_least_recently_used():
    cache, made = BoundedCache(3), []

    def get(key):
        return cache.get(key, lambda: made.append(key) or key.upper())
    for key in ("a", "b", "c"):
        get(key)
    assert get("a") == "A"                  # used: "b" is now the oldest
    get("d")
    assert len(cache) == 3 and made == ["a", "b", "c", "d"]
    get("a"), get("c")
    assert made == ["a", "b", "c", "d"]     # kept
    get("b")
    assert made[-1] == "b" and len(cache) == 3

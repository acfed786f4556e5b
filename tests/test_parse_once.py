"""A scene's TOML parsed once per use, and the thread pools found once:
what a study's point no longer repeats (issue 30, part 5)."""

from __future__ import annotations

import pickle
import sys
import tomllib
import types

import pytest

from flexbed import threads
from flexbed.errors import InputError
from flexbed.files.scene import load_scene, parse_scene, scene_data
from flexbed.files.variants import vary


@pytest.mark.parametrize("changes", [
    {"mount.M5.k": [6.1e4, 7.3e4, 1.9e5], "bed.thickness": 0.0913},
    {"solver.t_end": 0.5, "body.equipment A.mass": 612.5},
    {"mount.M9.k": [1e5, 1e5, 1e5], "scene.gravity": [0.0, 0.0, -9.80665]},
])
def test_a_variant_is_the_scene_its_text_makes(changes):
    """vary() checks the data its text was written from, not the text parsed
    again: the scene must be the one its own text gives, field by field."""
    v = vary(load_scene(), changes)
    again = parse_scene(v.text, v.source)
    assert pickle.dumps(v) == pickle.dumps(again)             # every field, arrays too
    assert v.digest == again.digest and v.statics_digest == again.statics_digest


@pytest.mark.parametrize("changes", [
    {"mount.M5.k": [6.1e4, 7.3e4, 1.9e5], "bed.thickness": 0.0913},
    {"body.equipment A.mass": 612.5, "base.force[0].amplitude": 2.5e4},
    {"mount.M9.axes_deg": [0.0, 10.0, 0.0], "solver.t_end": 0.5},
])
def test_a_variant_from_kept_entries_is_the_one_read_afresh(changes, monkeypatch):
    """The entries a variant leaves unchanged come from the scene read before
    (the reader's and the TOML writer's kept results): the variant must be
    the one read with nothing kept, field by field and byte by byte, and
    share exactly the unchanged entries with the base."""
    from flexbed.dynamics.bounded_cache import BoundedCache
    from flexbed.files import scene as scene_module
    from flexbed.files import toml_text
    base = load_scene()
    kept = vary(base, changes)
    for module, name in ((scene_module, "_CHECKED"), (toml_text, "_WRITTEN")):
        monkeypatch.setattr(module, name, BoundedCache(512))
    afresh = vary(load_scene(), changes)
    assert kept.text == afresh.text
    assert pickle.dumps(kept) == pickle.dumps(afresh)
    assert (kept.digest, kept.statics_digest) == (afresh.digest, afresh.statics_digest)
    changed = {p.split(".")[1] for p in changes if p.startswith("mount.")}
    for m, b in zip(kept.scene.mounts, base.scene.mounts):
        assert (m is b) == (m.name not in changed), m.name
    assert (kept.scene.base is base.scene.base) == (not any(p.startswith("base.")
                                                            for p in changes))


def test_table_keys_part_what_the_checks_part():
    import datetime
    from flexbed.files.scene_text import table_key
    values = [1, 1.0, True, -0.0, 0.0, "1", [1.0], {"k": 1.0}, {"k": 1},
              {"t": datetime.date(2026, 11, 27)}]
    keys = [table_key(v) for v in values]
    assert len(set(keys)) == len(values)
    assert table_key({"k": [1.0, 2.0], "n": "M5"}) == table_key(tomllib.loads(
        'k = [1.0, 2.0]\nn = "M5"\n'))


def test_a_refused_entry_is_refused_again_after_a_good_one():
    base = load_scene()
    vary(base, {"mount.M5.k": [6.1e4, 7.3e4, 1.9e5]})
    for _ in range(2):
        with pytest.raises(InputError, match=r"lee1999\.toml: mount 'M5': k\[0\] = -1\.0 must "
                                             r"be > 0"):
            vary(base, {"mount.M5.k": [-1.0, 7.3e4, 1.9e5]})


def test_scene_data_is_the_parse_and_a_fresh_copy():
    text = load_scene().text
    a = scene_data(text)
    assert a == tomllib.loads(text)
    a["body"][1]["mass"] = -1.0
    a.pop("bed", None)
    assert scene_data(text) == tomllib.loads(text)        # the kept parse is untouched


def test_scene_data_keeps_the_recent_texts_and_raises_as_tomllib():
    texts = [f'[scene]\nname = "s{i}"\n' for i in range(8)]
    for t in texts:
        assert scene_data(t) == {"scene": {"name": t.split('"')[1]}}
    with pytest.raises(tomllib.TOMLDecodeError):
        scene_data("[scene\n")


def test_limited_holds_and_restores_the_pools(monkeypatch):
    np = pytest.importorskip("numpy")  # noqa: F841  (a BLAS loaded)
    from threadpoolctl import threadpool_info, threadpool_limits
    monkeypatch.setenv("FLEXBED_THREADS", "1")
    with threadpool_limits(limits=2):                    # pools of 2: the limit shows
        before = [p["num_threads"] for p in threadpool_info()]
        if max(before, default=1) < 2:
            pytest.skip("no thread pool here can hold 2 threads")
        with threads.limited():
            assert {p["num_threads"] for p in threadpool_info()} == {1}
            with threads.limited():                      # nested: held, not restored
                assert {p["num_threads"] for p in threadpool_info()} == {1}
            assert {p["num_threads"] for p in threadpool_info()} == {1}
        assert [p["num_threads"] for p in threadpool_info()] == before


def test_limited_holds_the_pools_until_the_last_caller_leaves(monkeypatch):
    """Two threads inside limited(): the pools are process-wide, so the one
    that leaves first must not restore them under the other. (The last to
    leave restores them; whether OpenBLAS takes a setting made from a thread
    other than the main one is its own affair, so that is not checked here.)"""
    import threading
    pytest.importorskip("numpy")
    from threadpoolctl import threadpool_info, threadpool_limits
    monkeypatch.setenv("FLEXBED_THREADS", "1")
    inside, leave = threading.Event(), threading.Event()

    def other():
        with threads.limited():
            inside.set()
            leave.wait(10)

    with threadpool_limits(limits=2):
        before = [p["num_threads"] for p in threadpool_info()]
        if max(before, default=1) < 2:
            pytest.skip("no thread pool here can hold 2 threads")
        worker = threading.Thread(target=other)
        with threads.limited():
            worker.start()
            assert inside.wait(10)
        held = {p["num_threads"] for p in threadpool_info()}   # the other thread is inside
        leave.set()
        worker.join(10)
        assert held == {1}


def test_the_pools_are_looked_for_again_after_an_import(monkeypatch):
    with threads.limited():
        pass
    found = threads._controller()
    assert threads._controller() is found                # no import since: kept
    monkeypatch.setitem(sys.modules, "flexbed_test_new_module", types.ModuleType("m"))
    assert threads._controller() is not found            # a module more: found again

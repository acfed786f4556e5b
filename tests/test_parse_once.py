"""A scene's TOML parsed once per use, and the thread pools found once:
what a study's point no longer repeats (issue 30, part 5)."""

from __future__ import annotations

import pickle
import sys
import tomllib
import types

import pytest

from flexbed import threads
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

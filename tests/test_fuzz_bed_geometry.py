"""A fuzzer over beds as built (issue 28): random outlines, cut-outs,
thickness zones, fixed masses and element sizes, hostile values among
them (non-finite, 1e308, subnormal, zero, negative, repeated and crossing
points), each written into a small scene (a Mindlin bed, no mounts) and
run through ``flexbed modes`` in-process. Only the error model is
asserted: exit 0 with no line on stderr but warnings, and a modes file
with finite data; or exit 2 with exactly one line naming the scene and
the bed, and nothing written. Derandomised and small (meshes of at most a
few hundred nodes), so it is part of the fast suite.
"""

from __future__ import annotations

import contextlib
import io
import math

import h5py
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from flexbed.cli import main
from flexbed.files.toml_text import dumps

HOSTILE = st.sampled_from([math.nan, math.inf, -math.inf, 1e308, -1e308, 1e200, 5e-324, 0.0,
                           -0.0, 1e7, -1e-300])
#: coordinates on a 0.1 m lattice, so that points coincide and edges cross often
COORD = st.one_of(st.integers(-12, 12).map(lambda i: i / 10), HOSTILE)
NICE = st.integers(-10, 10).map(lambda i: i / 10)
POINT = st.tuples(NICE, NICE)
INNER = st.integers(-6, 6).map(lambda i: i / 10)
SIZE = st.one_of(*[st.sampled_from([0.1, 0.2, 0.3, 0.5, 0.5, 3.0])] * 4, HOSTILE)


def _polygon(coord):
    return st.lists(st.tuples(coord, coord).map(list), min_size=0, max_size=6)


def _region(coord):
    return st.one_of(
        st.fixed_dictionaries({"shape": st.just("rectangle"),
                               "centre": st.tuples(coord, coord).map(list),
                               "size": st.tuples(SIZE, SIZE).map(list)}),
        st.fixed_dictionaries({"shape": st.just("circle"),
                               "centre": st.tuples(coord, coord).map(list),
                               "radius": SIZE}),
        st.fixed_dictionaries({"shape": st.just("polygon"), "points": _polygon(coord)}),
    )


def _mostly(nice, hostile):
    """Nice values nine times in ten."""
    return st.one_of(*([nice] * 9), hostile)


OUTLINE = st.one_of(st.none(), _mostly(
    st.sampled_from([[[-1, -1], [1, -1], [1, 1], [-1, 1]],
                     [[-1, -1], [1, -1], [0.2, 1.2]],
                     [[-1, -1], [1, -1], [1, 0], [0, 0], [0, 1], [-1, 1]]]),
    _polygon(COORD)))
BED = st.fixed_dictionaries({
    "outline": OUTLINE,
    "cutout": st.lists(_region(_mostly(INNER, COORD)), max_size=2),
    "zone": st.lists(_region(_mostly(INNER, COORD)), max_size=1),
    "fixed_mass": st.lists(st.fixed_dictionaries({
        "position": st.tuples(_mostly(INNER, COORD), _mostly(INNER, COORD),
                              st.sampled_from([0.0, 0.1, 1e308])).map(list),
        "mass": st.sampled_from([5.0, 5.0, 5.0, 0.0, math.nan, 1e308])}), max_size=2),
    "element_size": st.one_of(*[st.sampled_from([None, 0.25, 0.4, 1e-4])] * 3, HOSTILE),
})


def _scene(bed: dict) -> dict:
    table = {"model": "flexible", "theory": "mindlin", "length_x": 2.0, "length_y": 2.0,
             "thickness": 0.02, "nx": 6, "ny": 6, "modes": 2}
    if bed["outline"] is not None:
        table["outline"] = bed["outline"]
    if bed["element_size"] is not None:
        table["element_size"] = bed["element_size"]
    if bed["cutout"]:
        table["cutout"] = bed["cutout"]
    if bed["zone"]:
        table["zone"] = [dict(z, thickness=0.04) for z in bed["zone"]]
    if bed["fixed_mass"]:
        table["fixed_mass"] = [dict(m, name=f"m{i}") for i, m in enumerate(bed["fixed_mass"])]
    return {"scene": {"name": "fuzz"},
            "body": [{"name": "base", "mass": 1000.0, "inertia": [100.0, 100.0, 100.0],
                      "position": [0.0, 0.0, 0.0]},
                     {"name": "bed", "position": [0.0, 0.0, 0.5]}],
            "bed": table}


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("fuzz-bed")


def _finite(path) -> None:
    with h5py.File(path, "r") as f:
        def check(name, obj):
            if isinstance(obj, h5py.Dataset) and obj.dtype.kind in "fc":
                assert np.all(np.isfinite(obj[()])), f"{path}: {name} holds non-finite values"
        f.visititems(check)


@settings(max_examples=100, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(BED)
def test_modes_of_a_fuzzed_bed_runs_or_refuses_in_one_line(folder, bed):
    text = dumps(_scene(bed))
    src = folder / "bed.toml"
    src.write_text(text, encoding="utf-8")
    out = folder / "out"
    for f in out.glob("*"):
        f.unlink()
    err, std = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(std):
        code = main(["modes", str(src), "-o", str(out / "m.h5")])
    lines = err.getvalue().splitlines()
    problems = [ln for ln in lines if not ln.startswith("flexbed modes: warning: ")]
    assert code in (0, 2), (code, lines, text)
    assert "Traceback" not in err.getvalue()
    if code == 0:
        assert problems == [], (lines, text)
        _finite(out / "m.h5")
    else:
        assert len(problems) == 1 and len(lines) == 1, (lines, text)
        assert lines[0].startswith("flexbed modes: bed.toml: bed: "), (lines, text)
        assert not out.exists() or not list(out.iterdir()), (lines, text)

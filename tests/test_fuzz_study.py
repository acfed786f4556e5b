"""A fuzzer over study files (issue 28).

Hypothesis mutates a small valid study of the built-in scene — values
replaced by wrong types, huge, tiny, negative, zero or non-finite numbers,
keys removed, unknown keys added — and each mutant is read and planned
(:func:`~flexbed.study.spec.parse_study`, :func:`~flexbed.study.plan.make_plan`:
every path, point and metric checked, nothing run). Only the error model is
asserted: a plan, or :class:`~flexbed.errors.InputError` in one line that
names the study file; nothing else escapes. The point limit is lowered to
8 for the run (so a mutant asking for 10^5 points is refused, not planned
for minutes; the limit's own test is in test_study_faults.py).
Derandomised, so CI runs the same examples every time.
"""

from __future__ import annotations

import copy
import math
import tomllib

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from flexbed.errors import InputError
from flexbed.files.toml_text import dumps
from flexbed.study import spec
from flexbed.study.plan import make_plan

BASE = tomllib.loads("""
[study]
name = "fuzz"
sampling = "grid"

[study.set]
"solver.t_end" = 0.05

[[parameter]]
path = "bed.thickness"
from = 0.08
to = 0.12
num = 2
scale = "linear"

[[parameter]]
path = "mount.M5.k"
values = [[1.0e5, 1.0e5, 1.0e5]]

[[metric]]
kind = "peak_displacement"
point = "A top"

[[metric]]
kind = "peak_mount_force"
mounts = ["M5", "M9"]

[[metric]]
kind = "natural_frequency"
mode = 2

[[metric]]
kind = "transmissibility"
point = "A top"
frequency = 8.0

[[metric]]
kind = "peak_transmissibility"
point = "A top"
band = [1.0, 40.0]
""")


def _leaves(data, prefix=()):
    items = data.items() if isinstance(data, dict) else enumerate(data)
    for key, value in items:
        path = prefix + (key,)
        yield path
        if isinstance(value, (dict, list)):
            yield from _leaves(value, path)


PATHS = list(_leaves(BASE))
NUMBERS = st.sampled_from([0, 0.0, -0.0, -1.0, 1e-300, 5e-324, 1e100, 1e308, -1e308,
                           2 ** 63 - 1, 10 ** 400, math.inf, -math.inf, math.nan, 1, 2, 7,
                           100000, 3.5])
VALUES = st.one_of(
    NUMBERS, st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(2 ** 70), max_value=2 ** 70), st.text(max_size=8), st.booleans(),
    st.lists(NUMBERS, max_size=4), st.just({}), st.just([[1.0, 2.0, 3.0]] * 2),
    st.sampled_from(["grid", "zip", "list", "lhs", "log", "A top", "M5", "bed.thickness",
                     "mount.M5.k", "base.force[0].amplitude", "modal", "frf", "simulate"]))
MUTATION = st.one_of(
    st.tuples(st.just("set"), st.sampled_from(PATHS), VALUES),
    st.tuples(st.just("delete"), st.sampled_from(PATHS), st.none()),
    st.tuples(st.just("add"), st.sampled_from([p for p in PATHS if len(p) <= 2]),
              st.sampled_from(["bogus", "samples", "seed", "num", "values", "band", "batch",
                               "analyses", "relative_to", "axis"])),
)


def _mutated(mutations) -> dict:
    data = tomllib.loads(dumps(BASE))
    for kind, path, value in mutations:
        try:
            parent = data
            for key in path[:-1]:
                parent = parent[key]
            if kind == "set":
                parent[path[-1]] = copy.deepcopy(value)   # no value shared twice
            elif kind == "delete":
                if isinstance(parent, dict) or len(parent) > 1:
                    del parent[path[-1]]
            else:
                target = parent[path[-1]]
                if isinstance(target, dict):
                    target[value] = 3
        except (KeyError, IndexError, TypeError):
            pass            # the path no longer exists after an earlier mutation
    return data


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("fuzz-study")


@settings(max_examples=100, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(st.lists(MUTATION, min_size=1, max_size=3))
def test_a_mutated_study_is_planned_or_refused_in_one_line(folder, monkeypatch, mutations):
    monkeypatch.setattr(spec, "MAX_POINTS", 8)
    try:
        text = dumps(_mutated(mutations))
    except (TypeError, ValueError):
        return                                   # not expressible as TOML
    try:
        plan = make_plan(spec.parse_study(text, folder / "study.toml"))
    except InputError as exc:
        msg = str(exc)
        assert "\n" not in msg and msg.startswith("study.toml: "), msg
        return
    assert 1 <= len(plan.points) <= 8
    assert plan.metric_columns

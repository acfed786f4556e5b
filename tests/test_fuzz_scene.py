"""A fuzzer over the scene loader and ``flexbed static`` (issue 12).

Hypothesis mutates a small rigid scene (a body on four mounts above a
fixed base): values replaced by wrong types, huge, tiny, negative, zero
or non-finite numbers, keys removed, unknown keys added; each mutant is
written as TOML and run through ``flexbed static`` in-process. Only the
error model is asserted: exit 0, 1 or 2; on failure exactly one line on
stderr (besides one-line warnings), on success none; and no non-finite
value in any dataset of a file written. Derandomised, so CI runs the
same examples every time. The command runs as :func:`flexbed.cli.main`
runs it (``run_command`` and one line per error) without the argument
parser, which the catalogue covers.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import math
import sys
import tomllib
from pathlib import Path

import h5py
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from flexbed.commands import static
from flexbed.console import run_command
from flexbed.errors import FlexbedError
from flexbed.files.toml_text import dumps
from scene_text import body_on_four_mounts

pytestmark = pytest.mark.slow             # hundreds of mutants through the command

BASE = tomllib.loads(body_on_four_mounts(extra='\n[solver]\nstatic_tol = 1e-6\n'))


def _leaves(data, prefix=()):
    """Paths to every value of the parsed scene (tables and lists entered)."""
    items = data.items() if isinstance(data, dict) else enumerate(data)
    for key, value in items:
        path = prefix + (key,)
        yield path
        if isinstance(value, (dict, list)):
            yield from _leaves(value, path)


PATHS = list(_leaves(BASE))

NUMBERS = st.sampled_from([0, 0.0, -0.0, -1.0, -1e5, 1e-300, 5e-324, 1e-100, 1e100, 1e101,
                           1e308, -1e308, 2 ** 63 - 1, -(2 ** 63), 10 ** 400, math.inf,
                           -math.inf, math.nan, 1, 3.5, 1e6, 1e-6])
VALUES = st.one_of(
    NUMBERS,
    st.floats(allow_nan=True, allow_infinity=True),
    st.integers(min_value=-(2 ** 70), max_value=2 ** 70),
    st.text(max_size=8),
    st.booleans(),
    st.lists(NUMBERS, max_size=4),
    st.just({}),
    st.just([[1.0, 2.0, 3.0]] * 3),
)


def _set(data, path, value):
    for key in path[:-1]:
        data = data[key]
    data[path[-1]] = value


def _delete(data, path):
    for key in path[:-1]:
        data = data[key]
    if isinstance(data, dict):
        del data[path[-1]]
    elif len(data) > 1:
        del data[path[-1]]


MUTATION = st.one_of(
    st.tuples(st.just("set"), st.sampled_from(PATHS), VALUES),
    st.tuples(st.just("delete"), st.sampled_from(PATHS), st.none()),
    st.tuples(st.just("add"), st.sampled_from([p for p in PATHS if len(p) <= 2]),
              st.sampled_from(["bogus", "mass", "k", "name", "t_end"])),
)


def _mutated(mutations) -> dict:
    data = tomllib.loads(dumps(BASE))
    for kind, path, value in mutations:
        try:
            if kind == "set":
                _set(data, path, value)
            elif kind == "delete":
                _delete(data, path)
            else:
                parent = data
                for key in path:
                    parent = parent[key]
                if isinstance(parent, dict):
                    parent[value] = 1.0
        except (KeyError, IndexError, TypeError):
            pass            # the path no longer exists after an earlier mutation
    return data


def _static(src: Path, out: Path) -> int:
    """``flexbed static SRC -o OUT`` as :func:`flexbed.cli.main` runs it,
    without building the argument parser and the thread-pool limits each
    time (they are the same for every example)."""
    args = argparse.Namespace(command="static", scene=str(src), output=str(out), tol=None,
                              modes_file=None, allow_unstable=False)
    try:
        return run_command(static, args)
    except FlexbedError as exc:
        print(f"flexbed static: {exc}", file=sys.stderr)
        return exc.exit_code


def _finite(path: Path) -> None:
    with h5py.File(path, "r") as f:
        def check(name, obj):
            if isinstance(obj, h5py.Dataset) and obj.dtype.kind in "fc":
                assert np.all(np.isfinite(obj[()])), f"{path}: {name} holds non-finite values"
        f.visititems(check)


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    return tmp_path_factory.mktemp("fuzz")


@settings(max_examples=1000, deadline=None, derandomize=True, database=None,
          suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])
@given(st.lists(MUTATION, min_size=1, max_size=3))
def test_static_on_a_mutated_scene_exits_cleanly(folder, mutations):
    data = _mutated(mutations)
    try:
        text = dumps(data)
    except TypeError:               # a value TOML cannot hold: not a scene file at all
        return
    src = folder / "fuzz.toml"
    src.write_text(text, encoding="utf-8")
    out = folder / "fuzz-eq.h5"
    out.unlink(missing_ok=True)
    err, std = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(std):
        code = _static(src, out)
    lines = err.getvalue().splitlines()
    problems = [ln for ln in lines if not ln.startswith("flexbed static: warning: ")]
    assert code in (0, 1, 2), (code, text)
    assert len(problems) == (0 if code == 0 else 1), (code, lines, text)
    assert all(ln.startswith("flexbed static: ") for ln in lines), lines
    if code == 0:
        _finite(out)
    else:
        assert not out.exists()
    assert not list(folder.glob(".*.tmp"))

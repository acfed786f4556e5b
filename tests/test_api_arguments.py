"""The API refuses wrong arguments at the boundary: one InputError line
naming the function, the argument and the value — never a TypeError from
deep inside, never a wrong type accepted silently (issue 28)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import flexbed
from flexbed.errors import InputError


@pytest.fixture(scope="module")
def rigid():
    sc = flexbed.load_scene()
    return dataclasses.replace(sc, bed=dataclasses.replace(sc.bed, model="rigid"))


@pytest.fixture(scope="module")
def short_run(rigid):
    return flexbed.simulate(rigid, t_end=0.02, integrator="dop853")


def refused(call, function: str, *words: str) -> str:
    """Run ``call``; it must raise InputError whose one line starts with
    ``flexbed.<function>:`` and holds every word."""
    with pytest.raises(InputError) as info:
        call()
    text = str(info.value)
    assert "\n" not in text
    assert text.startswith(f"flexbed.{function}:"), text
    for w in words:
        assert w in text, (w, text)
    return text


# wrong calls: (function name in the message, the call, words it must name)
WRONG = [
    ("simulate", lambda sc: flexbed.simulate("ref.toml"), ("scene", "ref.toml", "load_scene")),
    ("simulate", lambda sc: flexbed.simulate(sc, progress=5), ("progress", "5")),
    ("simulate", lambda sc: flexbed.simulate(sc, t_end="1.0"), ("t_end", "'1.0'")),
    ("simulate", lambda sc: flexbed.simulate(sc, t_end=-1.0), ("t_end", "-1.0")),
    ("simulate", lambda sc: flexbed.simulate(sc, t_end=math.nan), ("t_end", "nan")),
    ("simulate", lambda sc: flexbed.simulate(sc, start="middle"), ("start", "'middle'")),
    ("simulate", lambda sc: flexbed.simulate(sc, model=3), ("model", "3")),
    ("simulate", lambda sc: flexbed.simulate(sc, integrator="rk5"), ("integrator", "'rk5'")),
    ("simulate", lambda sc: flexbed.simulate(sc, modes="m.h5"), ("modes", "m.h5")),
    ("simulate", lambda sc: flexbed.simulate(sc, equilibrium=1.0), ("equilibrium", "1.0")),
    ("simulate", lambda sc: flexbed.simulate(sc, linear_tol="small"), ("linear_tol",)),
    ("simulate", lambda sc: flexbed.simulate(sc, rtol=True), ("rtol", "True")),
    ("simulate", lambda sc: flexbed.simulate(sc, speed=2), ("unknown setting", "speed")),
    ("statics", lambda sc: flexbed.statics(sc, tol="tight"), ("tol", "'tight'")),
    ("statics", lambda sc: flexbed.statics(sc, tol=0.0), ("tol", "0.0")),
    ("statics", lambda sc: flexbed.statics(sc, sag="yes"), ("sag", "'yes'")),
    ("statics", lambda sc: flexbed.statics(123), ("scene", "123")),
    ("modes", lambda sc: flexbed.modes(sc, file=3), ("file", "3")),
    ("modes", lambda sc: flexbed.modes(sc, force=1), ("force", "1")),
    ("modal", lambda sc: flexbed.modal(None), ("scene", "None")),
    ("modal", lambda sc: flexbed.modal(sc, equilibrium=[1, 2]), ("equilibrium",)),
    ("frf", lambda sc: flexbed.frf(sc, band="1,40"), ("band", "'1,40'")),
    ("frf", lambda sc: flexbed.frf(sc, band=(40, 1)), ("band", "f_min < f_max")),
    ("frf", lambda sc: flexbed.frf(sc, band=(0, 10)), ("band[0]", "0")),
    ("frf", lambda sc: flexbed.frf(sc, n=1e9), ("n", "1000000000.0")),
    ("frf", lambda sc: flexbed.frf(sc, n=10 ** 9), ("n", "100,000")),
    ("frf", lambda sc: flexbed.frf(sc, n=1), ("n", "1")),
    ("frf", lambda sc: flexbed.frf(sc, input=3), ("input", "3")),
    ("frf", lambda sc: flexbed.frf(sc, points=["c=bed:0,0,0"]), ("points[0]", "'c=bed:0,0,0'")),
    ("frf", lambda sc: flexbed.frf(sc, points=[("c", "bed", "0,0,0")]), ("position", "'0,0,0'")),
    ("frf", lambda sc: flexbed.frf(sc, points=[("c", "nobody", [0, 0, 0])]),
     ("points[0] body", "'nobody'", "bed")),
    ("frf", lambda sc: flexbed.frf(sc, input="force z", force_at=("nobody", [0, 0, 0])),
     ("force_at body", "'nobody'")),
    ("frf", lambda sc: flexbed.frf(sc, input="force z", force_at="bed:0,0,0"), ("force_at",)),
    ("frf", lambda sc: flexbed.frf(sc, frequencies="10"), ("frequencies", "'10'")),
    ("frf", lambda sc: flexbed.frf(sc, frequencies=[10, -1]), ("frequencies[1]", "-1")),
    ("compare", lambda sc: flexbed.compare(sc, t_end="1"), ("t_end", "'1'")),
    ("compare", lambda sc: flexbed.compare("scene.toml"), ("scene",)),
    ("open_results", lambda sc: flexbed.open_results(12345), ("path", "12345")),
    ("srs", lambda sc: flexbed.srs(12345), ("results", "12345")),
    ("sweep", lambda sc: flexbed.sweep(12345), ("study", "12345")),
    ("sweep", lambda sc: flexbed.sweep("s.toml", workers=0), ("workers", "0")),
    ("sweep", lambda sc: flexbed.sweep("s.toml", batch=True), ("batch", "True")),
    ("sweep", lambda sc: flexbed.sweep("s.toml", progress="no"), ("progress", "'no'")),
    # session 35: the argument's type, and its meaning, at every exported function
    ("load_scene", lambda sc: flexbed.load_scene(123), ("path = 123", "load_scene")),
    ("load_scene", lambda sc: flexbed.load_scene(b"s.toml"), ("path = b's.toml'",)),
    ("load_scene", lambda sc: flexbed.load_scene(["s.toml"]), ("path",)),
    ("vary", lambda sc: flexbed.vary(None, {}), ("scene = None",)),
    ("vary", lambda sc: flexbed.vary(sc, "bed.thickness=0.1"), ("changes", "mapping")),
    ("vary", lambda sc: flexbed.vary(sc, None), ("changes = None",)),
    ("vary", lambda sc: flexbed.vary(sc, {1: 2}), ("changes", "not 1")),
    ("vary", lambda sc: flexbed.vary(sc, {"bed.thickness": 0.1}, name=5), ("name = 5",)),
    ("frf", lambda sc: flexbed.frf(sc, input="force z"), ("force_at = None", "'force z'")),
    ("frf", lambda sc: flexbed.frf(sc, input="base z", force_at=("bed", [0, 0, 0])),
     ("force_at", "None with input = 'base z'")),
    ("frf", lambda sc: flexbed.frf(sc, input="sideways"), ("input = 'sideways'",)),
    ("transmitted", lambda sc: flexbed.transmitted(5), ("results = 5",)),
    ("optimize", lambda sc: flexbed.optimize("o.toml", workers=10 ** 6), ("workers", "1,024")),
    ("sweep", lambda sc: flexbed.sweep("s.toml", batch=10 ** 6), ("batch", "10,000")),
    ("synthesise", lambda sc: flexbed.synthesise("sp.toml", seed=-1), ("seed = -1",)),
    ("random_vibration", lambda sc: flexbed.random_vibration(sc, psd=3), ("psd = 3",)),
]


@pytest.mark.parametrize("function, call, words", WRONG,
                         ids=[f"{w[0]}-{i}" for i, w in enumerate(WRONG)])
def test_wrong_call_is_one_line(rigid, function, call, words):
    refused(lambda: call(rigid), function, *words)


@pytest.mark.parametrize("kwargs, words", [
    ({"q": "10"}, ("q", "'10'")),
    ({"fmin": 0.0}, ("fmin", "0.0")),
    ({"per_octave": 10 ** 9}, ("per_octave", "1000")),
    ({"per_octave": 2.5}, ("per_octave", "2.5")),
    ({"point": "c=bed:0,0,0"}, ("point", "'c=bed:0,0,0'", "(name, body")),
    ({"point": ("c", "nobody", [0, 0, 0])}, ("point body", "'nobody'")),
    ({"fmin": 5e-324}, ("fmin = 5e-324", "out of range")),
    ({"fmin": 1e-9}, ("fmin = 1e-09", "at least 1e-06 Hz")),
    ({"q": 0.3}, ("q = 0.3", "above 0.5")),
    ({"fmin": 100.0, "fmax": 10.0}, ("fmax = 10.0", "at or above fmin = 100 Hz")),
    ({"point": ("c", "bed", [0, 0, 0], "equipment A")},
     ("point relative_to", "'equipment A'", "absolute")),
])
def test_srs_arguments(short_run, kwargs, words):
    refused(lambda: flexbed.srs(short_run, **kwargs), "srs", *words)


@pytest.mark.parametrize("args, kwargs, words", [
    (("bed", "0,0,0"), {}, ("position", "'0,0,0'")),
    (("bed", [0, 0]), {}, ("position",)),
    (("bed", [0, 0, math.inf]), {}, ("position", "inf")),
    ((3, [0, 0, 0]), {}, ("body", "3")),
    (("nobody", [0, 0, 0]), {}, ("body", "'nobody'", "equipment A")),
    (("bed", [0, 0, 0]), {"relative_to": "floor"}, ("relative_to", "'floor'")),
])
def test_results_point_arguments(short_run, args, kwargs, words):
    refused(lambda: short_run.point(*args, **kwargs), "Results.point", *words)


@pytest.mark.parametrize("kwargs, words", [
    ({"start": -1.0}, ("start = -1.0", "in the run")),
    ({"start": "0.01"}, ("start = '0.01'", "number")),
    ({"fmax": 0.5}, ("fmax = 0.5", "at least 1 Hz")),
    ({"fmax": 5e-324}, ("fmax = 5e-324", "out of range")),
])
def test_transmitted_arguments(short_run, kwargs, words):
    refused(lambda: flexbed.transmitted(short_run, **kwargs), "transmitted", *words)


@pytest.mark.parametrize("psd, words", [
    ({"z": [[5.0, 1e308], [100.0, 0.01]]}, ("level 1e+308", "out of range")),
    ({"z": [[5e-324, 0.01], [100.0, 0.01]]}, ("frequency 4.94066e-324 Hz", "1e-06")),
    ({"z": [[5.0, 0.01], [1e308, 0.01]]}, ("frequency 1e+308 Hz", "1e+07")),
])
def test_psd_values_are_checked_as_the_file_is(rigid, psd, words):
    """A PSD given as a dict meets the PSD file's rules: frequencies where
    responses are computed, levels within the scene's range."""
    with pytest.raises(InputError) as info:
        flexbed.random_vibration(rigid, psd=psd)
    for w in words:
        assert w in str(info.value), (w, str(info.value))


def test_points_have_one_form(short_run):
    """The tuple form frf takes is the form srs takes: the same point, the same spectrum."""
    a = flexbed.srs(short_run, point=("c", "bed", [0.1, 0.2, 0.0]), fmin=5, fmax=40)
    b = flexbed.srs(short_run, point=[("c", "bed", (0.1, 0.2, 0.0))], fmin=5, fmax=40)
    assert np.array_equal(a.points[0].maximax, b.points[0].maximax)


def test_numpy_scalars_are_numbers(rigid):
    """A NumPy float or int is a number (a study's values often are)."""
    run = flexbed.simulate(rigid, t_end=np.float64(0.01), integrator="dop853")
    assert run.complete and abs(run["time"][-1] - 0.01) < 1e-12


# the fuzzer: any value of any type in any argument is either accepted or
# refused in one line by InputError; nothing else escapes
VALUES = st.one_of(
    st.none(), st.booleans(), st.integers(min_value=-10 ** 20, max_value=10 ** 20),
    st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=8),
    st.lists(st.floats(allow_nan=True, allow_infinity=True), max_size=4),
    st.tuples(st.text(max_size=4), st.text(max_size=4), st.lists(st.integers(-3, 3),
                                                                 max_size=4)),
    st.just(object()), st.just({"a": 1}))

CHEAP = {   # arguments checked before any work
    "simulate": ("t_end", "dt", "rtol", "atol", "output_dt", "start", "model", "linear_tol",
                 "progress", "integrator", "equilibrium", "modes"),
    "statics": ("tol", "sag", "modes"),
    "frf": ("band", "n", "input", "points", "force_at", "frequencies", "equilibrium"),
    "modal": ("equilibrium", "modes"),
}
POSITIVE = {"t_end", "dt", "rtol", "atol", "output_dt", "linear_tol", "tol"}
CHOICES = {"start": ("equilibrium", "initial"), "model": ("nonlinear", "linear", "auto"),
           "integrator": ("auto", "rk4", "dop853", "radau")}


class Reached(Exception):
    """The call got past its checks to the work."""


def _reached(*args, **kwargs):
    raise Reached


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(function=st.sampled_from(sorted(CHEAP)), data=st.data(), value=VALUES)
def test_fuzz_api_arguments(function, data, value):
    """Any value in any argument: InputError in one line starting with the
    function's name, or the call reaches its work (stubbed out here) with a
    value the docstring calls valid. Nothing else escapes."""
    from unittest import mock

    name = data.draw(st.sampled_from(CHEAP[function]))
    sc = flexbed.load_scene()
    sc = dataclasses.replace(sc, bed=dataclasses.replace(sc.bed, model="rigid"))
    with mock.patch("flexbed.api.bed_modes.compile_scene", _reached), \
            mock.patch("flexbed.api.frequency.amodal.mounted", _reached):
        try:
            getattr(flexbed, function)(sc, **{name: value})
        except InputError as exc:
            assert "\n" not in str(exc) and str(exc).startswith(f"flexbed.{function}:"), exc
            return
        except Reached:
            pass
    if value is None:
        return
    if name in POSITIVE:
        assert isinstance(value, (int, float)) and not isinstance(value, bool)
        assert math.isfinite(value) and value > 0
    if name in CHOICES:
        assert value in CHOICES[name]
    if name == "n":
        assert isinstance(value, int) and 2 <= value <= 100_000
    if name in ("sag",):
        assert isinstance(value, bool)


@settings(max_examples=60, deadline=None)
@given(value=VALUES)
def test_fuzz_load_scene_and_vary(value):
    """load_scene(value) and vary(scene, value): a scene, or InputError in
    one line; nothing else escapes (no TypeError, AttributeError)."""
    scene = flexbed.load_scene()
    for call in (lambda: flexbed.load_scene(value),
                 lambda: flexbed.vary(scene, value),
                 lambda: flexbed.vary(value, {})):
        try:
            call()
        except InputError as exc:
            assert "\n" not in str(exc), exc


@pytest.mark.parametrize("name", ["\n", "scene\n.toml", "a\tb.toml", "x\x1b[31m.toml", "d\x7f"])
def test_a_file_name_with_a_control_character_is_refused_in_one_line(name, tmp_path):
    """A line break, a tab or an escape in a file name would break the
    one-line message that names the file (the hypothesis fuzzer found
    ``load_scene("\\n")``): refused as input, shown escaped, for a file
    read, a file written and an output folder; nothing is created."""
    from flexbed.files.destination import check_destination, make_folder
    for call, doing in ((lambda: flexbed.load_scene(name), "cannot read the scene file"),
                        (lambda: check_destination(tmp_path / name), "cannot write here"),
                        (lambda: make_folder(tmp_path / name), "cannot create the folder")):
        with pytest.raises(InputError, match="holding a control character") as err:
            call()
        text = str(err.value)
        assert "\n" not in text and "\t" not in text and "\x1b" not in text, text
        assert doing in text and repr(name)[1:-1] in text
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("name", ["\x00", "scene\x00.toml"])
def test_a_file_name_with_a_nul_character_is_one_line(name, tmp_path):
    """The operating system refuses such a name with a ValueError: flexbed
    says so as input, for a file read and for one written."""
    with pytest.raises(InputError, match="a file name cannot hold a NUL character") as err:
        flexbed.load_scene(name)
    assert "\n" not in str(err.value)
    from flexbed.files.destination import check_destination
    with pytest.raises(InputError, match="cannot write here: a file name cannot hold a NUL"):
        check_destination(tmp_path / name)

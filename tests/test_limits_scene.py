"""The scene file's limits (issue 23, parts 2–3): stroke, load, fragility
and clearance keys read into :class:`flexbed.files.limits.Limits`, and each
bad value refused in one line naming the file, the entry and the value."""

from __future__ import annotations

from pathlib import Path

import pytest

from flexbed.errors import InputError
from flexbed.files.limits import STANDARD_GRAVITY, check_static_strokes
from flexbed.files.scene import parse_scene

from scene_text import body_on_four_mounts

import numpy as np

LIMITS = """
stroke_compression = [0.004, 0.005, 0.006]
stroke_extension = [0.007, 0.008, 0.009]
rated_load = 200.0
max_force = 600.0
"""

CLEARANCES = """
[[clearance]]
name = "side"
body = "mass"
point = [0.25, 0.0, 0.0]
other = "base"
plane = {point = [0.3, 0.0, 0.5], normal = [-2.0, 0.0, 0.0]}
minimum = 0.01

[[clearance]]
name = "corner"
body = "mass"
point = [0.0, 0.0, 0.1]
other = "base"
other_point = [0.0, 0.0, 0.9]
minimum = 0.0

[[clearance]]
name = "shelf"
body = "mass"
point = [0.0, 0.0, 0.1]
other = "base"
box = {min = [-0.1, -0.1, 0.8], max = [0.1, 0.1, 1.0]}
minimum = 0.02
"""


def scene(limits: str = LIMITS, fragility: str = '{peak = 40, units = "g"}',
          clearances: str = CLEARANCES) -> str:
    text = body_on_four_mounts(extra=clearances)
    text = text.replace('k = [1.0e5, 1.0e5, 1.0e5]', 'k = [1.0e5, 1.0e5, 1.0e5]\n' + limits, 1)
    if fragility:
        text = text.replace("inertia = [2.0, 3.0, 4.0]",
                            f"inertia = [2.0, 3.0, 4.0]\nfragility = {fragility}")
    return text


def read(text: str):
    return parse_scene(text, Path("skid.toml"))


def test_the_limits_are_read_in_si():
    sf = read(scene())
    m1 = sf.limits.mount("M1")
    assert m1.compression == (0.004, 0.005, 0.006) and m1.extension == (0.007, 0.008, 0.009)
    assert (m1.rated_load, m1.max_force) == (200.0, 600.0)
    assert sf.limits.mount("M2").compression is None         # no limits: all None
    frag = sf.limits.body("mass")
    assert frag.peak == 40 * STANDARD_GRAVITY and frag.given == 40 and frag.point is None
    side, corner, shelf = sf.limits.clearances
    assert side.kind == "plane" and side.geometry[1] == (-1.0, 0.0, 0.0)   # normalised
    assert corner.kind == "point" and corner.minimum == 0.0
    assert shelf.kind == "box" and shelf.geometry == ((-0.1, -0.1, 0.8), (0.1, 0.1, 1.0))


def test_limits_leave_the_equilibrium_hash_alone():
    """An equilibrium file stays valid when only limits change."""
    plain = read(scene(limits="", fragility="", clearances=""))
    limited = read(scene())
    assert plain.statics_digest == limited.statics_digest
    assert plain.digest != limited.digest
    assert plain.limits.empty and not limited.limits.empty


BAD = [
    ("units", scene(fragility='{peak = 40, units = "G"}'),
     "skid.toml: body 'mass': fragility.units = 'G' must be one of 'm/s2', 'g'"),
    ("fragility peak", scene(fragility='{peak = -3}'),
     "skid.toml: body 'mass': fragility.peak = -3.0 must be > 0"),
    ("fragility not a table", scene(fragility='40'),
     "skid.toml: body 'mass': fragility = 40 must be a table"),
    ("stroke zero", scene(limits="stroke_compression = [0.01, 0.0, 0.01]"),
     "skid.toml: mount 'M1': stroke_compression[1] = 0.0 must be > 0"),
    ("stroke count", scene(limits="stroke_extension = [0.01, 0.01]"),
     "skid.toml: mount 'M1': stroke_extension = [0.01, 0.01] must have 3 numbers, has 2"),
    ("rated load", scene(limits='rated_load = "200 N"'),
     "skid.toml: mount 'M1': rated_load = '200 N' must be a number"),
    ("self clearance", scene(clearances=CLEARANCES.replace('other = "base"\nplane',
                                                            'other = "mass"\nplane')),
     "skid.toml: clearance 'side': other = 'mass' is the body itself"),
    ("unknown body", scene(clearances=CLEARANCES.replace('body = "mass"', 'body = "pump"', 1)),
     "skid.toml: clearance 'side': body = 'pump' is not a body (bodies: base, mass)"),
    ("no shape", scene(clearances=CLEARANCES.replace(
        'plane = {point = [0.3, 0.0, 0.5], normal = [-2.0, 0.0, 0.0]}\n', '')),
     "skid.toml: clearance 'side': give exactly one of other_point, plane, box"),
    ("zero normal", scene(clearances=CLEARANCES.replace("[-2.0, 0.0, 0.0]", "[0, 0, 0]")),
     "skid.toml: clearance 'side': plane.normal = [0.0, 0.0, 0.0] must be a non-zero vector"),
    ("empty box", scene(clearances=CLEARANCES.replace("max = [0.1, 0.1, 1.0]",
                                                      "max = [0.1, -0.1, 1.0]")),
     "skid.toml: clearance 'shelf': box.min[1] = -0.1 must be < box.max[1] = -0.1"),
    ("negative minimum", scene(clearances=CLEARANCES.replace("minimum = 0.01", "minimum = -1")),
     "skid.toml: clearance 'side': minimum = -1.0 must be >= 0"),
    ("twice", scene(clearances=CLEARANCES.replace('"corner"', '"side"')),
     "skid.toml: clearance 'side': name is used twice"),
    ("unknown key", scene(clearances=CLEARANCES.replace("minimum = 0.0\n", "gap = 0.0\n")),
     "skid.toml: clearance 'corner': unknown key 'gap'"),
    ("base fragility", scene(fragility="").replace(
        "inertia = [100.0, 100.0, 100.0]", "inertia = [100.0, 100.0, 100.0]\n"
        "fragility = {peak = 3}"),
     "skid.toml: body 'base': fragility: the base carries no equipment"),
]


@pytest.mark.parametrize("text, words", [(t, w) for _, t, w in BAD],
                         ids=[n for n, _, _ in BAD])
def test_bad_limits_are_one_line_naming_file_entry_and_value(text, words):
    with pytest.raises(InputError) as exc:
        read(text)
    msg = str(exc.value)
    assert msg.startswith(words) and "\n" not in msg


def test_a_stroke_smaller_than_the_static_deflection_is_refused():
    sf = read(scene())
    names = [m.name for m in sf.scene.mounts]
    dx = np.zeros((4, 3))
    dx[0, 2] = -0.0059                                     # within 6 mm of compression
    check_static_strokes("skid.toml", sf.limits, names, dx)
    dx[0, 2] = -0.0061
    with pytest.raises(InputError, match=r"^skid.toml: mount 'M1': stroke_compression\[2\] = "
                                         r"0.006 m is smaller than the static deflection in "
                                         r"direction 3, 0.0061 m of compression"):
        check_static_strokes("skid.toml", sf.limits, names, dx)
    dx[0, 2] = 0.0
    dx[0, 0] = 0.0071                                      # extension past 7 mm
    with pytest.raises(InputError, match=r"stroke_extension\[0\] = 0.007 m"):
        check_static_strokes("skid.toml", sf.limits, names, dx)

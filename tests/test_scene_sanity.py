"""Physical sanity at load: the triangle inequality of principal moments
of inertia (refused), mount points far from their body (warned)."""

import math
import warnings
from pathlib import Path

import pytest

from flexbed.errors import FlexbedWarning, InputError
from flexbed.files.sanity import FAR_POINT, body_sizes
from flexbed.files.scene import parse_scene
from scene_text import body_on_four_mounts


def _box(m, a, b, c):
    """Principal moments of a uniform a x b x c box of mass m [kg m^2]."""
    return [m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12]


def test_the_size_of_a_body_is_the_half_diagonal_of_its_uniform_box():
    J = _box(50.0, 0.4, 0.6, 1.2)
    sf = parse_scene(body_on_four_mounts(inertia=str(J)), Path("s.toml"))
    size = body_sizes(sf.scene, None, sf.bed)["mass"]
    assert size == pytest.approx(0.5 * math.sqrt(0.4 ** 2 + 0.6 ** 2 + 1.2 ** 2), rel=1e-14)


def test_a_lamina_meets_the_triangle_inequality_with_equality_and_is_accepted():
    m, a, b = 50.0, 0.4, 0.6
    J = [m * b * b / 12, m * a * a / 12, m * (a * a + b * b) / 12]     # J3 = J1 + J2
    parse_scene(body_on_four_mounts(inertia=str(J)), Path("s.toml"))
    J[2] *= 1.0 + 1e-6                                                  # no body has this
    with pytest.raises(InputError, match="triangle inequality"):
        parse_scene(body_on_four_mounts(inertia=str(J)), Path("s.toml"))


def test_a_mount_point_is_warned_about_just_past_ten_sizes():
    J = _box(50.0, 0.4, 0.6, 1.2)
    size = 0.5 * math.sqrt(0.4 ** 2 + 0.6 ** 2 + 1.2 ** 2)
    # M1's point_j is (-0.2, -0.2, z): put it at FAR_POINT sizes, then just past
    for factor, warned in ((0.999, False), (1.001, True)):
        z = -math.sqrt((factor * FAR_POINT * size) ** 2 - 0.08)
        text = body_on_four_mounts(inertia=str(J)).replace("-0.2]", f"{z!r}]", 1)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            parse_scene(text, Path("s.toml"))
        got = [str(w.message) for w in caught if issubclass(w.category, FlexbedWarning)]
        assert len(got) == warned, got
        if warned:
            assert got[0].startswith("s.toml: mount 'M1': point_j = ")

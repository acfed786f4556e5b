"""A flat/T/I stiffener sits on the plate's local face: under a thickness
zone its offset is the zone's t/2 + c, not the nominal plate's (issue 14)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from flexbed.errors import InputError
from flexbed.fem.bed import compute_bed_modes
from flexbed.fem.geometry import BedGeometry, Region, Zone
from flexbed.fem.spec import PlateSpec
from flexbed.files.bed_geometry import read_stiffeners

E, NU, RHO = 2.1e11, 0.3, 7800.0
B, L, T0, TZ = 0.2, 3.0, 0.02, 0.03            # strip, nominal and zone thickness [m]
BAR = {"name": "bar", "start": [0.0, -L / 2], "end": [0.0, L / 2], "section": "flat",
       "height": 0.1, "width": 0.02}


def _table(**extra):
    return {"thickness": T0, "length_x": B, "length_y": L, "stiffener": [dict(BAR, **extra)]}


def test_stiffener_under_a_zone_sits_on_the_zone_face():
    """A zone of 30 mm over the whole 20 mm strip: the bar's offset is
    −(0.015 + 0.05) m, and the bed's modes equal those of a uniform 30 mm
    strip with the same bar (round-off); its first bending mode lies 0.5 …
    1.5 % below Euler–Bernoulli theory for the composite T-section (the
    shear flexibility of plate and web, as for the strip of
    test_stiffeners.py), while the nominal face (the old offset) would be
    2.1 % off that theory's."""
    geometry = BedGeometry(zones=(Zone(Region("rectangle", (0.0, 0.0), size=(B, L)), TZ),),
                           element_size=0.05)
    (st,) = read_stiffeners(_table(), "s.toml: bed", geometry)
    assert st.offset == pytest.approx(-(TZ / 2 + 0.05), rel=1e-15)
    (above,) = read_stiffeners(_table(side="above"), "s.toml: bed", geometry)
    assert above.offset == pytest.approx(TZ / 2 + 0.05, rel=1e-15)
    common = dict(length_x=B, length_y=L, young=E, poisson=NU, density=RHO, theory="mindlin")
    zoned = compute_bed_modes(PlateSpec(thickness=T0, geometry=geometry, stiffeners=(st,),
                                        **common), n_modes=3)
    uniform = compute_bed_modes(PlateSpec(thickness=TZ, nx=4, ny=60, stiffeners=(st,),
                                          **common), n_modes=3)
    assert np.allclose(zoned.modes.frequency, uniform.modes.frequency, rtol=1e-9, atol=0)

    def beam(offset):
        Af, Aw = B * TZ, st.section.area
        zc = Aw * offset / (Af + Aw)
        EI = E * (B * TZ ** 3 / 12 + Af * zc ** 2 + st.section.Iy + Aw * (offset - zc) ** 2)
        return 4.730040745 ** 2 / (2 * math.pi * L * L) * math.sqrt(EI / (RHO * (Af + Aw)))

    f1 = zoned.modes.frequency[0]
    assert 0.005 < 1 - f1 / beam(st.offset) < 0.015
    assert abs(beam(-(T0 / 2 + 0.05)) / f1 - 1) > 0.02


def test_stiffener_off_zones_keeps_the_nominal_face():
    geometry = BedGeometry(zones=(Zone(Region("rectangle", (0.06, 0.0), size=(0.04, 1.0)), TZ),))
    (st,) = read_stiffeners(_table(), "s.toml: bed", geometry)
    assert st.offset == pytest.approx(-(T0 / 2 + 0.05), rel=1e-15)
    general = read_stiffeners({"stiffener": [{"name": "g", "start": [0, -1], "end": [0, 1],
                                              "section": "general", "area": 1e-3, "Iy": 1e-6,
                                              "Iz": 1e-7, "J": 1e-8, "offset": -0.2}]},
                              "s.toml: bed", geometry)
    assert general[0].offset == -0.2


@pytest.mark.parametrize("zone", [Region("rectangle", (0.0, 1.0), size=(0.1, 0.6)),
                                  Region("rectangle", (0.05, 0.0), size=(0.1, 3.0)),
                                  Region("circle", (0.0, -0.5), radius=0.05)])
def test_stiffener_over_a_zone_edge_is_refused(zone):
    """Crossing a zone (rectangle, circle) or running along its edge: no
    single face to sit on."""
    geometry = BedGeometry(zones=(Zone(zone, TZ),), element_size=0.05)
    with pytest.raises(InputError, match=r"^s.toml: bed: stiffener 'bar': from \[0.0, -1.5\] "
                                         r"to \[0.0, 1.5\] m it lies on plate of thickness "
                                         r"0.02, 0.03 m \(it crosses or runs along a zone's "
                                         r"edge\)"):
        read_stiffeners(_table(), "s.toml: bed", geometry)


def test_scene_file_stiffener_under_a_zone(tmp_path):
    """Through the scene reader: the keel under a 0.14 m zone of the 0.1 m
    bed sits 0.07 m + its centroid below the mid-surface; moved across the
    zone's edge it is refused, naming the file and the stiffener."""
    import flexbed
    from flexbed.files.builtin import builtin_scene_path
    text = builtin_scene_path().read_text().replace(
        'model = "rigid"', 'model = "flexible"\ntheory = "mindlin"', 1)
    text = text.replace("nx = 10\nny = 10\n", "nx = 4\nny = 24\n")
    extra = ('[[bed.zone]]\nshape = "rectangle"\ncentre = [0.0, 0.0]\nsize = [0.4, 4.8]\n'
             'thickness = 0.14\n'
             '[[bed.stiffener]]\nname = "keel"\nstart = [0.0, -2.4]\nend = [0.0, 2.4]\n'
             'section = "flat"\nheight = 0.1\nwidth = 0.02\n')
    good = text.replace("rayleigh = [0.0, 0.01]\n", "rayleigh = [0.0, 0.01]\n" + extra, 1)
    (tmp_path / "good.toml").write_text(good)
    st = flexbed.load_scene(tmp_path / "good.toml").bed.plate.stiffeners[0]
    assert st.offset == pytest.approx(-(0.07 + 0.05), rel=1e-15)
    (tmp_path / "bad.toml").write_text(good.replace("size = [0.4, 4.8]", "size = [0.4, 2.0]"))
    with pytest.raises(InputError, match=r"^\S*bad.toml: bed: stiffener 'keel': from "
                                         r"\[0.0, -2.4\] to \[0.0, 2.4\] m it lies on plate of "
                                         r"thickness 0.1, 0.14 m"):
        flexbed.load_scene(tmp_path / "bad.toml")

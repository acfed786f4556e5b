"""The bed body's mass and inertia from the plate: omitted, they are the
solid plate's (the modes file's invariants); given with a flexible bed,
they must agree, and the message says both values without float noise and
that the key can be omitted."""

import re

import numpy as np
import pytest

from flexbed.errors import InputError
from flexbed.files.scene import builtin_scene_path, load_scene
from flexbed.stages.modes import ensure_modes
from flexbed.stages.system import compile_scene

REF = builtin_scene_path().read_text()


def scene_with(tmp_path, text, name="bed.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


def flexible(text):
    return text.replace('model = "rigid"', 'model = "flexible"')


def with_bed_keys(text, keys):
    return text.replace('name = "bed"', 'name = "bed"\n' + keys, 1)


def test_builtin_bed_takes_the_plates_mass_and_inertia():
    """Table 1's bed: 2995.2 kg, [5753.28, 162.24, 5910.53] kg m² (the last
    rounded from 5910.528), from ρabt and the solid plate."""
    bed = load_scene().scene.bodies[1]
    assert bed.name == "bed"
    assert bed.mass == pytest.approx(2995.2, rel=1e-15)
    assert np.allclose(bed.inertia, np.diag([5753.28, 162.24, 5910.528]), rtol=1e-15, atol=0)
    assert re.search(r'name = "bed"\s*(#.*)?\nposition', REF)      # no mass, no inertia


def test_thicker_plate_needs_no_hand_edits(tmp_path):
    """A 12 cm plate, flexible, mass and inertia omitted: the bed body gets
    ρabt = 3594.24 kg and the solid plate's inertia, the same values as the
    modes file's invariants, so the flexible model is accepted."""
    text = flexible(REF).replace("thickness = 0.1", "thickness = 0.12")
    sf = load_scene(scene_with(tmp_path, text))
    bed = sf.scene.bodies[1]
    m = 7800.0 * 0.8 * 4.8 * 0.12
    assert bed.mass == pytest.approx(m, rel=1e-15)
    J = np.diag([m * (4.8 ** 2 + 0.12 ** 2), m * (0.8 ** 2 + 0.12 ** 2), m * (0.8 ** 2 + 4.8 ** 2)])
    assert np.allclose(bed.inertia, J / 12.0, rtol=1e-14, atol=0)
    data, _ = ensure_modes(sf, tmp_path / "bed-modes.h5", log=lambda m: None)
    assert data.invariants.mass == bed.mass
    assert np.array_equal(data.invariants.inertia, bed.inertia)
    system = compile_scene(sf, tmp_path / "bed-modes.h5")
    assert system.mass[1] == bed.mass


def test_given_values_that_agree_are_accepted(tmp_path):
    """Given as published (5910.53 for 5910.528, within 1e-4), as today."""
    text = flexible(with_bed_keys(REF, "mass = 2995.2\ninertia = [5753.28, 162.24, 5910.53]"))
    assert load_scene(scene_with(tmp_path, text)).scene.bodies[1].inertia[2, 2] == 5910.53


@pytest.mark.parametrize("keys,message", [
    ("mass = 2995.5",
     "bed.toml: body 'bed': mass = 2995.5 kg differs from the plate's 2995.2 kg "
     "(density × length_x × length_y × thickness); omit mass to take the plate's"),
    ("mass = 3594.24",
     "bed.toml: body 'bed': mass = 3594.24 kg differs from the plate's 2995.2 kg"),
    ("inertia = [5753.28, 162.24, 5920.0]",
     "bed.toml: body 'bed': inertia = [5753.28, 162.24, 5920.0] kg m^2 differs from the "
     "plate's [5753.28, 162.24, 5910.53] kg m^2 (the solid plate about its centre); omit "
     "inertia to take the plate's"),
    ("inertia = [[5753.28, 0.0, 0.0], [0.0, 162.24, 3.0], [0.0, 3.0, 5910.53]]",
     "bed.toml: body 'bed': inertia = [[5753.28, 0.0, 0.0], [0.0, 162.24, 3.0], "
     "[0.0, 3.0, 5910.53]] kg m^2 differs from the plate's [5753.28, 162.24, 5910.53]"),
])
def test_disagreeing_values_refused_with_both_values_and_the_way_out(tmp_path, keys, message):
    with pytest.raises(InputError) as exc:
        load_scene(scene_with(tmp_path, flexible(with_bed_keys(REF, keys))))
    assert str(exc.value).startswith(message), str(exc.value)


def test_float_noise_never_shown(tmp_path):
    """The plate's mass 0.8·4.8·0.1·7800 is 2995.2000000000003 in floating
    point; the message shows 2995.2 (6 significant digits) and the typed
    value as typed."""
    with pytest.raises(InputError) as exc:
        load_scene(scene_with(tmp_path, flexible(with_bed_keys(REF, "mass = 2995.6001"))))
    assert "mass = 2995.6001 kg differs from the plate's 2995.2 kg" in str(exc.value)
    assert "00000" not in str(exc.value)


def test_rigid_bed_keeps_given_values_and_the_flexible_switch_checks_them(tmp_path):
    """A rigid bed's given mass is used as it is (a rigid bed need not be
    the plate); made flexible later (as `compare` does), the same check and
    message apply."""
    from dataclasses import replace

    from flexbed.stages.flexible_bed import with_flexible_bed
    sf = load_scene(scene_with(tmp_path, with_bed_keys(REF, "mass = 3000.0")))
    assert sf.scene.bodies[1].mass == 3000.0
    data, _ = ensure_modes(sf, tmp_path / "bed-modes.h5", log=lambda m: None)
    flex = replace(sf, bed=replace(sf.bed, model="flexible"))
    with pytest.raises(InputError) as exc:
        with_flexible_bed(flex, data)
    assert str(exc.value).startswith("bed.toml: body 'bed': mass = 3000.0 kg differs from the "
                                     "plate's 2995.2 kg")


def test_without_a_bed_table_mass_and_inertia_stay_required(tmp_path):
    """No [bed] table: body 2 is not taken to be a plate; no silent mass."""
    a = REF.index("\n[bed]\n")
    text = REF[:a] + REF[REF.index("\n[[mount]]", a):]
    assert "bed" in load_scene(scene_with(tmp_path, with_bed_keys(
        text, "mass = 2995.2\ninertia = [5753.28, 162.24, 5910.53]"))).scene.bodies[1].name
    with pytest.raises(InputError, match="bed.toml: body 'bed': 'mass' is required"):
        load_scene(scene_with(tmp_path, text))


def test_bed_body_named_in_the_bed_table(tmp_path):
    """``[bed] body`` names the bed's body: that one takes the plate's values,
    body 2 must give its own."""
    text = REF.replace('name = "bed"', 'name = "raft"').replace('"bed"', '"raft"')
    text = text.replace("[bed]\n", '[bed]\nbody = "raft"\n')
    text = text.replace('name = "equipment A"\nmass = 100.0\n', 'name = "equipment A"\n')
    assert load_scene(scene_with(tmp_path, text.replace('name = "equipment A"\n',
                                                        'name = "equipment A"\nmass = 100.0\n')))
    with pytest.raises(InputError, match="body 'equipment A': 'mass' is required"):
        load_scene(scene_with(tmp_path, text))

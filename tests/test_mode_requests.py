"""What a bed's modes may be asked for, refused before any work: more
elastic modes than its FE model has (``modes``, ``correction_modes``,
``--modes``), counted on the mesh before any assembly; and the modes of a
scene with no ``[bed]`` table, by ``flexbed modes`` and ``flexbed.modes``
alike (one line, exit 2, nothing written)."""

from dataclasses import replace

import pytest

import flexbed
from flexbed.cli import main
from flexbed.errors import InputError
from flexbed.fem.geometry import BedGeometry, Region
from flexbed.fem.layout import elastic_mode_count
from flexbed.fem.spec import PlateSpec
from flexbed.fem.stiffeners import Stiffener, section_of
from flexbed.files.builtin import builtin_scene_text
from scene_text import one_stage

BAR = Stiffener("bar", (0.0, -2.4), (0.0, 2.4), section_of("flat", height=0.1, width=0.02),
                -0.1)


@pytest.mark.parametrize("spec", [
    PlateSpec(nx=4, ny=6),
    PlateSpec(nx=4, ny=6, theory="mindlin"),
    PlateSpec(nx=8, ny=12, theory="mindlin",
              geometry=BedGeometry(cutouts=(Region("rectangle", (0.0, 1.0), size=(0.4, 0.8)),))),
    PlateSpec(nx=10, ny=10, theory="mindlin", stiffeners=(BAR,)),
], ids=["kirchhoff", "mindlin", "cut-out", "hinged-stiffener"])
def test_the_count_is_the_assembled_model_s(spec):
    """Degrees of freedom less rigid-body modes of the assembled model,
    exactly (a hinged stiffener's own section rotations included)."""
    from flexbed.fem.bed import assemble_bed
    model = assemble_bed(spec)
    assert elastic_mode_count(spec) == model.K.shape[0] - getattr(model, "n_rigid", 3)
    if spec.stiffeners:
        assert BAR.model == "hinged" and elastic_mode_count(spec) > elastic_mode_count(
            replace(spec, stiffeners=()))


def _flexible():
    return builtin_scene_text().replace('model = "rigid"', 'model = "flexible"', 1)


@pytest.fixture()
def no_assembly(monkeypatch):
    """Any FE assembly fails the test: the refusals come before it."""
    import flexbed.fem.bed as bed

    def refuse(spec):
        raise AssertionError("the bed was assembled")
    monkeypatch.setattr(bed, "assemble_bed", refuse)


@pytest.mark.parametrize("old, new, words", [
    ("modes = 2", "modes = 1000000000",
     "s.toml: bed: modes = 1000000000: the 10 x 10 plate has only 481 elastic modes"),
    ("modes = 2", "modes = 482", "modes = 482: the 10 x 10 plate has only 481 elastic modes"),
    ("modes = 2", "modes = 2\nstatic_correction = true\ncorrection_modes = 1000000000",
     "s.toml: bed: correction_modes = 1000000000: the 10 x 10 plate has only 481"),
], ids=["modes-1e9", "modes-482", "correction-modes-1e9"])
def test_too_many_modes_are_refused_before_assembly(tmp_path, capsys, no_assembly, old, new,
                                                    words):
    text = _flexible()
    assert old in text
    scene = tmp_path / "s.toml"
    scene.write_text(text.replace(old, new, 1))
    code = main(["modes", str(scene), "-o", str(tmp_path / "m.h5")])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1 and words in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["s.toml"]
    with pytest.raises(InputError, match=words.split(": ", 1)[1]):
        flexbed.load_scene(scene)
    # the API's variant of a good scene, the same rule
    with pytest.raises(InputError, match="has only 481 elastic modes"):
        flexbed.vary(flexbed.load_scene(), {"bed.modes": 1000000000})
    # 481 is every mode the mesh has: allowed
    assert flexbed.vary(flexbed.load_scene(), {"bed.modes": 481}).bed.modes == 481


def test_the_modes_option_is_refused_before_assembly(tmp_path, capsys, no_assembly):
    code = main(["modes", "-o", str(tmp_path / "m.h5"), "--modes", "1000000000"])
    err = capsys.readouterr().err
    assert code == 2 and len(err.strip().splitlines()) == 1, err
    assert "--modes 1000000000: the 10 x 10 plate has only 481 elastic modes" in err
    assert list(tmp_path.iterdir()) == []


def test_an_auto_mesh_is_held_to_the_mesh_limit(tmp_path):
    text = builtin_scene_text().replace("nx = 10\nny = 10", 'theory = "mindlin"\n'
                                        'element_size = "auto"', 1)
    assert 'element_size = "auto"' in text
    scene = tmp_path / "auto.toml"
    scene.write_text(text.replace("modes = 2", "modes = 1000000000", 1))
    with pytest.raises(InputError, match=r"auto.toml: bed: modes = 1000000000: element_size = "
                                         r"\"auto\" meshes the bed with at most 250,000 "):
        flexbed.load_scene(scene)


def test_a_scene_with_no_bed_has_no_modes(tmp_path, capsys):
    """``flexbed modes`` and ``flexbed.modes`` refuse a scene with no
    ``[bed]`` table alike; a rigid bed's plate still has its modes (the
    tour's ``flexbed modes --modes 4``)."""
    scene = tmp_path / "iso.toml"
    scene.write_text(one_stage(0.0))
    code = main(["modes", str(scene), "-o", str(tmp_path / "m.h5")])
    err = capsys.readouterr().err
    words = "iso.toml: no [bed] table: the scene has no bed to compute the modes of"
    assert code == 2 and err.strip().splitlines() == [f"flexbed modes: {words}"], err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["iso.toml"]
    sf = flexbed.load_scene(scene)
    with pytest.raises(InputError) as refused:
        flexbed.modes(sf)
    assert str(refused.value) == words
    with pytest.raises(InputError, match="no \\[bed\\] table"):
        flexbed.modes(sf, file=tmp_path / "m.h5")
    assert not (tmp_path / "m.h5").exists()
    rigid = flexbed.load_scene()
    assert rigid.bed.model == "rigid" and flexbed.modes(rigid).n_modes == 2

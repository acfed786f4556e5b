"""The modes file: exact round trip, self-description, refusal of foreign,
damaged or stale files, and atomic writes."""

import h5py
import numpy as np
import pytest

from flexbed.fem.bed import compute_bed_modes
from flexbed.fem.spec import PlateSpec
from flexbed.files import store
from flexbed.errors import InputError
from flexbed.files.modes import read_modes_file, write_modes_file


@pytest.fixture(scope="module")
def bed():
    return compute_bed_modes(PlateSpec(), n_modes=4)


def test_round_trip_is_exact(tmp_path, bed):
    path = write_modes_file(tmp_path / "m.h5", bed)
    data = read_modes_file(path)
    assert data.plate == bed.spec
    assert data.input_hash == bed.spec.digest()
    assert np.array_equal(data.frequency, bed.modes.frequency)
    assert np.array_equal(data.omega, bed.modes.omega)
    assert np.array_equal(data.translation, bed.translation)
    assert np.array_equal(data.rotation, bed.rotation)
    assert np.array_equal(data.twist, bed.twist)
    assert np.array_equal(data.nodes, bed.nodes)
    assert np.array_equal(data.cells, bed.cells)
    assert data.labels == bed.modes.labels and data.symmetry == bed.modes.symmetry
    for key in ("first_moment", "inertia", "phi_integral", "u_cross_phi", "phi_cross_phi",
                "modal_mass", "inertia_first_order", "inertia_second_order", "modal_stiffness"):
        assert np.array_equal(getattr(data.invariants, key), getattr(bed.invariants, key)), key
    assert data.invariants.mass == bed.invariants.mass
    assert data.next_frequency == pytest.approx(bed.modes.omega_next / (2 * np.pi), rel=1e-15)


def test_plain_h5py_sees_units_on_every_dataset(tmp_path, bed):
    path = write_modes_file(tmp_path / "m.h5", bed)
    seen = []
    with h5py.File(path, "r") as f:
        assert f.attrs["schema"] == "flexbed.modes"
        assert f.attrs["schema_version"] == "1.4"
        assert str(f.attrs["creator"]).startswith("flexbed ")
        assert "T" in str(f.attrs["created"])
        assert f.attrs["input_hash"] == bed.spec.digest()
        assert float(f["plate"].attrs["thickness"]) == 0.1

        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                seen.append(name)
                assert "units" in obj.attrs, name
        f.visititems(visit)
        assert f["invariants/mass"].attrs["source"].startswith("solid")
        assert f["invariants/phi_cross_phi"].attrs["source"].startswith("FE")
    assert "invariants/inertia_second_order" in seen and len(seen) >= 20


def test_truncated_file_is_refused_naming_it(tmp_path, bed):
    path = write_modes_file(tmp_path / "m.h5", bed)
    raw = path.read_bytes()
    bad = tmp_path / "cut.h5"
    bad.write_bytes(raw[: len(raw) // 2])
    with pytest.raises(InputError, match="cut.h5: not a readable HDF5 file"):
        read_modes_file(bad)


def test_corrupted_dataset_is_refused_naming_file_and_dataset(tmp_path, bed):
    path = write_modes_file(tmp_path / "m.h5", bed)
    with h5py.File(path, "a") as f:
        del f["modes/twist"]
    with pytest.raises(InputError, match=r"m.h5: dataset 'modes/twist' is missing"):
        read_modes_file(path)
    path = write_modes_file(tmp_path / "n.h5", bed)
    with h5py.File(path, "a") as f:
        del f["modes/rotation"]
        f["modes/rotation"] = np.zeros((2, 3))
        f["modes/rotation"].attrs["units"] = "1"
    with pytest.raises(InputError, match=r"n.h5: dataset 'modes/rotation' has shape"):
        read_modes_file(path)


def test_dataset_without_units_is_refused(tmp_path, bed):
    path = write_modes_file(tmp_path / "m.h5", bed)
    with h5py.File(path, "a") as f:
        del f["modes/omega"].attrs["units"]
    with pytest.raises(InputError, match="'modes/omega' has no 'units'"):
        read_modes_file(path)


@pytest.mark.parametrize("attr, value, match", [
    ("schema", "flexbed.results", "schema is 'flexbed.results', expected 'flexbed.modes'"),
    ("schema_version", "2.0", "version 2.0 is not supported.*upgrade flexbed"),
    ("schema_version", "0.9", "version 0.9 is not supported.*older flexbed"),
])
def test_other_schema_or_version_is_refused(tmp_path, bed, attr, value, match):
    path = write_modes_file(tmp_path / "m.h5", bed)
    with h5py.File(path, "a") as f:
        f.attrs[attr] = value
    with pytest.raises(InputError, match=match):
        read_modes_file(path)


def test_newer_minor_version_is_read(tmp_path, bed):
    path = write_modes_file(tmp_path / "m.h5", bed)
    with h5py.File(path, "a") as f:
        f.attrs["schema_version"] = "1.7"
    assert read_modes_file(path).n_modes == 4


def test_edited_plate_inputs_break_the_hash(tmp_path, bed):
    path = write_modes_file(tmp_path / "m.h5", bed)
    with h5py.File(path, "a") as f:
        f["plate"].attrs["thickness"] = 0.12
    with pytest.raises(InputError, match="input_hash does not match"):
        read_modes_file(path)


def test_failed_write_leaves_nothing_behind(tmp_path, bed, monkeypatch):
    def broken(*args, **kwargs):
        raise OSError("disk full")
    monkeypatch.setattr(h5py.Group, "create_dataset", broken)
    with pytest.raises(InputError, match="m.h5: cannot write it .disk full.; nothing was written"):
        write_modes_file(tmp_path / "m.h5", bed)
    assert list(tmp_path.iterdir()) == []


def test_write_replaces_an_existing_file_atomically(tmp_path, bed):
    path = tmp_path / "m.h5"
    path.write_bytes(b"old")
    write_modes_file(path, bed)
    assert read_modes_file(path).n_modes == 4
    assert [p.name for p in tmp_path.iterdir()] == ["m.h5"]


def test_store_refuses_missing_file(tmp_path):
    with pytest.raises(InputError, match="no such file"):
        store.read_file(tmp_path / "none.h5", schema="x", major=1)


def test_the_invariants_contract_is_written_once(bed):
    """fem's Invariants and dynamics' FlexibleBody hold exactly the modes
    file's INVARIANTS: the same names, the shapes fem makes, the shapes
    dynamics accepts (and no other)."""
    from dataclasses import fields as dataclass_fields

    from flexbed.dynamics.errors import SceneError
    from flexbed.dynamics.flexible import FlexibleBody
    from flexbed.fem.invariants import Invariants
    from flexbed.files.modes import INVARIANTS

    names = {v.name for v in INVARIANTS}
    assert {f.name for f in dataclass_fields(Invariants)} - {"model_mass"} == names
    assert set(Invariants.SOURCES) == names
    assert names <= {f.name for f in dataclass_fields(FlexibleBody)}
    n = bed.modes.omega.size
    for v in INVARIANTS:
        assert np.shape(getattr(bed.invariants, v.name)) == v.shape_for(n), v.name
    given = {v.name: getattr(bed.invariants, v.name) for v in INVARIANTS}
    rest = dict(modal_damping=np.zeros((n, n)), points=np.zeros((0, 3)),
                point_shapes=np.zeros((0, 3, n)))
    body = FlexibleBody(**given, **rest)            # what fem makes, dynamics takes
    assert body.n_modes == n
    for v in INVARIANTS:
        if v.shape:
            with pytest.raises(SceneError):
                FlexibleBody(**{**given, v.name: np.zeros(v.shape_for(n) + (2,))}, **rest)

"""The bed's motion for ParaView: every dataset of the XDMF's HDF5 companion
is named and has units, and an independent XDMF reader (meshio's) reads the
same motion back."""

import h5py
import meshio
import numpy as np

from flexbed.files.store import read_file
from flexbed.files.xdmf import BED_MOTION_SCHEMA, write_bed_motion


def test_bed_motion_round_trip_with_units_on_every_dataset(tmp_path):
    rng = np.random.default_rng(7)
    nx, ny = 3, 2
    xs, ys = np.meshgrid(np.linspace(-0.4, 0.4, nx + 1), np.linspace(-2.4, 2.4, ny + 1))
    nodes = np.column_stack([xs.ravel(), ys.ravel(), np.full(xs.size, 5.0)])
    cells = np.array([[j * (nx + 1) + i, j * (nx + 1) + i + 1, (j + 1) * (nx + 1) + i + 1,
                       (j + 1) * (nx + 1) + i] for j in range(ny) for i in range(nx)])
    times = np.arange(12) * 0.01
    disp = rng.normal(size=(times.size, nodes.shape[0], 3))
    defl = rng.normal(size=(times.size, nodes.shape[0]))
    xdmf = write_bed_motion(tmp_path / "case-bed.xdmf", nodes, cells, times, disp, defl)
    h5 = tmp_path / "case-bed.h5"
    assert xdmf.is_file() and h5.is_file()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["case-bed.h5", "case-bed.xdmf"]

    names, missing = [], []
    with h5py.File(h5, "r") as f:
        def visit(name, obj):
            if isinstance(obj, h5py.Dataset):
                names.append(name)
                if "units" not in obj.attrs or "description" not in obj.attrs:
                    missing.append(name)
        f.visititems(visit)
        assert f["frames/0011"].attrs["time"] == times[11]
    assert len(names) == 3 + 2 * times.size and not missing, missing
    c = read_file(h5, schema=BED_MOTION_SCHEMA, major=1)      # the project's own reader
    assert c.units["frames/0003/displacement"] == "m" and c.units["time"] == "s"

    with meshio.xdmf.TimeSeriesReader(xdmf) as reader:
        points, blocks = reader.read_points_cells()
        assert np.array_equal(points, nodes)
        assert blocks[0].type == "quad" and np.array_equal(blocks[0].data, cells)
        assert reader.num_steps == times.size
        for k in (0, 5, 11):
            t, point_data, _ = reader.read_data(k)
            assert t == times[k]
            assert np.array_equal(point_data["displacement"], disp[k])
            assert np.array_equal(point_data["deflection"], defl[k])

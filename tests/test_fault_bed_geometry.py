"""The fault catalogue of beds as built (issue 28): every bad outline,
cut-out, zone, fixed mass, element size and mesh file ends in exit 2 and
exactly one line on stderr naming the scene, the entry and the value, with
no traceback and nothing written — checked before any work (a mesh past
the 250,000-DOF limit is refused from its estimate or its file's header,
at once). One case per kind of fault, as the command line runs it
(:func:`flexbed.cli.main` in-process, as ``test_fault_catalogue`` does);
then what a mesh file's reader repairs (orientation, unused nodes) and
what it counts.
"""

from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass
from pathlib import Path

import meshio
import numpy as np
import pytest

from flexbed.cli import main
from flexbed.fem.cells import areas
from flexbed.fem.geometry import BedGeometry, GeometryError, Region, Zone
from flexbed.fem.layout import bed_mass_properties
from flexbed.fem.mesh_file import declared_points, read_mesh_file
from flexbed.fem.spec import PlateSpec

_SCENE = """
[scene]
name = "geo"

[[body]]
name = "base"
mass = 1000.0
inertia = [100.0, 100.0, 100.0]
position = [0.0, 0.0, 0.0]

[[body]]
name = "bed"
position = [0.0, 0.0, 0.5]

[bed]
model = "flexible"
theory = "mindlin"
length_x = 0.8
length_y = 4.8
thickness = 0.1
nx = 2
ny = 6
modes = 2
"""

_MOUNT = """
[[mount]]
name = "M1"
body_i = "base"
body_j = "bed"
point_i = [{x}, {y}, 0.3]
point_j = [{x}, {y}, 0.0]
law = "linear"
k = [1.0e6, 1.0e6, 1.0e6]
"""


def _rect(centre, size, table="cutout"):
    return (f'[[bed.{table}]]\nshape = "rectangle"\ncentre = {list(centre)}\n'
            f'size = {list(size)}\n')


def _grid(nx=2, ny=6, a=0.8, b=4.8):
    """Nodes (N, 2) and counter-clockwise quads of an a × b grid centred on 0."""
    X, Y = np.meshgrid(np.linspace(-a / 2, a / 2, nx + 1), np.linspace(-b / 2, b / 2, ny + 1))
    i, j = np.meshgrid(np.arange(nx), np.arange(ny))
    n0 = (i + j * (nx + 1)).ravel()
    return (np.column_stack([X.ravel(), Y.ravel()]),
            np.column_stack([n0, n0 + 1, n0 + nx + 2, n0 + nx + 1]))


N, C = _grid()


def _write_mesh(path: Path, nodes, cells, **kw) -> None:
    nodes = np.asarray(nodes, dtype=float)
    meshio.write(path, meshio.Mesh(np.column_stack([nodes, np.zeros(len(nodes))]), cells), **kw)


@dataclass(frozen=True)
class Case:
    """One fault: the [bed] keys and tables, files beside the scene (name →
    bytes, or a function of the path that writes it), the command and the
    words the one line must hold."""

    name: str
    bed: str
    words: tuple
    files: dict | None = None
    extra: str = ""
    command: str = "modes"


def _mesh(name, nodes, cells, words, file="bed.vtu", **kw):
    def write(path):
        _write_mesh(path, nodes, cells, **kw)
    return Case(name, f'mesh_file = "{file}"\n', ("mesh_file = '" + file + "'",) + words,
                {file: write})


def _raw(name, content: bytes, words, file="bed.vtu"):
    return Case(name, f'mesh_file = "{file}"\n', ("mesh_file = '" + file + "'",) + words,
                {file: content})


_VTU_10M = (b'<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="0.1">\n'
            b'<UnstructuredGrid>\n<Piece NumberOfPoints="10000000" NumberOfCells="9980001">\n'
            b'<Points>\n<DataArray type="Float64" NumberOfComponents="3" format="ascii">\n'
            b'0 0 0\n')
_MSH_10M = b"$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n10000000\n1 0 0 0\n2 1 0 0\n"
_MSH4_10M = (b"$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 10000000 1 10000000\n"
             b"2 1 0 10000000\n")
_TWO = np.vstack([N, N + [2.0, 0.0]])
_ARROW = N.copy()
_ARROW[4] = [0.35, -0.9]                         # a corner of 180+ degrees in quad 3
_FOLD = np.vstack([N, [[0.2, 2.0]]])             # a cell folded back over its neighbour

CASES = [
    # the outline as a polygon
    Case("outline-self-intersecting", "outline = [[0, 0], [2, 0], [2, 2], [1, -1], [0, 2]]\n",
         ("bed: outline", "cross or touch", "[2, 2]-[1, -1]")),
    Case("outline-two-points", "outline = [[0, 0], [1, 0]]\n",
         ("bed: outline = [[0, 0], [1, 0]]", "at least 3")),
    Case("outline-two-distinct-points", "outline = [[0, 0], [1, 0], [0, 0]]\n",
         ("bed: outline", "points 1 and 3", "same point [0, 0]")),
    Case("outline-repeated-point", "outline = [[0, 0], [1, 0], [1, 0], [1, 1], [0, 1]]\n",
         ("bed: outline", "points 2 and 3", "[1, 0]")),
    Case("outline-zero-area", "outline = [[0, 0], [1, 0], [2, 0]]\n",
         ("bed: outline = [[0, 0], [1, 0], [2, 0]]", "encloses no area")),
    Case("outline-turns-back", "outline = [[0, 0], [2, 0], [1, 0], [1, 1]]\n",
         ("bed: outline", "turns back on itself at point 2 = [2, 0]")),
    Case("outline-nan", "outline = [[0, 0], [nan, 0], [1, 1]]\n",
         ("bed: outline[1][0] = nan", "finite")),
    Case("outline-inf", "outline = [[0, 0], [inf, 0], [1, 1]]\n",
         ("bed: outline[1][0] = inf", "finite")),
    Case("outline-1e308", "outline = [[0, 0], [1e308, 0], [1, 1]]\n",
         ("bed: outline[1][0] = 1e+308", "out of range")),
    Case("outline-1e7", "outline = [[0, 0], [1e7, 0], [1, 1]]\n",
         ("bed: outline", "point 2 = [1e+07, 0]", "beyond 1e+06 m")),
    Case("outline-not-points", 'outline = [[0, 0], "corner", [1, 1]]\n',
         ("bed: outline", "'corner'", "list of [x, y] points")),
    # cut-outs
    Case("cutout-outside", _rect((5.0, 0.0), (0.2, 0.2)),
         ("bed: cutout 1", "rectangle 0.2 x 0.2 m at (5.0, 0.0)", "outside the bed")),
    Case("cutout-across-the-edge", _rect((0.4, 0.0), (0.2, 0.2)),
         ("bed: cutout 1", "at (0.4, 0.0)", "meets the outline's edge")),
    Case("cutout-covers-the-bed", _rect((0.0, 0.0), (2.0, 6.0)),
         ("bed: cutout 1", "rectangle 2 x 6 m", "covers the whole bed")),
    Case("cutout-circle-without-centre", '[[bed.cutout]]\nshape = "circle"\nradius = 0.1\n',
         ("bed: cutout 1", "'centre' is required for a circle")),
    Case("cutout-rectangle-with-a-radius", _rect((0.0, 1.0), (0.2, 0.2)) + "radius = 0.1\n",
         ("bed: cutout 1", "'radius' does not apply to a rectangle", "centre, size")),
    Case("zone-polygon-with-a-centre", '[[bed.zone]]\nshape = "polygon"\n'
         'points = [[0, 0], [0.2, 0], [0.2, 0.2]]\ncentre = [0, 0]\nthickness = 0.12\n',
         ("bed: zone 1", "'centre' does not apply to a polygon")),
    Case("cutouts-overlap", _rect((0.0, 1.0), (0.2, 0.2)) + _rect((0.1, 1.0), (0.2, 0.2)),
         ("bed: cutout 2", "at (0.1, 1.0)", "overlaps cutout 1")),
    Case("cutouts-touch", _rect((-0.1, 1.0), (0.2, 0.2)) + _rect((0.1, 1.0), (0.2, 0.2)),
         ("bed: cutout 2", "at (0.1, 1.0)", "touches or overlaps cutout 1")),
    Case("cutout-circle-in-another", _rect((0.0, 1.0), (0.4, 0.4))
         + '[[bed.cutout]]\nshape = "circle"\ncentre = [0.0, 1.0]\nradius = 0.05\n',
         ("bed: cutout 2", "circle r = 0.05 m", "overlaps cutout 1")),
    Case("cutout-polygon-self-intersecting",
         '[[bed.cutout]]\nshape = "polygon"\n'
         'points = [[0, 0], [0.2, 0], [0.2, 0.2], [0.1, -0.1], [0, 0.2]]\n',
         ("bed: cutout 1", "points", "cross or touch")),
    Case("cutout-radius-1e7", '[[bed.cutout]]\nshape = "circle"\ncentre = [0, 0]\n'
                              'radius = 1e7\n', ("bed: cutout 1", "radius = 10000000.0")),
    Case("cutout-far-smaller-than-the-elements", '[[bed.cutout]]\nshape = "circle"\n'
                                                 'centre = [0.1, 1.0]\nradius = 1e-3\n',
         ("bed: the mesh (element size 0.4 m from nx, ny)", "degrees, below 0.5",
          "too distorted", "smaller element_size")),
    Case("cutout-size-1e308", _rect((0.0, 0.0), (1e308, 0.2)),
         ("bed: cutout 1", "size[0] = 1e+308", "out of range")),
    # thickness zones
    Case("zone-outside", _rect((5.0, 0.0), (0.2, 0.2), "zone") + "thickness = 0.2\n",
         ("bed: zone 1", "rectangle 0.2 x 0.2 m at (5.0, 0.0)", "holds no cell")),
    Case("zone-in-a-cutout", _rect((0.0, 1.0), (0.4, 0.4))
         + _rect((0.0, 1.0), (0.2, 0.2), "zone") + "thickness = 0.2\n",
         ("bed: zone 1", "at (0.0, 1.0)", "holds no cell", "in a cut-out")),
    Case("zone-polygon-repeated-point",
         '[[bed.zone]]\nshape = "polygon"\npoints = [[0, 0], [0.2, 0], [0.2, 0], [0, 0.2]]\n'
         "thickness = 0.2\n", ("bed: zone 1", "points 2 and 3", "same point")),
    Case("zone-thickness-inf", _rect((0.0, 0.0), (0.2, 0.2), "zone") + "thickness = inf\n",
         ("bed: zone 1", "thickness = inf", "finite")),
    # fixed masses and mounts on the shell
    Case("fixed-mass-off-the-bed", '[[bed.fixed_mass]]\nname = "pump"\n'
                                   "position = [3.0, 0.0, 0.1]\nmass = 10.0\n",
         ("bed: fixed_mass 'pump'", "position = [3.0, 0.0, 0.1] m", "off the bed")),
    Case("fixed-mass-in-a-cutout", _rect((0.0, 1.0), (0.2, 0.2))
         + '[[bed.fixed_mass]]\nname = "pump"\nposition = [0.0, 1.0, 0.1]\nmass = 10.0\n',
         ("bed: fixed_mass 'pump'", "position = [0.0, 1.0, 0.1] m", "in a cut-out")),
    Case("fixed-mass-height-1e7", '[[bed.fixed_mass]]\nname = "pump"\n'
                                  "position = [0.0, 0.0, 1e7]\nmass = 10.0\n",
         ("bed: fixed_mass 'pump'", "position", "beyond 1e+06 m")),
    Case("fixed-mass-mass-1e308", '[[bed.fixed_mass]]\nname = "pump"\n'
                                  "position = [0.0, 0.0, 0.1]\nmass = 1e308\n",
         ("bed: fixed_mass 'pump'", "mass = 1e+308", "out of range")),
    Case("mount-in-a-cutout", _rect((0.0, 1.0), (0.2, 0.2)),
         ("geo.toml: mount 'M1'", "point_j = [0.0, 1.0, 0.0] m", "off the bed"),
         extra=_MOUNT.format(x=0.0, y=1.0)),
    Case("mount-off-a-mesh-file", 'mesh_file = "bed.vtu"\n',
         ("geo.toml: mount 'M1'", "point_j = [0.5, 0.0, 0.0] m", "off the bed"),
         files={"bed.vtu": lambda p: _write_mesh(p, N, [("quad", C)])},
         extra=_MOUNT.format(x=0.5, y=0.0)),
    Case("stiffener-far-off-the-bed",
         'element_size = 0.2\n[[bed.stiffener]]\nname = "rib"\nstart = [0.0, -2.4]\n'
         'end = [0.0, 1e6]\nsection = "flat"\nheight = 0.1\nwidth = 0.01\n',
         ("bed: stiffener 'rib'", "[0.0, 1000000.0]", "leaves the bed")),
    # sizes: refused from the request, before any meshing or reading
    Case("element-size-1e-4", "element_size = 1e-4\n",
         ("bed: element_size = 0.0001 m", "degrees of freedom", "the limit is 250,000")),
    Case("element-size-general-mesh", "element_size = 0.005\n"
         '[[bed.cutout]]\nshape = "circle"\ncentre = [0.0, 1.0]\nradius = 0.1\n',
         ("bed: element_size = 0.005 m", "degrees of freedom", "the limit is 250,000")),
    Case("element-size-1e-7", "element_size = 1e-7\n", ("bed: element_size = 1e-07",)),
    _raw("mesh-vtu-header-10M-points", _VTU_10M,
         ("declares 10,000,000 points", "50,000,000 degrees of freedom", "250,000")),
    _raw("mesh-gmsh2-header-10M-points", _MSH_10M, ("declares 10,000,000 points",),
         file="bed.msh"),
    _raw("mesh-gmsh4-header-10M-points", _MSH4_10M, ("declares 10,000,000 points",),
         file="bed.msh"),
    # mesh files that cannot be read
    _raw("mesh-corrupt-vtu", b"<VTKFile>garbage", ("cannot read it", "not a valid vtu file")),
    _raw("mesh-empty-file", b"", ("cannot read it",)),
    _raw("mesh-gmsh-garbage", b"this is no mesh\n", ("cannot read it",), file="bed.msh"),
    _raw("mesh-unknown-format", b"1 2 3\n", ("cannot read it", "file format"), file="bed.xyz"),
    Case("mesh-file-is-a-fifo", 'mesh_file = "bed.vtu"\n',
         ("bed: mesh_file = 'bed.vtu' is a FIFO, device or socket",),
         {"bed.vtu": lambda p: os.mkfifo(p)}),
    Case("mesh-file-is-a-folder", 'mesh_file = "bed.vtu"\n',
         ("bed: mesh_file = 'bed.vtu' is a folder",), {"bed.vtu": lambda p: p.mkdir()}),
    Case("correction-modes-past-the-mesh", "static_correction = true\ncorrection_modes = 10000\n",
         ("bed: correction_modes = 10000", "has only")),
    Case("mesh-file-a-loop-of-links", 'mesh_file = "bed.vtu"\n',
         ("bed: mesh_file = 'bed.vtu': cannot read it",), {"bed.vtu": lambda p: p.symlink_to(p)}),
    Case("mesh-missing", 'mesh_file = "none.vtu"\n',
         ("bed: mesh_file = 'none.vtu'", "cannot read it")),
    # mesh files that are not a shell
    _mesh("mesh-hexahedra-only", np.array([[0, 0], [1, 0], [1, 1], [0, 1]] * 2),
          [("hexahedron", [[0, 1, 2, 3, 4, 5, 6, 7]])], ("no quad or triangle", "hexahedron")),
    _mesh("mesh-lines-only", N, [("line", C[:, :2])], ("no quad or triangle", "line")),
    _mesh("mesh-quadratic-quads-only", np.vstack([N, N + 0.01, N + 0.02]),
          [("quad9", np.column_stack([C, C + 21, C[:, :1] + 42]))],
          ("no quad or triangle", "quad9")),
    # cells that are not sound
    _mesh("mesh-index-out-of-range", N, [("quad", np.vstack([C, [[0, 1, 2, 999]]]))],
          ("quad 12 refers to nodes [0, 1, 2, 999]", "21 points")),
    _mesh("mesh-zero-area-triangle", N, [("quad", C), ("triangle", [[0, 1, 2]])],
          ("triangle 0", "has no area")),
    _mesh("mesh-triangle-repeated-node", N, [("quad", C), ("triangle", [[0, 0, 1]])],
          ("triangle 0 has a repeated corner",)),
    _mesh("mesh-degenerate-quad", N, [("quad", np.vstack([C[:-1], [[16, 17, 17, 19]]]))],
          ("quad 11 has a repeated corner", "[16, 17, 17, 19]")),
    _mesh("mesh-bow-tie-quad", N, [("quad", np.vstack([C[:-1], C[-1:, [0, 1, 3, 2]]]))],
          ("quad 11", "has no area")),
    _mesh("mesh-non-convex-quad", _ARROW, [("quad", C)], ("quad 3 (corners", "is not convex")),
    _mesh("mesh-repeated-cell", N, [("quad", np.vstack([C, C[3:4, [1, 2, 3, 0]]]))],
          ("quad 3 and quad 12 have the same corners", "1 cell repeat")),
    _mesh("mesh-every-cell-twice", N, [("quad", np.vstack([C, C]))],
          ("quad 0 and quad 12 have the same corners", "12 cells repeat")),
    _mesh("mesh-cells-folded-over", _FOLD, [("quad", np.vstack([C[:-1], [[16, 17, 21, 18]]]))],
          ("the cells around node", "cells overlap there")),
    _mesh("mesh-cells-on-one-side-of-an-edge", np.vstack([N, [[-0.2, 2.0]]]),
          [("quad", C[:-1]), ("triangle", [[16, 19, 21]])],
          ("quad 10 and triangle 0 lie on the same side of their common edge", "overlap")),
    _mesh("mesh-edge-of-three-cells", np.vstack([N, [[0.6, 1.0]]]),
          [("quad", C), ("triangle", [[3, 4, 21]])], ("belongs to 3 cells",)),
    _mesh("mesh-nan-coordinate", np.where(np.arange(21)[:, None] == 3, np.nan, N),
          [("quad", C)], ("node 3 = [nan, nan]", "not finite")),
    _mesh("mesh-1e308-coordinate", np.vstack([N, [[1e308, 0.0]]]),
          [("quad", C), ("triangle", [[0, 1, 21]])], ("node 21 = [1e+308, 0]", "beyond")),
    _mesh("mesh-duplicate-node", np.vstack([N, N[4:5]]),
          [("quad", np.where(C == 4, 21, C)[:3].tolist() + C[3:].tolist())],
          ("nodes 4 and 21 are at the same point [0, -1.6] m",)),
    _mesh("mesh-two-pieces", _TWO, [("quad", np.vstack([C, C + 21]))],
          ("the mesh is in 2 pieces (12, 12 cells)",)),
    _mesh("mesh-pieces-joined-at-a-node", np.vstack([N, N + N[-1] - N[0]]),
          [("quad", np.vstack([C, np.where(C + 21 == 21, 20, C + 21)]))],
          ("the mesh is in 2 pieces",)),
    Case("mesh-with-a-zone-off-it", 'mesh_file = "bed.vtu"\n'
         + _rect((5.0, 0.0), (0.2, 0.2), "zone") + "thickness = 0.2\n",
         ("bed: zone 1", "holds no cell"), {"bed.vtu": lambda p: _write_mesh(p, N,
                                                                             [("quad", C)])}),
    # the frequency commands read the same bed
    Case("frf-unreadable-mesh", 'mesh_file = "bed.vtu"\n',
         ("geo.toml: bed: mesh_file = 'bed.vtu'", "cannot read it"),
         {"bed.vtu": b"<VTKFile>garbage"}, command="frf"),
]


def _snapshot(folder: Path) -> dict:
    out = {}
    for root, _, files in os.walk(folder):
        for f in files:
            p = Path(root) / f
            if p.is_file() and not p.is_symlink():           # not the FIFO of a case
                out[p.relative_to(folder).as_posix()] = hashlib.sha256(p.read_bytes()).hexdigest()
    return out


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_bed_fault(case, tmp_path, capsys):
    for name, content in (case.files or {}).items():
        if callable(content):
            content(tmp_path / name)
        else:
            (tmp_path / name).write_bytes(content)
    text = _SCENE + case.bed + case.extra
    (tmp_path / "geo.toml").write_text(text)
    before = _snapshot(tmp_path)
    out = tmp_path / "out"
    argv = {"modes": ["modes", str(tmp_path / "geo.toml"), "-o", str(out / "m.h5")],
            "frf": ["frf", str(tmp_path / "geo.toml"), "-o", str(out / "frf"), "--no-plots"]}
    code = main(argv[case.command])
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert code == 2, err
    assert "Traceback" not in err
    assert len(lines) == 1, err
    assert lines[0].startswith(f"flexbed {case.command}: geo.toml: "), lines[0]
    assert len(lines[0]) < 400, lines[0]
    for w in case.words:
        assert w in lines[0], (w, lines[0])
    assert _snapshot(tmp_path) == before
    assert not out.exists()


def test_the_catalogue_covers_every_kind():
    assert len(CASES) >= 55


# --- what a mesh file's reader repairs and counts --------------------------------------

def _mass(path: Path) -> float:
    spec = PlateSpec(theory="mindlin", geometry=BedGeometry(mesh_file=str(path)))
    return bed_mass_properties(spec).mass


def test_clockwise_cells_are_turned_and_unused_nodes_dropped(tmp_path):
    """A mesh with some cells clockwise, and a node no cell uses: the same
    nodes and cells as the clean mesh (orientation turned, the node
    dropped), so the same mass to the last bit."""
    tri = np.vstack([C[0, [0, 1, 2]], C[0, [0, 2, 3]]])
    _write_mesh(tmp_path / "clean.vtu", N, [("quad", C[1:]), ("triangle", tri)])
    mixed = np.vstack([C[1:5], C[5:, ::-1]])
    _write_mesh(tmp_path / "mixed.vtu", np.vstack([N, [[9.0, 9.0]]]),
                [("quad", mixed), ("triangle", tri[:, ::-1])])
    clean = read_mesh_file(tmp_path / "clean.vtu", per_node=5, limit=250_000)
    mixed = read_mesh_file(tmp_path / "mixed.vtu", per_node=5, limit=250_000)
    assert np.array_equal(clean[0], mixed[0])
    assert np.array_equal(np.sort(clean[1][:, :3], axis=1), np.sort(mixed[1][:, :3], axis=1))
    assert np.all(areas(*mixed) > 0)
    assert _mass(tmp_path / "mixed.vtu") == pytest.approx(_mass(tmp_path / "clean.vtu"),
                                                         rel=1e-14)
    assert _mass(tmp_path / "clean.vtu") == pytest.approx(7800.0 * 0.1 * 0.8 * 4.8, rel=1e-13)


def test_the_node_count_is_checked_after_reading_too(tmp_path):
    """A format whose header is not searched (meshio's own XDMF) is counted
    after reading: the nodes the cells use against the limit."""
    path = tmp_path / "bed.xdmf"
    _write_mesh(path, N, [("quad", C)])
    assert declared_points(path) is None
    with pytest.raises(GeometryError, match=r"has 21 nodes in its cells: 105 degrees of "
                                            r"freedom \(5 per node\); the limit is 100"):
        read_mesh_file(path, per_node=5, limit=100)
    vtu = tmp_path / "bed.vtu"
    _write_mesh(vtu, N, [("quad", C)])
    assert declared_points(vtu) == 21
    msh = tmp_path / "bed.msh"
    _write_mesh(msh, N, [("quad", C)], file_format="gmsh22", binary=False)
    assert declared_points(msh) == 21


@pytest.mark.parametrize("geometry", [
    BedGeometry(cutouts=(Region("rectangle", (0.1, 1.0), size=(0.3, 0.5)),), element_size=0.05),
    BedGeometry(outline=((0, 0), (4, 0), (4, 0.5), (0.5, 0.5), (0.5, 4), (0, 4)),
                element_size=0.05),
    BedGeometry(cutouts=(Region("circle", (0.0, 1.0), radius=0.2),), element_size=0.05),
    BedGeometry(outline=((0, 0), (2, 0), (2, 1), (0.8, 1.4), (0, 1)), element_size=0.05),
    BedGeometry(zones=(Zone(Region("circle", (0, 0), radius=0.3), 0.2),), element_size=0.02),
], ids=["rectilinear-hole", "rectilinear-L", "circle-hole", "slanted", "circle-zone"])
def test_the_size_estimate_is_within_20_percent(geometry, monkeypatch):
    """The nodes estimated before meshing (what a too-fine element_size is
    refused on) against the nodes of the mesh made, on both routes of the
    mesher."""
    from flexbed.fem import mesher
    seen = []

    def spy(*args):
        seen.append(mesher_estimate(*args))
        return seen[-1]
    mesher_estimate = mesher.estimated_nodes
    monkeypatch.setattr(mesher, "estimated_nodes", spy)
    nodes, _, _ = mesher.mesh_bed(geometry, 0.8, 4.8, 0.1, 10, 10)
    assert 0.8 < seen[0] / nodes.shape[0] < 1.2, (seen[0], nodes.shape[0])

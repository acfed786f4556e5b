"""Beds as they are built (issue 14, geometry): outlines, cut-outs,
thickness zones and imported meshes; mass properties exact; points off the
bed refused by name; the bed's frame at its centre of mass."""

from __future__ import annotations

import math

import meshio
import numpy as np
import pytest

import flexbed
from flexbed.errors import InputError
from flexbed.fem.bed import compute_bed_modes
from flexbed.fem.geometry import BedGeometry, GeometryError, Region, Zone
from flexbed.fem.invariants import shell_mass_properties
from flexbed.fem.mass_properties import shift_inertia
from flexbed.fem.layout import bed_layout, bed_mass_properties
from flexbed.fem.shell import assemble_shell, grid_mesh
from flexbed.fem.spec import PlateSpec, PlateSpecError
from flexbed.files.builtin import builtin_scene_path

RHO, T = 7800.0, 0.1


def _rect_inertia(m, a, b, t, cx, cy):
    """Inertia about the origin (3, 3) of a solid block a × b × t centred at (cx, cy, 0)."""
    J = np.diag([m * (b * b + t * t) / 12, m * (a * a + t * t) / 12, m * (a * a + b * b) / 12])
    c = np.array([cx, cy, 0.0])
    return J + m * (c @ c * np.eye(3) - np.outer(c, c))


def test_cut_out_and_zone_mass_properties_are_exact():
    """Plate 0.8 × 4.8 × 0.1 minus a 0.3 × 0.5 hole at (0.1, 1.0) plus a
    0.8 × 0.6 zone 0.15 thick at y = -1.5: mass, centre of mass and inertia
    by superposition of blocks, to round-off — from the mesh and from the
    assembled mass matrix alike."""
    g = BedGeometry(cutouts=(Region("rectangle", (0.1, 1.0), size=(0.3, 0.5)),),
                    zones=(Zone(Region("rectangle", (0.0, -1.5), size=(0.8, 0.6)), 0.15),))
    spec = PlateSpec(theory="mindlin", geometry=g, nx=8, ny=48)
    blocks = [(+1, 0.8, 4.8, T, 0.0, 0.0), (-1, 0.3, 0.5, T, 0.1, 1.0),
              (-1, 0.8, 0.6, T, 0.0, -1.5), (+1, 0.8, 0.6, 0.15, 0.0, -1.5)]
    m = sum(s * RHO * a * b * t for s, a, b, t, _, _ in blocks)
    first = sum(s * RHO * a * b * t * np.array([x, y, 0.0]) for s, a, b, t, x, y in blocks)
    J0 = sum(s * _rect_inertia(RHO * a * b * t, a, b, t, x, y) for s, a, b, t, x, y in blocks)
    c = first / m
    mp = bed_mass_properties(spec)
    assert mp.mass == pytest.approx(m, rel=1e-13)
    assert np.allclose(mp.centre, c, rtol=0, atol=1e-13)
    assert np.allclose(mp.inertia, shift_inertia(m, J0, c), rtol=1e-12, atol=1e-9)
    model = assemble_shell(spec)                   # origin moved to the centre of mass
    mm, mfirst, mJ = shell_mass_properties(model)
    assert mm == pytest.approx(m, rel=1e-13)
    assert np.abs(mfirst).max() < 1e-11 * m
    assert np.allclose(mJ, mp.inertia, rtol=1e-12, atol=1e-9)


def test_circular_cut_out_has_the_circles_area():
    """A circle is meshed as the regular k-gon (k ≥ 24, sides about
    element_size) of area πr²: the cut-out's mass exactly, its centre of
    mass exactly on the circle's centre."""
    r, h = 0.2, 0.05
    spec = PlateSpec(theory="mindlin", geometry=BedGeometry(
        cutouts=(Region("circle", (0.0, 1.0), radius=r),), element_size=h))
    mp = bed_mass_properties(spec)
    m_plate, m_hole = RHO * T * 0.8 * 4.8, RHO * T * math.pi * r * r
    assert mp.mass == pytest.approx(m_plate - m_hole, rel=1e-12)
    assert mp.centre[1] == pytest.approx(-m_hole * 1.0 / (m_plate - m_hole), rel=1e-11)
    # Jzz: the disc's own polar moment m r²/2 within O(1/k²)
    Jzz = _rect_inertia(m_plate, 0.8, 4.8, T, 0, 0)[2, 2] - m_hole * (r * r / 2 + 1.0)
    Jzz -= mp.mass * mp.centre[1] ** 2
    assert mp.inertia[2, 2] == pytest.approx(Jzz, rel=1e-6)


def test_outline_polygon_with_slanted_edges():
    outline = ((0.0, 0.0), (2.0, 0.0), (2.0, 1.0), (0.8, 1.4), (0.0, 1.0))
    spec = PlateSpec(theory="mindlin", geometry=BedGeometry(outline=outline, element_size=0.1))
    lay = bed_layout(spec)
    nodes, cells = lay.nodes, lay.cells
    area = 2.0 * 1.0 + 0.5 * 2.0 * 0.4
    assert RHO * T * area == pytest.approx(bed_mass_properties(spec).mass, rel=1e-12)
    xy = nodes[cells]
    signed = 0.5 * np.sum(xy[:, :, 0] * np.roll(xy[:, :, 1], -1, axis=1)
                          - np.roll(xy[:, :, 0], -1, axis=1) * xy[:, :, 1], axis=1)
    assert np.all(signed > 0)                     # counter-clockwise, none degenerate


def test_imported_mesh_gives_the_generated_modes(tmp_path):
    """The reference grid written with meshio and read back as mesh_file:
    the same frequencies; as triangles (the triangle element) the same mass."""
    spec = PlateSpec(theory="mindlin", nx=4, ny=24)
    nodes, cells = grid_mesh(spec)
    path = tmp_path / "bed.vtu"
    meshio.write(path, meshio.Mesh(np.column_stack([nodes, np.zeros(len(nodes))]),
                                   [("quad", cells)]))
    imported = PlateSpec(theory="mindlin", geometry=BedGeometry(mesh_file=str(path)))
    a = compute_bed_modes(spec, n_modes=6).modes.frequency
    b = compute_bed_modes(imported, n_modes=6).modes.frequency
    assert np.allclose(a, b, rtol=1e-10)
    tri = np.vstack([cells[:, [0, 1, 2]], cells[:, [0, 2, 3]]])
    path2 = tmp_path / "tri.msh"
    meshio.write(path2, meshio.Mesh(np.column_stack([nodes, np.zeros(len(nodes))]),
                                    [("triangle", tri)]), file_format="gmsh22", binary=False)
    tri_spec = PlateSpec(theory="mindlin", geometry=BedGeometry(mesh_file=str(path2)))
    assert bed_mass_properties(tri_spec).mass == pytest.approx(spec.mass, rel=1e-13)
    assert imported.digest() != tri_spec.digest()


def test_geometry_needs_the_mindlin_shell_and_valid_regions():
    with pytest.raises(PlateSpecError, match='need theory = "mindlin"'):
        PlateSpec(geometry=BedGeometry(element_size=0.1))
    with pytest.raises(GeometryError, match="radius = -1"):
        Region("circle", (0, 0), radius=-1)
    with pytest.raises(GeometryError, match="shape = 'oval'"):
        Region("oval")


def _scene(tmp_path, extra_bed: str, tables: str = "", mounts=None) -> str:
    text = builtin_scene_path().read_text()
    text = text.replace('model = "rigid"', f'model = "flexible"\ntheory = "mindlin"\n'
                                           f'{extra_bed}', 1)
    text = text.replace("nx = 10\nny = 10\n", "nx = 4\nny = 24\n")
    text = text.replace("rayleigh = [0.0, 0.01]\n", f"rayleigh = [0.0, 0.01]\n{tables}", 1)
    for old, new in (mounts or {}).items():
        text = text.replace(old, new, 1)
    path = tmp_path / "geo.toml"
    path.write_text(text)
    return path


def test_point_in_a_cut_out_is_refused_by_name(tmp_path):
    hole = '[[bed.cutout]]\nshape = "rectangle"\ncentre = [-0.24, -1.44]\nsize = [0.1, 0.1]\n'
    with pytest.raises(InputError, match=r"geo.toml: mount 'M5': point_i = \[-0.24, -1.44, "
                                         r"0.0\] m is off the bed"):
        flexbed.load_scene(_scene(tmp_path, "", hole))
    with pytest.raises(InputError, match=r"mount 'M1': point_j = \[-0.5, -2.4, 0.0\] m is "
                                         r"off the bed"):
        flexbed.load_scene(_scene(tmp_path, "", mounts={"point_j = [-0.40, -2.40, 0.00]":
                                                        "point_j = [-0.50, -2.40, 0.00]"}))
    with pytest.raises(InputError, match=r"geo.toml: bed: cutout 1: radius = 0"):
        flexbed.load_scene(_scene(tmp_path, "", '[[bed.cutout]]\nshape = "circle"\n'
                                                'centre = [0, 0]\nradius = 0\n'))


def test_asymmetric_bed_frame_at_its_centre_of_mass(tmp_path):
    """A cut-out moves the centre of mass: the bed body's position and the
    points on the bed are moved with it, the statics run with the
    invariants' first moment zero."""
    hole = '[[bed.cutout]]\nshape = "rectangle"\ncentre = [0.2, 1.0]\nsize = [0.2, 0.6]\n'
    sf = flexbed.load_scene(_scene(tmp_path, "", hole))
    mp = sf.bed.mass_properties
    assert mp.centre[0] < 0 and mp.centre[1] < 0
    bed = sf.scene.bodies[1]
    assert np.allclose(bed.position, np.array([0.0, 0.0, 5.1]) + mp.centre, atol=1e-15)
    assert bed.mass == pytest.approx(RHO * T * (0.8 * 4.8 - 0.12), rel=1e-13)
    m1 = sf.scene.mounts[0]
    assert np.allclose(m1.point_j, np.array([-0.4, -2.4, 0.0]) - mp.centre)
    data = flexbed.modes(sf)
    assert np.abs(data.invariants.first_moment).max() < 1e-9
    assert np.allclose(data.invariants.inertia, mp.inertia, rtol=1e-12, atol=1e-9)
    eq = flexbed.statics(sf)
    assert eq.equilibrium.success


def test_post_takes_bed_points_in_the_drawing_frame(tmp_path):
    """After a run of the asymmetric bed, a point given at a mount's bed end
    (drawing frame, as in the scene) moves with that mount end: the
    mount's deflection is the distance of its two points, to round-off."""
    from flexbed.analyses.points import Point, Run
    from flexbed.cli import main
    hole = '[[bed.cutout]]\nshape = "rectangle"\ncentre = [0.2, 1.0]\nsize = [0.2, 0.6]\n'
    scene = _scene(tmp_path, "", hole)
    modes, results = tmp_path / "m.h5", tmp_path / "r.h5"
    assert main(["modes", str(scene), "-o", str(modes)]) == 0
    assert main(["simulate", str(scene), "--modes-file", str(modes), "-o", str(results),
                 "--t-end", "0.05", "--no-progress"]) == 0
    run = Run(results)
    assert np.allclose(run.bed_centre, flexbed.load_scene(scene).bed.mass_properties.centre)
    Pi = run.absolute(Point("i", "base", np.array([-0.4, -2.4, 5.0])))
    Pj = run.absolute(Point("j", "bed", np.array([-0.4, -2.4, 0.0])))
    m = run.mount_names.index("M1")
    dx = Pj.position - Pi.position - np.array([0.0, 0.0, 0.1])
    assert np.abs(dx - run.mounts["deflection"][:, m]).max() < 1e-12

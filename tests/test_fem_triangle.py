"""The three-node shell triangle (issue 14, imported triangle meshes):
patch tests, no shear locking, NAFEMS FV12 and the reference bed against
the 3D solid on triangles, mixed meshes, exact mass properties, a point
inside a triangle, and a scene whose bed is an imported triangle mesh."""

from __future__ import annotations

import meshio
import numpy as np
import pytest

from flexbed.analyses.points import Point, Run
from flexbed.cli import main
from flexbed.errors import InputError
from flexbed.fem.bed import compute_bed_modes
from flexbed.fem.cells import as_cells, is_triangle
from flexbed.fem.geometry import BedGeometry
from flexbed.fem.invariants import shell_mass_properties
from flexbed.fem.layout import bed_layout
from flexbed.fem.modes import free_free_modes
from flexbed.fem.quad_shapes import QuadShapes
from flexbed.fem.shell import assemble_mesh, assemble_shell, grid_mesh
from flexbed.fem.spec import PlateSpec
from flexbed.files.builtin import builtin_scene_path
from flexbed.files.modes import read_modes_file

FV12 = dict(length_x=10.0, length_y=10.0, young=2e11, poisson=0.3, density=8000.0)
SOLID = np.array([23.144, 63.807, 80.281, 124.997, 163.317, 169.63, 206.168])

# MacNeal & Harder's patch: a 0.24 x 0.12 rectangle, four distorted inner quads
PATCH_NODES = np.array([[0.0, 0.0], [0.24, 0.0], [0.24, 0.12], [0.0, 0.12],
                        [0.04, 0.02], [0.18, 0.03], [0.16, 0.08], [0.08, 0.08]])
PATCH_QUADS = np.array([[0, 1, 5, 4], [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7], [4, 5, 6, 7]])


def triangles(spec: PlateSpec, nodes: np.ndarray, quads: np.ndarray) -> np.ndarray:
    """Each grid quad in two triangles, the diagonals mirrored quadrant by
    quadrant (the mesh is its own mirror image in x and in y)."""
    i, j = (g.ravel() for g in np.meshgrid(np.arange(spec.nx), np.arange(spec.ny)))
    a, b, c, d = quads.T
    same = ((i < spec.nx / 2) == (j < spec.ny / 2))[:, None]
    t1 = np.where(same, np.column_stack([a, b, c]), np.column_stack([a, b, d]))
    t2 = np.where(same, np.column_stack([a, c, d]), np.column_stack([b, c, d]))
    return as_cells(np.zeros((0, 4)), np.vstack([t1, t2]))


def tri_modes(spec: PlateSpec, n_modes: int):
    nodes, quads = grid_mesh(spec)
    return free_free_modes(assemble_mesh(spec, nodes, triangles(spec, nodes, quads)),
                           n_modes=n_modes)


def _patches():
    """The patch as triangles only, and mixed (two quads kept)."""
    q = PATCH_QUADS
    tri = np.vstack([q[:, [0, 1, 2]], q[:, [0, 2, 3]]])
    mixed = as_cells(q[:2], np.vstack([q[2:, [0, 1, 2]], q[2:, [0, 2, 3]]]))
    return {"triangles": as_cells(np.zeros((0, 4)), tri), "mixed": mixed}


@pytest.mark.parametrize("kind", ["triangles", "mixed"])
def test_patch_tests_constant_strain_and_constant_curvature(kind):
    """A linear in-plane field and a quadratic deflection (constant strain,
    constant curvature, zero shear): no force on the inner nodes and the
    exact strain energy, on distorted triangles and on a mixed patch."""
    spec = PlateSpec(length_x=0.24, length_y=0.12, thickness=0.001, young=1e6,
                     poisson=0.25, theory="mindlin")
    cells = _patches()[kind]
    model = assemble_mesh(spec, PATCH_NODES, cells)
    x, y = PATCH_NODES.T
    C = np.array([[1.0, 0.25, 0.0], [0.25, 1.0, 0.0], [0.0, 0.0, 0.375]])
    area = 0.24 * 0.12
    a, b, c = 1e-3, 2e-3, 1.5e-3
    membrane = model.dof_vector(u=a * x + 0.5 * c * y, v=b * y + 0.5 * c * x)
    eps = np.array([a, b, c])
    # w = (a x² + b y² + c x y) / 2, normal along it: θy = −w,x, θx = w,y
    bending = model.dof_vector(w=0.5 * (a * x * x + b * y * y + c * x * y),
                               ty=-(a * x + 0.5 * c * y), tx=b * y + 0.5 * c * x)
    kappa = -eps
    Dm = 1e6 * 0.001 / (1 - 0.0625)
    Db = 1e6 * 0.001 ** 3 / (12 * (1 - 0.0625))
    inner = model.node_dofs[:, 4:].ravel()
    for d, D, e in ((membrane, Dm, eps), (bending, Db, kappa)):
        f = model.K @ d
        scale = np.abs(model.K).max() * np.abs(d).max()          # the terms that cancel
        assert np.abs(f[inner]).max() <= 1e-13 * scale, np.abs(f[inner]).max() / scale
        assert 0.5 * d @ f == pytest.approx(0.5 * D * e @ C @ e * area, rel=1e-12)
    # no shear: zero to round-off of the shear stiffness's terms
    shear = bending @ model.K_shear @ bending
    assert abs(shear) <= 1e-13 * np.abs(model.K_shear).max() * np.abs(bending).max() ** 2


@pytest.mark.slow
def test_no_shear_locking_at_t_over_l_1_1000():
    """t/L = 1/1000 on triangles: against the converged thin-plate
    (Kirchhoff) values the error is the mesh's; the largest falls as h²
    (2 × n × n triangles, n = 8, 16, 32: 4.96, 1.18, 0.29 %, ratio 4.1 per
    halving); a locking element stays far off whatever the mesh (MITC3
    without the shear stabilisation: 18, 13, 3.5 %)."""
    spec = dict(FV12, thickness=0.01)
    thin = compute_bed_modes(PlateSpec(**spec, nx=24, ny=24, rotary_inertia=False),
                             n_modes=6).modes.frequency
    err = [np.abs(tri_modes(PlateSpec(**spec, nx=n, ny=n, theory="mindlin"), 6).frequency
                  / thin - 1.0) for n in (8, 16, 32)]
    worst = [e.max() for e in err]
    assert worst[2] < 0.003, err[2]
    assert worst[0] / worst[1] > 3.5 and worst[1] / worst[2] > 3.5, worst
    assert np.all(err[2] < err[1]) and np.all(err[1] < err[0]), err


@pytest.mark.slow
def test_nafems_fv12_on_triangles():
    """NAFEMS FV12 on 2 x 48 x 48 triangles within 0.15 % of 1.622, 2.360,
    2.922 and Leissa's 4.190, 4.190, 7.356 Hz (−0.12, −0.00, +0.03, −0.05,
    −0.05, +0.10 %); from 24 to 48 elements a side the 3rd and 6th modes'
    errors fall four-fold and more (+0.15 → +0.03 %, +0.49 → +0.10 %)."""
    target = np.array([1.622, 2.360, 2.922, 4.190, 4.190, 7.356])
    err = [tri_modes(PlateSpec(**FV12, thickness=0.05, nx=n, ny=n, theory="mindlin"),
                     6).frequency / target - 1.0 for n in (24, 48)]
    assert np.all(np.abs(err[1]) < 1.5e-3), err[1]
    assert np.all(np.abs(err[1][[2, 5]]) < 0.25 * np.abs(err[0][[2, 5]])), err


@pytest.mark.slow
def test_reference_bed_on_triangles_against_the_3d_solid():
    """2 x 20 x 120 triangles (5 cm squares halved): the first seven elastic
    modes within 0.35 % of the 3D solid (torsion +0.33 %, +0.35 %; the rest
    within 0.04 %), the in-plane mode 6th."""
    modes = tri_modes(PlateSpec(nx=20, ny=120, theory="mindlin"), 7)
    rel = modes.frequency / SOLID - 1.0
    assert np.all(np.abs(rel) < 3.5e-3), rel
    assert modes.labels[5] == "in-plane" and modes.labels[2] == "torsion"


def test_mixed_mesh_gives_the_grids_modes():
    """Half of the reference bed's grid as triangles, half as quads (conforming
    at the seam): within 1 % of the all-quad grid, six rigid modes at zero."""
    spec = PlateSpec(nx=8, ny=48, theory="mindlin")
    nodes, quads = grid_mesh(spec)
    y = nodes[quads].mean(axis=1)[:, 1]
    low, high = quads[y < 0], quads[y >= 0]
    cells = as_cells(high, np.vstack([low[:, [0, 1, 2]], low[:, [0, 2, 3]]]))
    mixed = assemble_mesh(spec, nodes, cells)
    assert is_triangle(mixed.cells).sum() == 2 * low.shape[0]
    f = free_free_modes(mixed, n_modes=7).frequency
    g = free_free_modes(assemble_mesh(spec, nodes, quads), n_modes=7).frequency
    assert np.all(np.abs(f / g - 1) < 0.01), f / g - 1
    R = mixed.rigid_vectors()
    assert np.abs(mixed.K @ R).max() <= 1e-9 * np.abs(mixed.K).max()


def test_triangle_mesh_mass_properties_are_exact():
    """An L-shaped bed meshed in triangles with a thicker triangle zone: mass,
    centre and inertia equal the solid's (exact integrals), and the shell's
    consistent mass holds the same numbers."""
    rho = 7800.0
    pts = np.array([[0, 0], [2, 0], [2, 1], [1, 1], [1, 3], [0, 3], [1, 0], [0, 1]], float)
    tri = np.array([[0, 6, 7], [6, 3, 7], [6, 1, 2], [6, 2, 3], [7, 3, 4], [7, 4, 5]])
    cells = as_cells(np.zeros((0, 4)), tri)
    t = np.array([0.1, 0.1, 0.1, 0.1, 0.2, 0.1])
    spec = PlateSpec(theory="mindlin", density=rho)
    model = assemble_mesh(spec, pts, cells, thickness=t)
    m, first, J = shell_mass_properties(model)
    # the same plate cut otherwise: [0,2]x[0,1] by its other diagonal (t = 0.1),
    # the triangle (0,1),(1,1),(1,3) (t = 0.2) and (0,1),(1,3),(0,3) (t = 0.1)
    parts = []                              # (mass, centroid, ∫x², ∫y², ∫xy, ∫z²)

    def tri_part(p, th):
        d1, d2 = p[1] - p[0], p[2] - p[0]
        A = 0.5 * abs(d1[0] * d2[1] - d1[1] * d2[0])

        def sx(f, g):
            return A / 12 * (sum(f[i] * g[i] for i in range(3)) + f.sum() * g.sum())

        x, y = p[:, 0], p[:, 1]
        mm = rho * th * A
        return mm, p.mean(axis=0), rho * th * sx(x, x), rho * th * sx(y, y), \
            rho * th * sx(x, y), mm * th * th / 12

    for tri_pts, th in ((pts[[0, 1, 2]], 0.1), (pts[[0, 2, 7]], 0.1), (pts[[7, 3, 4]], 0.2),
                        (pts[[7, 4, 5]], 0.1)):
        parts.append(tri_part(np.array(tri_pts), th))
    mass = sum(p[0] for p in parts)
    centre = sum(p[0] * p[1] for p in parts) / mass
    xx, yy, xy, zz = (sum(p[k] for p in parts) for k in (2, 3, 4, 5))
    J0 = np.array([[yy + zz, -xy, 0], [-xy, xx + zz, 0], [0, 0, xx + yy]])
    c = np.array([*centre, 0.0])
    Jc = J0 - mass * (c @ c * np.eye(3) - np.outer(c, c))
    assert m == pytest.approx(mass, rel=1e-13)
    assert np.allclose(first / m, c, rtol=1e-13, atol=1e-15)
    assert np.allclose(J - m * (first / m @ (first / m) * np.eye(3)
                                - np.outer(first / m, first / m)), Jc, rtol=1e-12)
    from flexbed.fem.mass_properties import plate_mass_properties
    mp = plate_mass_properties(pts, cells, t, rho)
    assert mp.mass == pytest.approx(mass, rel=1e-13)
    assert np.allclose(mp.centre, c, rtol=1e-13) and np.allclose(mp.inertia, Jc, rtol=1e-12)


def test_point_inside_a_triangle_is_the_linear_field():
    """Mode shapes at a point inside a triangle are the linear interpolation
    of its corners (and the height lever of the rotations); a point off the
    mesh is refused."""
    nodes = np.array([[0.0, 0.0], [1.0, 0.0], [0.3, 0.8], [1.2, 1.1]])
    cells = as_cells(np.zeros((0, 4)), [[0, 1, 2], [1, 3, 2]])
    rng = np.random.default_rng(3)
    trans, rot = rng.normal(size=(2, 2, 4, 3))
    shapes = QuadShapes(nodes, cells, trans, rot)
    p = 0.2 * nodes[1] + 0.5 * nodes[3] + 0.3 * nodes[2]          # in the second triangle
    cell, s = shapes.locate(*p)
    assert cell == 1
    t, r = shapes.at(np.array([[p[0], p[1], 0.05]]))

    def lin(f):
        return 0.2 * f[:, 1] + 0.5 * f[:, 3] + 0.3 * f[:, 2]

    assert np.allclose(r[:, 0], lin(rot), rtol=1e-13, atol=1e-14)
    expect = lin(trans) + 0.05 * np.stack([lin(rot)[:, 1], -lin(rot)[:, 0],
                                           np.zeros(2)], axis=1)
    assert np.allclose(t[:, 0], expect, rtol=1e-13, atol=1e-14)
    assert shapes.locate(1.0, 1.1) is None                      # outside both triangles


def _triangle_scene(tmp_path):
    """The built-in scene with a flexible Mindlin bed read from a triangle
    mesh file (the 4 x 24 grid halved), modes = "auto"."""
    nodes, quads = grid_mesh(PlateSpec(nx=4, ny=24))
    tri = np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    meshio.write(tmp_path / "bed.vtu", meshio.Mesh(np.column_stack([nodes, 0 * nodes[:, 0]]),
                                                   [("triangle", tri)]))
    text = builtin_scene_path().read_text()
    text = text.replace('model = "rigid"', 'model = "flexible"\ntheory = "mindlin"\n'
                        'mesh_file = "bed.vtu"', 1)
    text = text.replace("nx = 10\nny = 10\nmodes = 2\n", 'nx = 4\nny = 24\nmodes = "auto"\n')
    text = text.replace("t_end = 3.0", "t_end = 0.1")
    path = tmp_path / "tri.toml"
    path.write_text(text)
    return path


def test_scene_with_an_imported_triangle_mesh_simulates(tmp_path):
    """`flexbed modes` and `simulate` (statics, time integration) on a bed read
    from a triangle mesh: the modes file keeps the triangles (a, b, c, c);
    a mount's point inside a triangle moves as the blend of the triangle's
    corners, a point off the bed is refused."""
    scene = _triangle_scene(tmp_path)
    out, modes = tmp_path / "tri.h5", tmp_path / "tri-modes.h5"
    assert main(["modes", str(scene), "-o", str(modes)]) == 0
    assert main(["simulate", str(scene), "-o", str(out), "--t-end", "0.05",
                 "--modes-file", str(modes), "--no-progress"]) == 0
    run = Run(out)
    data = read_modes_file(run.modes_path)
    assert data.cells.shape == (192, 4) and is_triangle(data.cells).all()
    assert data.plate.theory == "mindlin" and data.n_modes >= 1
    # mount M5's bed end (-0.24, -1.44) is inside a triangle (grid nodes every
    # 0.2 m): rigid motion and the linear field make it the corners' blend
    p = np.array([-0.24, -1.44])
    cell, s = QuadShapes(data.nodes[:, :2], data.cells, data.translation,
                         data.rotation).locate(*p)
    N = np.array([1 - s[0] - s[1], s[0], s[1]])
    corners = data.cells[cell, :3]
    assert np.allclose(N @ data.nodes[corners, :2], p, rtol=0, atol=1e-14)

    def at(q):
        return run.absolute(Point("q", "bed", np.array([q[0], q[1], 0.0]))).position

    blend = sum(n * at(data.nodes[c]) for n, c in zip(N, corners))
    assert np.abs(at(p) - blend).max() < 1e-12
    assert np.abs(at(p)[-1] - at(p)[0]).max() > 1e-5             # and it moved
    with pytest.raises(InputError, match="lies off the bed"):
        run.absolute(Point("off", "bed", np.array([0.5, 0.0, 0.0])))
    lay = bed_layout(PlateSpec(theory="mindlin", geometry=BedGeometry(
        mesh_file=str(tmp_path / "bed.vtu"))))
    assert lay.mass_properties.mass == pytest.approx(0.8 * 4.8 * 0.1 * 7800.0, rel=1e-13)


@pytest.mark.parametrize("cells, blocks", [
    (as_cells([[0, 1, 4, 3]], [[1, 2, 5], [1, 5, 4]]), {"quad": 1, "triangle": 2}),
    (as_cells(np.zeros((0, 4)), [[0, 1, 4], [0, 4, 3]]), {"triangle": 2})])
def test_bed_motion_and_mode_vtu_files_hold_the_triangles(tmp_path, cells, blocks):
    """The XDMF bed motion ("Mixed" or "Triangle" topology) and the modes VTU
    read back with meshio give the cells as they are."""
    from flexbed.analyses.mode_shapes import ShapeMesh
    from flexbed.fem.export import write_modes_vtu
    from flexbed.files.xdmf import write_bed_motion, xdmf_topology
    nodes = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [0, 1, 0], [1, 1, 0], [2, 1, 0.0]])
    disp = np.arange(2 * 6 * 3, dtype=float).reshape(2, 6, 3)
    path = write_bed_motion(tmp_path / "m.xdmf", nodes, cells, np.array([0.0, 0.1]), disp,
                            disp[:, :, 2])
    with meshio.xdmf.TimeSeriesReader(path) as r:
        _, got = r.read_points_cells()
        t, data, _ = r.read_data(1)
    assert {b.type: len(b.data) for b in got} == blocks and t == 0.1
    assert np.array_equal(data["displacement"], disp[1])
    tri = is_triangle(cells)
    want = {"quad": cells[~tri].tolist(), "triangle": cells[tri, :3].tolist()}
    assert all(b.data.tolist() == want[b.type] for b in got)
    vtu = meshio.read(write_modes_vtu(tmp_path / "m.vtu", nodes, cells, disp[:1], disp[:1],
                                      np.array([1.0])))
    assert {b.type: b.data.tolist() for b in vtu.cells} == {k: want[k] for k in blocks}
    topo, flat = xdmf_topology(cells)
    assert ShapeMesh("bed", nodes, flat, topo, disp).cell_count == len(cells)


def test_stiffener_and_fixed_mass_on_a_triangle_mesh(tmp_path):
    """A bed read from a triangle mesh with a stiffener along a mesh line and
    a fixed mass inside a triangle: the shell's mass matrix holds the
    composite's mass properties exactly (rigid-body block RᵀMR), rigid
    motions strain nothing, and the frequencies agree with the same bed on
    the quad grid within 1.5 %."""
    from flexbed.fem.fixed_masses import FixedMass
    from flexbed.fem.stiffeners import Stiffener, section_of
    nodes, quads = grid_mesh(PlateSpec(nx=8, ny=24))
    tri = np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    meshio.write(tmp_path / "bed.vtu", meshio.Mesh(np.column_stack([nodes, 0 * nodes[:, 0]]),
                                                   [("triangle", tri)]))
    sec = section_of("flat", height=0.12, width=0.02)
    extras = dict(theory="mindlin",
                  stiffeners=(Stiffener("keel", (0.1, -2.4), (0.1, 2.4), sec,
                                        -(0.05 + sec.centroid)),),
                  masses=(FixedMass("pump", (0.23, 1.07, 0.3), 300.0,
                                    ((20.0, 1.0, 0.0), (1.0, 30.0, 2.0), (0.0, 2.0, 25.0))),))
    spec = PlateSpec(**extras, geometry=BedGeometry(mesh_file=str(tmp_path / "bed.vtu")))
    model = assemble_shell(spec)
    mp = bed_layout(spec).mass_properties
    m, c, J = mp.mass, np.array([0.0, 0.0, 0.0]), mp.inertia
    d = np.array([0.0, 0.0, -model.mid_z])                  # the mid-surface below c
    dt = np.array([[0, -d[2], d[1]], [d[2], 0, -d[0]], [-d[1], d[0], 0]])
    Jo = J + m * (d @ d * np.eye(3) - np.outer(d, d))
    expect = np.block([[m * np.eye(3), -m * dt], [m * dt, Jo]])
    R = model.rigid_vectors()
    assert np.allclose(R.T @ (model.M @ R), expect, rtol=1e-12, atol=1e-9 * m)
    assert np.abs(model.K @ R).max() < 1e-6 * np.abs(model.K).max()
    mm, first, _ = shell_mass_properties(model)
    assert mm == pytest.approx(m, rel=1e-13) and np.abs(first - m * c).max() < 1e-10 * m
    f_tri = free_free_modes(model, n_modes=6).frequency
    f_quad = compute_bed_modes(PlateSpec(**extras, nx=8, ny=24), n_modes=6).modes.frequency
    assert np.all(np.abs(f_tri / f_quad - 1) < 0.015), f_tri / f_quad - 1

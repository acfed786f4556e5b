"""Stiffeners (issue 14): beams along lines of the plate, joined with their
eccentricity. Mass properties exact, rigid-body mass matrix the
composite's, and a stiffened strip against Euler–Bernoulli beam theory for
its T-section (a documented converged reference)."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

import flexbed
from flexbed.errors import InputError
from flexbed.fem.bed import compute_bed_modes
from flexbed.fem.invariants import shell_mass_properties
from flexbed.fem.layout import bed_mass_properties
from flexbed.fem.shell import assemble_shell
from flexbed.fem.spec import PlateSpec, PlateSpecError
from flexbed.fem.stiffeners import Stiffener, section_of
from flexbed.files.builtin import builtin_scene_path

E, NU, RHO = 2.1e11, 0.3, 7800.0


def _bar_along_y(x0, y0, y1, sec, e):
    """Mass, centroid and inertia about the centroid of a prismatic bar along y."""
    L = y1 - y0
    m = RHO * sec.area * L
    J = np.diag([RHO * L * sec.Iy + m * L * L / 12, RHO * L * (sec.Iy + sec.Iz),
                 RHO * L * sec.Iz + m * L * L / 12])
    return m, np.array([x0, 0.5 * (y0 + y1), e]), J


def test_mass_properties_with_stiffeners_are_exact():
    t = 0.1
    flat = section_of("flat", height=0.12, width=0.02)
    tee = section_of("T", height=0.15, web=0.012, flange_width=0.1, flange=0.015)
    sts = (Stiffener("a", (-0.2, -2.4), (-0.2, 2.4), flat, -(t / 2 + flat.centroid)),
           Stiffener("b", (0.2, -1.2), (0.2, 2.0), tee, -(t / 2 + tee.centroid)))
    spec = PlateSpec(theory="mindlin", nx=4, ny=12, stiffeners=sts)
    parts = [(PlateSpec().mass, np.zeros(3), np.diag(PlateSpec().inertia)),
             _bar_along_y(-0.2, -2.4, 2.4, flat, sts[0].offset),
             _bar_along_y(0.2, -1.2, 2.0, tee, sts[1].offset)]
    m = sum(p[0] for p in parts)
    c = sum(p[0] * p[1] for p in parts) / m
    J = sum(Ji + mi * ((pi - c) @ (pi - c) * np.eye(3) - np.outer(pi - c, pi - c))
            for mi, pi, Ji in parts)
    mp = bed_mass_properties(spec)
    assert mp.mass == pytest.approx(m, rel=1e-14)
    assert np.allclose(mp.centre, c, rtol=0, atol=1e-14)
    assert np.allclose(mp.inertia, J, rtol=1e-13, atol=1e-9)
    model = assemble_shell(spec)
    mm, first, Jm = shell_mass_properties(model)
    assert mm == pytest.approx(m, rel=1e-13)
    assert np.abs(first).max() < 1e-11 * m
    assert np.allclose(Jm, J, rtol=1e-12, atol=1e-9)
    # the rigid composite's mass matrix about the mid-surface point under c
    R = model.rigid_vectors()
    d = np.array([0.0, 0.0, -model.mid_z])
    dt = np.array([[0, -d[2], d[1]], [d[2], 0, -d[0]], [-d[1], d[0], 0]])
    Jo = J + m * (d @ d * np.eye(3) - np.outer(d, d))
    expect = np.block([[m * np.eye(3), -m * dt], [m * dt, Jo]])
    assert np.allclose(R.T @ (model.M @ R), expect, rtol=1e-12, atol=1e-9 * m)
    # and rigid motions strain nothing
    assert np.abs(R.T @ (model.K @ R)).max() < 1e-6 * np.abs(model.K).max()


@pytest.mark.slow
def test_stiffened_strip_against_beam_theory_and_a_solid():
    """A 0.2 × 3 × 0.02 m strip with a 0.1 × 0.02 m flat bar below its centre
    line is a free–free T-beam (the neutral axis 31 mm below the plate). Its
    first vertical bending mode, converged in the mesh (4 × 60 against
    8 × 120 within 0.1 %), lies within 0.1 % of a 3D solid of the strip
    built here (27-node hexahedra, 16,335 DOFs; 67.388 Hz, 67.383 Hz at
    58,563 DOFs) and below Euler–Bernoulli for the composite section by
    the shear flexibility of plate and web (L/h = 25): 1.1 %. The old
    Euler–Bernoulli stiffener (model = "euler-bernoulli") is 0.5 % stiff.
    The default (model = "hinged", the web's own section rotation, extra
    DOFs) keeps the invariants exact: the mass, ∫ρΦ = 0 and ΦᵀMΦ = I."""
    from flexbed.fem.solid import SolidBed, Web, solid_modes
    b, L, t = 0.2, 3.0, 0.02
    sec = section_of("flat", height=0.1, width=0.02)
    st = Stiffener("bar", (0.0, -L / 2), (0.0, L / 2), sec, -(t / 2 + sec.centroid))
    assert st.model == "hinged" and sec.shear_area == pytest.approx(5 / 6 * 0.002)
    Af, Aw = b * t, sec.area
    zc = Aw * st.offset / (Af + Aw)
    EI = E * (b * t ** 3 / 12 + Af * zc ** 2 + sec.Iy + Aw * (st.offset - zc) ** 2)
    f1 = 4.730040745 ** 2 / (2 * math.pi * L * L) * math.sqrt(EI / (RHO * (Af + Aw)))
    solid = solid_modes(SolidBed(length_x=b, length_y=L, thickness=t, webs=(Web(0.0, 0.02, 0.1),),
                                 h0=0.1), level=1, nz=1, n_modes=2).frequency[0]
    f = {}
    for model, mesh in (("hinged", (4, 60)), ("hinged", (8, 120)), ("timoshenko", (8, 120)),
                        ("euler-bernoulli", (8, 120))):
        spec = PlateSpec(length_x=b, length_y=L, thickness=t, young=E, poisson=NU,
                         density=RHO, nx=mesh[0], ny=mesh[1], theory="mindlin",
                         stiffeners=(replace(st, model=model),))
        bed = compute_bed_modes(spec, n_modes=3)
        f[model, mesh] = bed.modes.frequency[0]
        inv = bed.invariants
        assert inv.mass == pytest.approx(RHO * (Af + Aw) * L, rel=1e-13)
        assert np.abs(inv.phi_integral).max() < 1e-10
        assert np.allclose(inv.modal_mass, np.eye(3), atol=1e-12)
    fine = f["hinged", (8, 120)]
    assert abs(fine / f["hinged", (4, 60)] - 1) < 1e-3
    assert abs(fine / solid - 1) < 1e-3, (fine, solid)
    assert abs(f["timoshenko", (8, 120)] / solid - 1) < 1e-3
    assert 0.005 < 1 - fine / f1 < 0.015
    assert f["euler-bernoulli", (8, 120)] / solid - 1 > 0.004


def test_stiffener_inputs(tmp_path):
    sec = section_of("flat", height=0.1, width=0.02)
    off_grid = Stiffener("keel", (0.05, -2.4), (0.05, 2.4), sec, -0.1)
    with pytest.raises(PlateSpecError, match="stiffener 'keel' from \\[0.05, -2.4\\]"):
        assemble_shell(PlateSpec(theory="mindlin", nx=4, ny=12, stiffeners=(off_grid,)))
    with pytest.raises(PlateSpecError, match="stiffener needs theory"):
        PlateSpec(stiffeners=(off_grid,))
    text = builtin_scene_path().read_text().replace(
        'model = "rigid"', 'model = "flexible"\ntheory = "mindlin"', 1)
    text = text.replace("nx = 10\nny = 10\n", "nx = 4\nny = 24\n")
    stiff = ('[[bed.stiffener]]\nname = "keel"\nstart = [0.0, -2.4]\nend = [0.0, 2.4]\n'
             'section = "T"\nheight = 0.15\nweb = 0.012\nflange_width = 0.1\nflange = 0.015\n')
    good = text.replace("rayleigh = [0.0, 0.01]\n", "rayleigh = [0.0, 0.01]\n" + stiff, 1)
    (tmp_path / "good.toml").write_text(good)
    sf = flexbed.load_scene(tmp_path / "good.toml")
    st = sf.bed.plate.stiffeners[0]
    assert st.offset == pytest.approx(-(0.05 + st.section.centroid))
    assert sf.scene.bodies[1].mass == pytest.approx(
        PlateSpec().mass + RHO * 4.8 * (0.15 * 0.012 + 0.1 * 0.015), rel=1e-13)
    (tmp_path / "bad.toml").write_text(good.replace("web = 0.012", "web = 0"))
    with pytest.raises(InputError, match=r"bad.toml: bed: stiffener 'keel': web = 0 must be"):
        flexbed.load_scene(tmp_path / "bad.toml")


def _mesh_scene(tmp_path, name, cells, stiffener):
    """The built-in scene with a flexible Mindlin bed read from a mesh file of
    the 4 x 24 grid's nodes and the given cells, and one flat stiffener."""
    import meshio
    from flexbed.fem.shell import grid_mesh
    nodes, _ = grid_mesh(PlateSpec(nx=4, ny=24))
    meshio.write(tmp_path / f"{name}.vtu",
                 meshio.Mesh(np.column_stack([nodes, 0 * nodes[:, 0]]), cells))
    text = builtin_scene_path().read_text().replace(
        'model = "rigid"', f'model = "flexible"\ntheory = "mindlin"\nmesh_file = "{name}.vtu"', 1)
    (a, b), (c, d) = stiffener
    stiff = (f'[[bed.stiffener]]\nname = "diag"\nstart = [{a}, {b}]\nend = [{c}, {d}]\n'
             'section = "flat"\nheight = 0.1\nwidth = 0.02\n')
    path = tmp_path / f"{name}.toml"
    path.write_text(text.replace("rayleigh = [0.0, 0.01]\n", "rayleigh = [0.0, 0.01]\n" + stiff, 1))
    return path


def test_stiffener_across_cells_is_refused(tmp_path):
    """A stiffener along the diagonals of the grid's squares has mesh nodes on
    its line from end to end, but on quads consecutive ones are opposite
    corners of a cell, joined through it by no edge: the scene is refused in
    one line naming the stiffener and the two nodes (exit 2). On triangles
    whose edges run along the line it is a beam of cell edges: accepted,
    through the five nodes in order. A line off the grid is refused by the
    scene reader too (before: a traceback from the modes stage, exit 1)."""
    from flexbed.cli import main
    from flexbed.fem.layout import bed_layout
    from flexbed.fem.shell import grid_mesh
    from flexbed.fem.stiffeners import line_nodes
    _, quads = grid_mesh(PlateSpec(nx=4, ny=24))
    line = ((-0.4, -2.4), (0.4, -1.6))
    bad = _mesh_scene(tmp_path, "quads", [("quad", quads)], line)
    with pytest.raises(InputError, match=r"^\S*quads.toml: bed: stiffener 'diag' from "
                                         r"\[-0.4, -2.4\] to \[0.4, -1.6\] m crosses cells: its "
                                         r"mesh nodes at \[-0.4, -2.4\] and \[-0.2, -2.2\] m, "
                                         r"next to each other on its line, are not joined by "
                                         r"a cell edge \(give the mesh cell edges along the "
                                         r"stiffener's line\)$"):
        flexbed.load_scene(bad)
    assert main(["modes", str(bad), "-o", str(tmp_path / "m.h5")]) == 2
    tri = np.vstack([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])   # diagonals along the line
    good = flexbed.load_scene(_mesh_scene(tmp_path, "tri", [("triangle", tri)], line))
    plate = good.bed.plate
    lay = bed_layout(plate)
    order, _ = line_nodes(plate.stiffeners[0], lay.nodes, lay.cells, lay.centre[:2])
    expect = np.linspace(line[0], line[1], 5)
    assert np.allclose(lay.nodes[order] + lay.centre[:2], expect, rtol=0, atol=1e-12)
    off = _mesh_scene(tmp_path, "off", [("quad", quads)], ((0.05, -2.4), (0.05, 2.4)))
    with pytest.raises(InputError, match=r"^\S*off.toml: bed: stiffener 'diag' from "
                                         r"\[0.05, -2.4\] to \[0.05, 2.4\] m does not run along "
                                         r"lines of the mesh"):
        flexbed.load_scene(off)

"""Stresses in the bed (issue 26 part 3): the recovery operators of
fem/stresses.py against closed forms — a plate strip in cylindrical
bending (σ = 6M/t², σyy = ν σxx) on the Mindlin shell and the Kirchhoff
plate, a stiffened strip as a composite beam (σ = E M (z − z_na)/EI) —
and the plane-stress measures."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg as sla

from flexbed.fem.plate import assemble_plate
from flexbed.fem.shell import assemble_shell
from flexbed.fem.spec import PlateSpec
from flexbed.fem.stiffeners import Stiffener, section_of
from flexbed.fem.stresses import (face_stresses, plate_stress_operators, principal,
                                  shell_stress_operators, von_mises)

L, B, T = 2.0, 0.2, 0.02          # strip: length [m], width [m], thickness [m]
P = 1000.0                        # tip line load [N/m], downwards


def _solve(K, f, fixed):
    u = np.zeros(f.size)
    free = ~fixed
    u[free] = sla.spsolve(K[free][:, free].tocsc(), f[free])
    return u


def _cantilever_shell(spec):
    """Strip clamped at x = −L/2 in cylindrical bending (v = θx = 0) under a
    downward line load P at x = +L/2: DOF vector and model. The clamp holds
    a hinged stiffener's own section rotation too (its DOFs after the
    nodes', :class:`flexbed.fem.shell.ShellModel`)."""
    m = assemble_shell(spec)
    x, y = m.nodes.T
    d = m.node_dofs
    fixed = np.zeros(m.K.shape[0], bool)
    fixed[d[:, np.isclose(x, -L / 2)].ravel()] = True
    fixed[d.size + np.flatnonzero(np.isclose(x[m.extra_nodes], -L / 2))] = True
    fixed[d[1]] = fixed[d[3]] = True
    tip = np.isclose(x, L / 2)
    dy = B / spec.ny
    share = np.where(np.isclose(np.abs(y[tip]), B / 2), 0.5, 1.0) * dy
    f = np.zeros(m.K.shape[0])
    f[d[2, tip]] = -P * share
    return _solve(m.K, f, fixed), m


def test_shell_strip_in_cylindrical_bending():
    """Hogging moment M = P (L/2 − x) per metre: top face σxx = 6M/t²,
    σyy = ν σxx, no membrane stress; bilinear elements are exact at their
    centres for a linear moment."""
    spec = PlateSpec(length_x=L, length_y=B, thickness=T, nx=20, ny=2, theory="mindlin")
    u, m = _cantilever_shell(spec)
    ops = shell_stress_operators(m)
    sm, sb = ops.of(u[:, None])
    M = P * (L / 2 - ops.centres[:, 0])
    exact = 6.0 * M / T ** 2
    assert np.max(np.abs(sb[0, :, 0] - exact)) <= 1e-8 * exact.max()
    assert np.max(np.abs(sb[0, :, 1] - spec.poisson * exact)) <= 1e-8 * exact.max()
    assert np.max(np.abs(sb[0, :, 2])) <= 1e-8 * exact.max()
    assert np.max(np.abs(sm)) <= 1e-8 * exact.max()
    top, bottom = face_stresses(sm, sb)[0].transpose(1, 0, 2)
    np.testing.assert_allclose(bottom, -top, atol=1e-8 * exact.max())


def test_kirchhoff_strip_in_cylindrical_bending():
    """The same strip on Bogner–Fox–Schmit elements (w cubic: exact)."""
    spec = PlateSpec(length_x=L, length_y=B, thickness=T, nx=10, ny=2)
    m = assemble_plate(spec)
    x, y = m.nodes.T
    d = m.node_dofs
    fixed = np.zeros(m.K.shape[0], bool)
    fixed[d[:, np.isclose(x, -L / 2)].ravel()] = True
    fixed[d[2]] = fixed[d[3]] = True                 # w_y = w_xy = 0: cylindrical
    tip = np.isclose(x, L / 2)
    share = np.where(np.isclose(np.abs(y[tip]), B / 2), 0.5, 1.0) * B / spec.ny
    f = np.zeros(m.K.shape[0])
    f[d[0, tip]] = -P * share
    u = _solve(m.K, f, fixed)
    ops = plate_stress_operators(m)
    _, sb = ops.of(u[:, None])
    exact = 6.0 * P * (L / 2 - ops.centres[:, 0]) / T ** 2
    assert np.max(np.abs(sb[0, :, 0] - exact)) <= 1e-6 * exact.max()
    assert np.max(np.abs(sb[0, :, 1] - spec.poisson * exact)) <= 1e-6 * exact.max()


def test_stiffened_strip_as_a_composite_beam():
    """A 100 × 20 mm flat bar under the strip: away from the clamp and the
    load (Saint-Venant), the plate's top face and the bar's centroid and
    lower fibre carry E' M (z − z_na)/EI (plate in plane strain, E' =
    E/(1 − ν²); bar E), within 1e-3 of the largest."""
    h, w = 0.1, 0.02
    section = section_of("flat", height=h, width=w)
    zs = -(T / 2 + h / 2)
    bar = Stiffener("bar", (-L / 2, 0.0), (L / 2, 0.0), section, zs)
    spec = PlateSpec(length_x=L, length_y=B, thickness=T, nx=20, ny=2, theory="mindlin",
                     stiffeners=(bar,))
    u, m = _cantilever_shell(spec)
    E, nu = spec.young, spec.poisson
    Ep = E / (1 - nu ** 2)
    EA = Ep * B * T + E * section.area
    zna = E * section.area * zs / EA
    EI = Ep * (B * T ** 3 / 12 + B * T * zna ** 2) + E * (section.Iy
                                                          + section.area * (zs - zna) ** 2)
    ops = shell_stress_operators(m)
    sm, sb = ops.of(u[:, None])
    xc = ops.centres[:, 0]
    inner = np.abs(xc) < 0.6
    curvature = P * B * (L / 2 - xc) / EI                    # hogging, 1/m
    top = Ep * curvature * (T / 2 - zna)
    scale = np.abs(top).max()
    assert np.max(np.abs((sm + sb)[0, inner, 0] - top[inner])) <= 1e-3 * scale
    st = ops.stiffeners[0]
    np.testing.assert_allclose(st.fibres, [h / 2, -h / 2])
    xs = st.centres[:, 0]
    inner = np.abs(xs) < 0.6
    k = P * B * (L / 2 - xs) / EI
    axial, gradient = st.axial @ u, st.gradient @ u
    lower = axial + st.fibres[1] * gradient
    expect_axial = E * k * (zs - zna)
    expect_lower = E * k * (zs - h / 2 - zna)
    assert np.max(np.abs(axial - expect_axial)[inner]) <= 1e-3 * np.abs(expect_axial).max()
    assert np.max(np.abs(lower - expect_lower)[inner]) <= 1e-3 * np.abs(expect_lower).max()


@pytest.mark.parametrize("sigma, vm, p", [
    ((100.0, 0.0, 0.0), 100.0, (100.0, 0.0)),                 # uniaxial
    ((0.0, 0.0, 50.0), 50.0 * np.sqrt(3.0), (50.0, -50.0)),   # pure shear
    ((80.0, 80.0, 0.0), 80.0, (80.0, 80.0)),                  # equibiaxial
    ((30.0, -10.0, 20.0), np.sqrt(900 + 300 + 100 + 1200), (10 + np.sqrt(800), 10 - np.sqrt(800))),
])
def test_plane_stress_measures(sigma, vm, p):
    s = np.array(sigma)
    assert von_mises(s) == pytest.approx(vm, rel=1e-14)
    np.testing.assert_allclose(principal(s), p, rtol=1e-14, atol=1e-12)
    # von Mises from the principal stresses
    s1, s2 = principal(s)
    assert von_mises(s) == pytest.approx(np.sqrt(s1 * s1 - s1 * s2 + s2 * s2), rel=1e-12)


def test_modal_stresses_round_trip_the_modes_file(tmp_path):
    """Schema 1.4 stores each mode's stresses, stiffeners' too; a 1.3 file
    (no group ``stress``) still reads, with no stresses."""
    import h5py

    from flexbed.fem.bed import compute_bed_modes
    from flexbed.files.modes import read_modes_file, write_modes_file

    bar = Stiffener("bar 1", (-0.2, -2.4), (-0.2, 2.4), section_of("flat", height=0.1, width=0.02),
                    -0.1)
    bed = compute_bed_modes(PlateSpec(theory="mindlin", nx=8, ny=24, stiffeners=(bar,)),
                            n_modes=3)
    path = write_modes_file(tmp_path / "m.h5", bed)
    s = read_modes_file(path).stress
    assert s.membrane.shape == (3, 192, 3)
    for name in ("centres", "membrane", "bending"):
        assert np.array_equal(getattr(s, name), getattr(bed.stress, name)), name
    (st,), (ref,) = s.stiffeners, bed.stress.stiffeners
    assert st.name == "bar 1" and np.array_equal(st.axial, ref.axial)
    assert np.array_equal(st.gradient, ref.gradient) and st.axial.shape == (3, 24)
    with h5py.File(path, "r") as f:
        vm = f["stress/von_mises"][...]
        assert f["stress/membrane"].attrs["units"] == "Pa kg^-1/2"
    faces = bed.stress.faces(np.eye(3))
    np.testing.assert_array_equal(vm, von_mises(faces))
    with h5py.File(path, "r+") as f:
        del f["stress"]
        f.attrs["schema_version"] = "1.3"
    assert read_modes_file(path).stress is None


def test_superposition_peaks_match_brute_force():
    """superpose (von Mises as |a W|, single-precision scan in blocks)
    against von Mises computed frame by frame in double precision: the
    peak, its element, face, time, the peak map, and a stiffener's fibre
    peak; 13 frames in blocks of 4."""
    from flexbed.analyses.bed_stress import superpose
    from flexbed.fem.modal_stress import ModalStress, StiffenerModalStress

    rng = np.random.default_rng(3)
    n, ne, k = 3, 7, 13
    bar = StiffenerModalStress("bar", rng.standard_normal((4, 2)), rng.standard_normal((n, 4)),
                               rng.standard_normal((n, 4)) * 10.0, np.array([0.05, -0.05]))
    s = ModalStress(centres=rng.standard_normal((ne, 2)), membrane=rng.standard_normal((n, ne, 3)),
                    bending=rng.standard_normal((n, ne, 3)), stiffeners=(bar,))
    a = rng.standard_normal((k, n))
    t = np.linspace(0.0, 1.2, k)
    got = superpose(s, a, t, chunk=4)
    vm = von_mises(s.faces(a))                                        # (k, ne, 2)
    f, e, face = np.unravel_index(np.argmax(vm), vm.shape)
    assert got.bed.value == pytest.approx(vm.max(), rel=1e-13)
    assert (got.bed.index, got.bed.where, got.bed.time) == (e, ("top", "bottom")[face], t[f])
    np.testing.assert_allclose(got.peak_map, vm.max(axis=(0, 2)), rtol=1e-6)
    np.testing.assert_allclose(got.initial, vm[0], rtol=1e-13)
    fibre = np.abs((a @ bar.axial)[..., None] + (a @ bar.gradient)[..., None] * bar.fibres)
    name, peak = got.stiffeners[0]
    assert name == "bar" and peak.value == pytest.approx(fibre.max(), rel=1e-13)
    f, j, side = np.unravel_index(np.argmax(fibre), fibre.shape)
    assert (peak.time, peak.index, peak.where) == (t[f], j, f"fibre {bar.fibres[side]:+.4g} m")

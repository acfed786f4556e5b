"""The plate model and its free-free modes against exact and converged
solutions."""

import math

import numpy as np
import pytest
import scipy.linalg as la

from flexbed.fem.bed import compute_bed_modes
from flexbed.fem.modes import ModesError, free_free_modes
from flexbed.fem.plate import assemble_plate
from flexbed.fem.spec import PlateSpec, PlateSpecError

REFERENCE = PlateSpec()


@pytest.fixture(scope="module")
def reference_modes():
    model = assemble_plate(REFERENCE)
    return model, free_free_modes(model, n_modes=8)


def test_reference_mesh_has_121_nodes(reference_modes):
    model, _ = reference_modes
    assert model.nodes.shape == (121, 2)
    assert model.K.shape == (484, 484)


def test_first_four_frequencies_within_0_2_percent_of_40x40(reference_modes):
    _, coarse = reference_modes
    fine = free_free_modes(assemble_plate(PlateSpec(nx=40, ny=40)), n_modes=4)
    rel = np.abs(coarse.frequency[:4] / fine.frequency - 1.0)
    assert np.all(rel < 2e-3), rel


def test_first_frequency_near_free_free_euler_bernoulli_beam(reference_modes):
    _, modes = reference_modes
    s = REFERENCE
    beta_l = 4.730040744862704            # first root of cos(x) cosh(x) = 1
    inertia, area = s.length_x * s.thickness ** 3 / 12, s.length_x * s.thickness
    f_beam = beta_l ** 2 / (2 * math.pi * s.length_y ** 2) * math.sqrt(
        s.young * inertia / (s.density * area))
    assert f_beam == pytest.approx(23.15, abs=0.01)
    assert modes.frequency[0] == pytest.approx(f_beam, rel=0.01)


def test_reference_mode_shapes_are_recognised(reference_modes):
    _, modes = reference_modes
    assert modes.labels[:3] == ("bending about x", "bending about x", "torsion")
    assert modes.symmetry[:3] == ("SS", "SA", "AA")


def test_rigid_modes_identified_by_projection(reference_modes):
    _, modes = reference_modes
    assert modes.rigid_omega.shape == (3,)
    assert np.all(modes.rigid_omega < 1e-3 * modes.omega[0])


def test_mass_normalised_and_rigid_free(reference_modes):
    model, modes = reference_modes
    phi = modes.vectors
    assert np.allclose(phi.T @ model.M @ phi, np.eye(phi.shape[1]), rtol=0, atol=1e-12)
    R = model.rigid_vectors()
    assert np.abs(R.T @ model.M @ phi).max() < 1e-12 * math.sqrt(REFERENCE.mass)
    k = phi.T @ model.K @ phi
    assert np.allclose(k, np.diag(modes.omega ** 2), rtol=0, atol=1e-10 * modes.omega[-1] ** 2)


def test_signs_are_deterministic(reference_modes):
    model, modes = reference_modes
    again = free_free_modes(assemble_plate(REFERENCE), n_modes=8)
    assert np.allclose(again.vectors, modes.vectors, rtol=0, atol=1e-9)
    w = modes.vectors[model.node_dofs[0]]
    for j in range(w.shape[1]):
        mag = np.abs(w[:, j])
        first = np.flatnonzero(mag >= (1 - 1e-6) * mag.max())[0]
        assert w[first, j] > 0


def test_fmax_keeps_every_mode_below_the_cut(reference_modes):
    model, modes = reference_modes
    cut = 0.5 * (modes.frequency[4] + modes.frequency[5])
    by_f = free_free_modes(model, fmax=cut)
    assert by_f.omega.size == 5
    assert np.allclose(by_f.omega, modes.omega[:5], rtol=1e-10)
    assert by_f.omega_next == pytest.approx(modes.omega[5], rel=1e-10)


def test_dense_and_sparse_paths_agree():
    spec = PlateSpec(nx=14, ny=14)            # 900 DOFs: the sparse shift-invert path
    model = assemble_plate(spec)
    sparse = free_free_modes(model, n_modes=6)
    vals = la.eigh(model.K.toarray(), model.M.toarray(), eigvals_only=True)
    assert np.allclose(sparse.omega, np.sqrt(vals[3:9]), rtol=1e-9)


@pytest.mark.parametrize("kwargs, match", [
    ({"n_modes": 0}, "at least one"),
    ({"n_modes": 482}, "only 481 elastic modes"),
    ({"fmax": 1.0}, "no elastic mode below"),
    ({}, "either"),
])
def test_impossible_requests(kwargs, match):
    model = assemble_plate(REFERENCE)
    with pytest.raises(ModesError, match=match):
        free_free_modes(model, **kwargs)


@pytest.mark.parametrize("entry, value", [
    ("poisson", 0.5), ("poisson", -1.0), ("thickness", 0.0), ("length_x", -0.8),
    ("nx", 0), ("density", float("nan")),
])
def test_plate_inputs_out_of_range(entry, value):
    with pytest.raises(PlateSpecError, match=entry):
        PlateSpec(**{entry: value})


@pytest.mark.slow
def test_whole_stage_on_64x64_keeps_the_frequencies():
    """4 096 elements (16 900 DOFs): the assembled model still reproduces
    the converged frequencies (the 40 x 40 values within the discretisation
    error). 100 x 100 took 40 s of CPU here; `flexbed bench` times the
    large meshes."""
    fine = compute_bed_modes(PlateSpec(nx=64, ny=64), n_modes=3)
    mid = compute_bed_modes(PlateSpec(nx=40, ny=40), n_modes=3)
    assert np.allclose(fine.modes.frequency, mid.modes.frequency, rtol=2e-5)

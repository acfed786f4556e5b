"""``[bed] static_correction``: residual vectors of the modes left out.

The bed's elastic deformation is driven by the mount forces alone (its own
weight has no elastic modal component: free–free modes are mass-orthogonal
to the rigid translations), so the static response of modes n … N−1 lies in
the span of the residual vectors, exactly: the corrected statics must equal
the N-mode statics to solver precision. In motion the correction leaves only
the dynamic amplification of the modes left out."""

from dataclasses import replace

import numpy as np
import pytest

from flexbed.dynamics.integrate import Settings, integrate
from flexbed.dynamics.statics import solve_statics
from flexbed.cli import main
from flexbed.stages.modes import ensure_modes
from flexbed.stages.system import compile_scene
from flexbed.analyses.points import Point, Run
from flexbed.files.scene import builtin_scene_path, load_scene
from flexbed.stages.residual_modes import change_of_modes, residual_basis

N_FILE = 20


@pytest.fixture(scope="module")
def models(tmp_path_factory):
    """Systems at their equilibria: (name → (system, y_eq)) for N_FILE modes,
    1 mode, and 1 mode + the correction drawing on N_FILE modes."""
    sf = load_scene()
    path = tmp_path_factory.mktemp("corr") / "m.h5"
    out = {}
    for name, n, corr in (("all", N_FILE, False), ("one", 1, False), ("corrected", 1, True)):
        s = replace(sf, bed=replace(sf.bed, model="flexible", modes=n, static_correction=corr,
                                    correction_modes=N_FILE, rayleigh=(0.0, 0.01)))
        data, _ = ensure_modes(s, path, log=lambda m: None)
        system = compile_scene(s, data.path)
        eq = solve_statics(system, tol=1e-10)
        assert eq.success
        out[name] = (system, eq.y)
    return out


def test_the_correction_adds_one_vector_per_loaded_direction(models):
    system, _ = models["corrected"]
    fb = dict(system.scene.flexible)["bed"]
    # 12 mount points on the bed's mid-surface: their vertical directions only
    assert fb.n_modes == 1 + 12
    assert fb.basis.shape[1] == 13 and np.allclose(fb.basis[:1, :1], 1.0)
    # mass-orthonormal, stiffness-diagonal coordinates
    assert np.allclose(fb.modal_mass, np.eye(13), atol=1e-12)
    K = fb.modal_stiffness
    assert np.abs(K - np.diag(np.diag(K))).max() < 1e-9 * np.abs(K).max()


def test_corrected_statics_equal_the_statics_with_every_mode(models):
    z = {k: models[k][0].layout.split(models[k][1])["r"][:, 2] for k in models}
    assert np.abs(z["corrected"] - z["all"]).max() < 1e-10
    assert np.abs(z["one"] - z["all"]).max() > 1e-5            # what the correction fixes


def test_in_motion_only_the_dynamic_part_is_left(models):
    st = Settings("radau", t_end=0.5, rtol=1e-9, atol=1e-12, output_dt=0.01)
    z = {}
    for k, (system, y0) in models.items():
        run = integrate(system, y0, st)
        assert run.complete
        z[k] = system.layout.split(run.y)["r"][:, :, 2]
    err_one = np.abs(z["one"] - z["all"]).max()
    err_corrected = np.abs(z["corrected"] - z["all"]).max()
    assert err_one > 1e-5 and err_corrected < 1e-4 * err_one, (err_one, err_corrected)


def test_change_of_modes_is_the_identity_for_the_identity():
    rng = np.random.default_rng(3)
    n = 4
    arrays = dict(I3=rng.standard_normal((3, n)), I4=rng.standard_normal((3, n)),
                  I5=rng.standard_normal((n, 3, n)), I6=np.eye(n),
                  I8=rng.standard_normal((n, 3, 3)), I9=rng.standard_normal((n, n, 3, 3)),
                  K=np.diag([1.0, 4.0, 9.0, 16.0]), shapes=rng.standard_normal((n, 5, 3)))
    out = change_of_modes(np.eye(n), **arrays)
    for key, value in arrays.items():
        assert np.array_equal(out[key], value), key
    # the residual vectors of modes 2-3 for a load seen by mode 2 only: mode 2 itself
    T, w = residual_basis(np.eye(n), arrays["K"], np.array([[0.0], [1.0], [0.0], [0.0]]), 1)
    assert T.shape == (4, 2) and np.allclose(np.abs(T[:, 1]), [0, 1, 0, 0]) and np.isclose(w[0], 2)


def test_post_rebuilds_the_corrected_bed(tmp_path):
    text = builtin_scene_path().read_text().replace('model = "rigid"', 'model = "flexible"')
    text = text.replace("[bed]\n", "[bed]\nstatic_correction = true\ncorrection_modes = 12\n", 1)
    scene = tmp_path / "corr.toml"
    scene.write_text(text)
    modes, results = tmp_path / "m.h5", tmp_path / "r.h5"
    assert main(["modes", str(scene), "-o", str(modes)]) == 0
    assert main(["simulate", str(scene), "--modes-file", str(modes), "-o", str(results),
                 "--t-end", "0.2", "--no-progress"]) == 0
    run = Run(results)
    assert run.a.shape[1] > 2                          # 2 modes + residual vectors
    Pi = run.absolute(Point("i", "base", np.array([-0.4, -2.4, 5.0])))
    Pj = run.absolute(Point("j", "bed", np.array([-0.4, -2.4, 0.0])))
    m = run.mount_names.index("M1")
    dx = Pj.position - Pi.position - np.array([0.0, 0.0, 0.1])
    assert np.abs(dx - run.mounts["deflection"][:, m]).max() < 1e-12


@pytest.mark.parametrize("line, words", [
    ("static_correction = 1", "static_correction = 1 must be true or false"),
    ("correction_modes = 1", "correction_modes = 1 must be an integer >= 2"),
    ("static_correction = true\ncorrection_modes = 2", "static_correction needs modes beyond"),
])
def test_bad_correction_input_is_one_line(tmp_path, capsys, line, words):
    text = builtin_scene_path().read_text().replace('model = "rigid"', 'model = "flexible"')
    scene = tmp_path / "bad.toml"
    scene.write_text(text.replace("[bed]\n", f"[bed]\n{line}\n", 1))
    modes = tmp_path / "m.h5"
    code = main(["modes", str(scene), "-o", str(modes)])          # the scene file is read
    if code == 0:                                                  # the hand-off refuses
        capsys.readouterr()
        code = main(["static", str(scene), "--modes-file", str(modes), "-o",
                     str(tmp_path / "eq.h5")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and words in err[0], err
    assert not (tmp_path / "eq.h5").exists()

"""Elastomer mounts in time runs (issue 25, part 4): the generalised Maxwell
series as internal states of the one right-hand side
(:mod:`flexbed.dynamics.maxwell_terms`).

The body of :mod:`test_modal` on four elastomer mounts moves vertically
alone under a vertical base acceleration a = A sin Ωt; its motion
relative to the base, u, has in steady state the complex amplitude
U = −m A/(κ(Ω) − mΩ²), κ = 4 K(Ω) the mounts' vertical complex stiffness.
The time run's κ is the fitted series'; the frequency analyses' the table's.
"""

import dataclasses
import math
import re

import numpy as np
import pytest
from scipy.linalg import expm

from scene_text import KX, KY, KZ, M1, elastomer_stage, sine_drive

AMP = 1.0                                   # base acceleration [m/s²]
F_TAB = [2.0, 5.0, 10.0, 20.0, 50.0]
KZ_TAB = [KZ * s for s in (1.0, 1.1, 1.25, 1.4, 1.6)]
ETA_TAB = [0.05, 0.08, 0.12, 0.15, 0.2]
TABLE = (f"elastomer = {{frequency = {F_TAB}, stiffness = "
         f"[{', '.join(f'[{KX}, {KY}, {k}]' for k in KZ_TAB)}], "
         f"loss_factor = [{', '.join(f'[0.1, 0.1, {e}]' for e in ETA_TAB)}]}}")


def _drive(freq: float) -> str:
    return sine_drive(AMP, freq)


def _system(tmp_path, text, name):
    import warnings

    from flexbed.errors import FlexbedWarning
    from flexbed.files.elastomer import time_run_scene
    from flexbed.files.scene import load_scene
    from flexbed.stages.system import compile_scene
    path = tmp_path / name
    path.write_text(text)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", FlexbedWarning)
        sf = load_scene(path)
    return sf, compile_scene(time_run_scene(sf))


def _steady_amplitude(tmp_path, freq, method="dop853"):
    """(U from the time run [m, complex], the SceneFile): the relative
    vertical motion's sine and cosine parts over the last 2 s of 8 s (the
    transient is below 1e-9 of it there)."""
    from flexbed.dynamics.integrate import Settings, integrate
    from flexbed.dynamics.statics import solve_statics
    sf, system = _system(tmp_path, elastomer_stage(TABLE) + _drive(freq), f"s{freq:g}.toml")
    eq = solve_statics(system, tol=1e-12)
    assert eq.success
    run = integrate(system, system.initial_state(eq.y),
                    Settings(method, t_end=8.0, rtol=1e-11, atol=1e-15, output_dt=1e-3))
    assert run.complete, run.message
    lay = system.layout
    z = run.y[:, lay.q_rigid.start + 2] - eq.y[lay.q_rigid.start + 2]
    W = 2 * math.pi * freq
    t = run.t
    u = z - (AMP / W * t - AMP / W ** 2 * np.sin(W * t))     # minus the base's exact motion
    tail = t >= 6.0
    B = np.column_stack([np.sin(W * t[tail]), np.cos(W * t[tail])])
    (s, c), *_ = np.linalg.lstsq(B, u[tail], rcond=None)
    return s + 1j * c, sf, system        # u = Im(U e^{iΩt}) = Re U sin + Im U cos


@pytest.mark.parametrize("freq", [4.0, 9.0, 25.0])
def test_steady_state_is_the_fitted_series_frf_and_the_table_within_its_error(tmp_path,
                                                                               freq):
    """(1) amplitude and phase equal the FRF of the fit's complex stiffness to
    1e-6; (2) against the table's exact complex stiffness within the fit's
    stated error ε carried through the response, |ΔU/U| ≤ ε |κ|/|κ_fit − mΩ²|."""
    from flexbed.dynamics.frequency.maxwell import fit_maxwell
    U, sf, _ = _steady_amplitude(tmp_path, freq)
    W = 2 * math.pi * freq
    table = sf.elastomers[0][1]
    fit = fit_maxwell(table)
    kap_fit = 4 * fit.complex([freq])[0, 2]
    U_fit = -M1 * AMP / (kap_fit - M1 * W ** 2)
    assert abs(U / U_fit - 1) < 1e-6, (U, U_fit)              # amplitude and phase
    kap_tab = 4 * table.complex([freq])[0, 2]
    U_tab = -M1 * AMP / (kap_tab - M1 * W ** 2)
    bound = fit.error[2] * abs(kap_tab) / abs(kap_fit - M1 * W ** 2)
    print(f"f = {freq} Hz: |U/U_fit - 1| = {abs(U / U_fit - 1):.2e}, |U/U_table - 1| = "
          f"{abs(U / U_tab - 1):.2e} <= {bound:.2e} (fit error {fit.error[2]:.2e})")
    assert abs(U / U_tab - 1) <= bound * (1 + 1e-6), (abs(U / U_tab - 1), bound)


def test_free_decay_of_one_maxwell_term_is_the_closed_form(tmp_path):
    """(3) The body displaced 1 mm up and let go (the term relaxed at the
    start, no gravity): u, u̇ and the term's state z follow
    x(t) = exp(A t) x(0) of m ü = −4k u − 4k₁ (u − z), ż = (u − z)/τ,
    to 1e-9 of the displacement."""
    from flexbed.dynamics.integrate import Settings, integrate
    from flexbed.dynamics.maxwell_terms import MaxwellSeries, relax_states
    from flexbed.dynamics.system import System
    text = elastomer_stage("").replace("gravity = [0.0, 0.0, -9.81]", "gravity = [0.0, 0.0, 0.0]")
    sf, _ = _system(tmp_path, text, "decay.toml")
    k1, tau = 3.0e4, 0.02
    terms = tuple(MaxwellSeries(m.name, [tau], [[0.0], [0.0], [k1]]) for m in sf.scene.mounts)
    system = System(dataclasses.replace(sf.scene, maxwell=terms))
    assert system.layout.n_internal == 4
    lay = system.layout
    y0 = system.initial_state()
    y0[lay.q_rigid.start + 2] += 1e-3
    y0 = relax_states(system, y0)
    assert np.allclose(y0[lay.internal], 1e-3, rtol=0, atol=1e-15)   # relaxed: z = d
    run = integrate(system, y0, Settings("radau", t_end=0.5, rtol=1e-11, atol=1e-15,
                                         output_dt=1e-3))
    assert run.complete, run.message
    A = np.array([[0.0, 1.0, 0.0],
                  [-4 * (KZ + k1) / M1, 0.0, 4 * k1 / M1],
                  [1.0 / tau, 0.0, -1.0 / tau]])
    x = np.array([expm(A * t) @ [1e-3, 0.0, 1e-3] for t in run.t])
    q = lay.q_rigid.start
    np.testing.assert_allclose(run.y[:, q + 2] - 0.5, x[:, 0], rtol=0, atol=1e-12)
    for j in range(4):
        np.testing.assert_allclose(run.y[:, lay.internal.start + j], x[:, 2], rtol=0,
                                   atol=1e-12)
    # the work of the mounts is minus the energy stored plus the dashpots' dissipation,
    # W(t) = E(0) − (2k u² + 2k₁ (u − z)²) − 4 k₁ τ ∫ ż² dt, the integral in closed form
    # (ż = Σ a_i e^{λ_i t} by the eigenvalues of A)
    lam, V = np.linalg.eig(A)
    a = np.array([1.0, 0.0, -1.0]) / tau @ V * np.linalg.solve(V, [1e-3, 0.0, 1e-3])
    s = lam[:, None] + lam[None, :]
    t = run.t[:, None, None]
    diss = 4 * k1 * tau * np.sum(a[:, None] * a[None, :] * np.expm1(s * t) / s, axis=(1, 2)).real
    stored = 2 * KZ * x[:, 0] ** 2 + 2 * k1 * (x[:, 0] - x[:, 2]) ** 2
    np.testing.assert_allclose(run.y[:, lay.work.start], stored[0] - stored - diss, rtol=0,
                               atol=1e-9 * stored[0])


def test_statics_see_the_static_stiffness_and_the_terms_at_rest(tmp_path):
    """The equilibrium of a time run's system is the one without Maxwell
    terms (k∞ = the law's k), its states at rest z = d, and the rates of
    that state zero."""
    from flexbed.dynamics.statics import solve_statics
    from flexbed.stages.system import compile_scene
    sf, system = _system(tmp_path, elastomer_stage(TABLE), "rest.toml")
    assert system.layout.n_internal > 0
    eq = solve_statics(system, tol=1e-12)
    plain = solve_statics(compile_scene(sf), tol=1e-12)
    lay = system.layout
    np.testing.assert_array_equal(eq.y[:lay.internal.start], plain.y[:lay.internal.start])
    dy = system.rhs(0.0, eq.y)
    assert np.max(np.abs(dy[lay.internal])) < 1e-12
    rows = system.data.mx_ints[:, 0]                 # 3 mount + direction of each state
    at_rest = np.where(rows % 3 == 2, -M1 * 9.81 / (4 * KZ), 0.0)
    np.testing.assert_allclose(eq.y[lay.internal], at_rest, rtol=1e-12, atol=1e-15)


def test_time_runs_take_elastomer_mounts_and_refuse_the_linear_model(tmp_path, capsys):
    """``flexbed simulate`` runs a scene with elastomer mounts (the stiffness
    check sees the terms' fastest rate, 1/τ of the series' shortest τ), its mount forces
    include the terms' (f3 = k Δx + Σ k_i (Δx − z_i), 0 at rest); ``model =
    "linear"`` is one line, exit 2; ``auto`` runs the nonlinear model; an
    equilibrium file without the states (``flexbed static``) starts it alike."""
    import flexbed
    from flexbed.cli import main
    from flexbed.files.results import read_results
    path = tmp_path / "rubber.toml"
    path.write_text(elastomer_stage(TABLE) + _drive(9.0) + "\n[solver]\nt_end = 0.2\n")
    out = tmp_path / "r.h5"
    assert main(["simulate", str(path), "-o", str(out), "--no-progress"]) == 0
    # the stiffness check sees the terms' rates 1/τ_i (the bodies' own are below 100 1/s)
    rate = float(re.search(r"the fastest rate (\S+) 1/s", capsys.readouterr().out).group(1))
    fastest = 2 * math.pi * 50.0 * 10 ** 0.5        # 1/τ_min: the band's top + ½ decade
    assert 0.9 * fastest < rate < 1.1 * fastest, (rate, fastest)
    c = read_results(out)
    f = np.asarray(c.get("mounts/force"))
    dx = np.asarray(c.get("mounts/deflection"))
    assert f.shape[1:] == (4, 3)
    spring = KZ * dx[:, 0, 2]
    assert abs(f[0, 0, 2] - spring[0]) < 1e-9 * abs(spring[0])        # at rest: k Δx alone
    assert np.max(np.abs(f[:, 0, 2] - spring)) > 1e-3 * np.max(np.abs(spring - spring[0]))
    assert main(["simulate", str(path), "--model", "linear", "-o", str(tmp_path / "l.h5")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 2 and "model = 'linear' does not take an elastomer mount's Maxwell" \
        in err[-1] and "'M1'" in err[-1], err
    assert not (tmp_path / "l.h5").exists()
    run = flexbed.simulate(flexbed.load_scene(path), model="auto")
    assert run.complete
    # an equilibrium file of `flexbed static` (no Maxwell states) starts the run alike
    assert main(["static", str(path), "-o", str(tmp_path / "eq.h5")]) == 0
    assert main(["simulate", str(path), "--equilibrium", str(tmp_path / "eq.h5"), "-o",
                 str(tmp_path / "e.h5"), "--no-progress"]) == 0
    np.testing.assert_array_equal(np.asarray(read_results(tmp_path / "e.h5").get("mounts/force")),
                                  f)

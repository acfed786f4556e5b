"""Bump stops (issue 23, part 2): an oscillator bottoming on its stop
against the exact piecewise-linear solution, arcs joined at the contact
instants, to 1e-9 relative; the contact located by every integrator.

A 50 kg body on four identical mounts in the plane of its centre of mass,
no gravity, launched downwards at 1 m/s: x = Δx3 (the same on every
mount, no rotation) obeys

    free:     m ẍ = −4 k x,                           while x > −g,
    contact:  m ẍ = −4 k x − 4 k_c (x + g) − 4 c_c ẋ, while x < −g,

the contact stiffness 100 times the mount's. Each arc is a (damped)
harmonic motion from the state where the last one ended; the free arc
reaches −g where its cosine says, the contact arc leaves where its
damped cosine crosses −g again (found to round-off by bisection).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

import flexbed

from scene_text import base_and_body, four_mounts

M, K, KC, CC, GAP, V0 = 50.0, 1.25e5, 1.25e7, 2.0e3, 0.006, -1.0
T_END = 0.12

LAW = (f'law = "linear"\nk = [5.0e4, 7.5e4, {K}]\n'
       f'bump_stop = {{direction = 3, gap_compression = {GAP}, stiffness = {KC}, '
       f'damping = {CC}}}')


def scene_text(integrator: str, extra: str = "") -> str:
    body = base_and_body("bump", gravity=0.0, body_extra=f"velocity = [0.0, 0.0, {V0}]")
    return body + four_mounts(LAW) + f"""
[solver]
start = "initial"
t_end = {T_END}
output_dt = 2.0e-4
integrator = "{integrator}"
{extra}
"""


def _arc(x0: float, v0: float, contact: bool):
    """x(s), v(s) of one arc from (x0, v0) at s = 0 (s: time since its start)."""
    if not contact:
        w = math.sqrt(4 * K / M)
        return (lambda s: x0 * np.cos(w * s) + v0 / w * np.sin(w * s),
                lambda s: -x0 * w * np.sin(w * s) + v0 * np.cos(w * s))
    w2 = 4 * (K + KC) / M
    xe = -KC * GAP / (K + KC)                       # the contact arc's rest point
    zeta = 4 * CC / (2 * M * math.sqrt(w2))
    w, wd = math.sqrt(w2), math.sqrt(w2) * math.sqrt(1 - zeta ** 2)
    a, b = x0 - xe, (v0 + zeta * w * (x0 - xe)) / wd
    def x(s):
        return xe + np.exp(-zeta * w * s) * (a * np.cos(wd * s) + b * np.sin(wd * s))
    def v(s):
        e = np.exp(-zeta * w * s)
        return e * ((-zeta * w * a + wd * b) * np.cos(wd * s)
                    + (-zeta * w * b - wd * a) * np.sin(wd * s))
    return x, v


def _crossing(f, lo: float, hi: float) -> float:
    """The root of f (sign change) in [lo, hi], to round-off."""
    flo = f(lo)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if mid in (lo, hi):
            break
        if (f(mid) > 0) == (flo > 0):
            lo, flo = mid, f(mid)
        else:
            hi = mid
    return hi


def exact(t: np.ndarray, rates: bool = False):
    """x(t) [m] at the times t (and ẋ(t) [m/s] with ``rates``), and the
    contact instants [s]."""
    out = np.empty_like(t)
    out_v = np.empty_like(t)
    t0, x0, v0, contact = 0.0, 0.0, V0, False
    instants = []
    while t0 < t[-1]:
        x, v = _arc(x0, v0, contact)
        # the arc's end: the first crossing of −g after a scan fine enough
        s = np.linspace(0.0, t[-1] - t0 + 1e-3, 200_001)[1:]
        g = x(s) + GAP
        bad = np.flatnonzero(g > 0) if contact else np.flatnonzero(g < 0)
        end = _crossing(lambda q, x=x: x(q) + GAP, s[bad[0] - 1], s[bad[0]]) if bad.size \
            else np.inf
        inside = (t >= t0) & (t < t0 + end)
        out[inside] = x(t[inside] - t0)
        out_v[inside] = v(t[inside] - t0)
        if not np.isfinite(end):
            break
        instants.append(t0 + end)
        x0, v0 = -GAP, float(v(end))
        t0 += end
        contact = not contact
    if rates:
        return out, out_v, np.array(instants)
    return out, np.array(instants)


@pytest.fixture(scope="module")
def reference():
    t = np.arange(0.0, T_END + 1e-9, 2.0e-4)
    return exact(t)


def _run(tmp_path, integrator: str, extra: str):
    path = tmp_path / "bump.toml"
    path.write_text(scene_text(integrator, extra))
    return flexbed.simulate(flexbed.load_scene(path))


def test_the_exact_solution_bottoms_several_times(reference):
    x, instants = reference
    assert instants.size >= 6                    # three contacts at least, each in and out
    assert x.min() < -GAP - 1e-4                 # into the stop by more than 0.1 mm


@pytest.mark.parametrize("integrator, extra, tol", [
    ("dop853", "rtol = 1e-13\natol = 1e-16", 1e-9),
    ("radau", "rtol = 1e-12\natol = 1e-16", 1e-9),
])
def test_bottoming_follows_the_piecewise_exact_solution(tmp_path, reference, integrator, extra,
                                                        tol):
    x_exact, instants = reference
    run = _run(tmp_path, integrator, extra)
    assert run.complete, run.message
    dx = run.mount_deflection[:, :, 2]
    assert np.ptp(dx, axis=1).max() < 1e-12      # the four mounts alike
    scale = np.abs(x_exact).max()
    err = np.abs(dx[:, 0] - x_exact).max() / scale
    assert err < tol, err
    events = np.asarray(run["contacts/time"]).reshape(-1, 4)   # four mounts at each instant
    assert events.shape[0] == instants.size
    np.testing.assert_allclose(events, np.repeat(instants[:, None], 4, axis=1), rtol=0,
                               atol=1e-10)
    begins = np.asarray(run["contacts/begins"]).reshape(-1, 4)
    assert np.all(begins[::2]) and not np.any(begins[1::2])   # in, out, in, out, …
    assert np.all(np.asarray(run["contacts/side"]) == -1)       # the compression stop
    print(f"{integrator}: max relative error {err:.2e}, contact instants within "
          f"{np.abs(events - instants[:, None]).max():.1e} s")


@pytest.mark.parametrize("integrator, extra, tol, tol_t", [
    ("rk4", "dt = 2.0e-5", 1e-8, 1e-10),
    ("adams", "rtol = 1e-10\natol = 1e-14", 1e-8, 1e-10),
    ("bdf", "rtol = 1e-9\natol = 1e-13", 2e-6, 2e-8),
])
def test_every_integrator_locates_the_contacts(tmp_path, reference, integrator, extra, tol,
                                               tol_t):
    """rk4 at a fixed step and SciPy's LSODA and BDF (their dense output)
    switch the contacts at the same instants; their errors are their
    orders' at these settings."""
    x_exact, instants = reference
    run = _run(tmp_path, integrator, extra)
    assert run.complete, run.message
    err = np.abs(run.mount_deflection[:, 0, 2] - x_exact).max() / np.abs(x_exact).max()
    events = np.asarray(run["contacts/time"]).reshape(-1, 4)
    print(f"{integrator}: max relative error {err:.2e}, contact instants within "
          f"{np.abs(events - instants[:, None]).max():.1e} s, {run.solver['steps']} steps")
    assert err < tol, err
    np.testing.assert_allclose(events, np.repeat(instants[:, None], 4, axis=1), rtol=0,
                               atol=tol_t)


def test_the_verdict_reports_the_bottoming(tmp_path):
    """Three contacts per mount, the first at the exact instant, the peak
    contact force k_c (x + g) + c_c ẋ within the sampling's reach of the
    exact one; the stroke used against the exact deepest compression."""
    t = np.linspace(0.0, T_END, 1_200_001)
    x, v, instants = exact(t, rates=True)
    inside = x < -GAP
    peak = np.abs(KC * (x + GAP) + CC * v)[inside].max()
    text = scene_text("dop853", "rtol = 1e-12\natol = 1e-15").replace(
        "bump_stop =", "stroke_compression = [0.01, 0.01, 0.007]\nbump_stop =")
    path = tmp_path / "bump.toml"
    path.write_text(text)
    q = flexbed.qualify(flexbed.load_scene(path))
    for m in q.verdict.mounts:
        assert m.contacts == 3 and m.first_contact == pytest.approx(instants[0], abs=1e-12)
        assert m.peak_contact_force == pytest.approx(peak, rel=2e-3)
        assert m.stroke_used[2] == pytest.approx(-x.min() / 0.007, rel=1e-5)   # sampled
    assert q.passed                             # bottoming is reported, not failed on
    assert "3× from t = 0.0064 s" in q.markdown()

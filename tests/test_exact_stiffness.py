"""Issue 25 part 5: the linearisation's stiffness and damping exact at rest
(:mod:`flexbed.dynamics.tangent`).

1. Kq, Kv and the mount outputs' derivatives equal Richardson-extrapolated
   central differences of the one right-hand side (steps h, h/2, h/4: the
   h² and h⁴ terms gone, the round-off of a step of 1e-4 left) to 1e-11
   of the matrix's largest entry, on the reference scene (rigid bed, and
   flexible with 6 modes), and on a bed with equipment on inclined
   polynomial and spline mounts.
2. The FRF at the resonances of modes with ζ ≈ 1e-5 of a box on four
   inclined, preloaded linear mounts (two with their axes in the box, which
   turn with it) equals that of an independent linear model written here
   (its own equilibrium by Newton, K and C by complex steps of its own
   generalized forces) to 1e-9 of each output's peak; central differences
   miss by far more there.
"""

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from built_scenes import bed_and_equipment

from flexbed.dynamics.block_linearisation import linearised
from flexbed.dynamics.body_loads import BodyLoad
from flexbed.dynamics.frequency.frf import Input, Outputs, responses
from flexbed.dynamics.frequency.mounted import mounted_system
from flexbed.dynamics.jacobian import mount_graph
from flexbed.dynamics.laws import BumpStop, CurveLaw, LinearLaw, PolynomialLaw
from flexbed.dynamics.scene import Base, Body, Mount, Scene
from flexbed.dynamics.statics import solve_statics
from flexbed.dynamics.system import System
from flexbed.dynamics.tangent import tangent, uncovered
from flexbed.dynamics.time_functions import Curve

FIELDS = ("w_dx", "w_dxd", "w_f", "w_F")


def _richardson(system, y, hq=4e-4, hv=4e-2):
    """Kq, Kv and the outputs by central differences at h, h/2, h/4 (hq in
    the positions, hv in the rates: the forces are polynomials of low
    degree in the rates at rest, and a larger step keeps their round-off
    against the preloads small), extrapolated twice (dense arrays)."""
    n = mount_graph(system, True).n
    lins = [linearised(system, y, np.full(n, hq / s), np.full(n, hv / s), capture=FIELDS)
            for s in (1, 2, 4)]

    def extrapolate(get):
        a, b, c = (get(lin).toarray() for lin in lins)
        r1, r2 = (4 * b - a) / 3, (4 * c - b) / 3
        return (16 * r2 - r1) / 15

    out = {"Kq": extrapolate(lambda L: L.Kq), "Kv": extrapolate(lambda L: L.Kv)}
    for f in FIELDS:
        out[f"q {f}"] = extrapolate(lambda L, f=f: L.outputs_q[f])
        out[f"v {f}"] = extrapolate(lambda L, f=f: L.outputs_v[f])
    return out


def _check_against_differences(system, y, tol=1e-11, hq=4e-4):
    assert uncovered(system, y) == ""
    tg = tangent(system, y, capture=FIELDS)
    assert tg is not None and tg.evaluations == 1
    ref = _richardson(system, y, hq=hq)
    got = {"Kq": tg.Kq, "Kv": tg.Kv}
    for f in FIELDS:
        got[f"q {f}"], got[f"v {f}"] = tg.outputs_q[f], tg.outputs_v[f]
    worst = {}
    for key, a in got.items():
        a = a.toarray()
        scale = np.abs(ref[key]).max()
        err = np.abs(a - ref[key]).max()
        worst[key] = err / scale if scale else err
        assert err <= tol * scale, (key, err / scale)
    print({k: f"{v:.1e}" for k, v in worst.items()})
    # the dense form is the sparse one
    dense = tangent(system, y, capture=FIELDS, dense=True)
    assert np.array_equal(dense.Kq, tg.Kq.toarray()) and np.array_equal(dense.Kv, tg.Kv.toarray())
    return tg


def test_reference_scene_rigid_bed(reference_system, reference_equilibrium):
    y = np.array(reference_equilibrium)
    tg = _check_against_differences(reference_system, y)
    assert tg.Kq.shape == (18, 18)
    # the mounted system's dense path and its block-sparse one (large scenes) agree
    dense = mounted_system(reference_system, y)
    sparse = mounted_system(reference_system, y, sparse=True)
    assert dense.evaluations == sparse.evaluations == 1
    for name in ("M", "K", "C", "D", "Dv", "Fq", "Fv", "Bq", "Bv", "k_tangent", "c_tangent"):
        a, b = getattr(dense, name), getattr(sparse, name)
        assert np.abs(a - b).max() <= 1e-15 * np.abs(a).max(), name


@pytest.mark.slow
def test_reference_scene_flexible_bed_six_modes(reference_scene, tmp_path):
    from flexbed.files.modes import read_modes_file
    from flexbed.stages.modes import ensure_modes
    from flexbed.stages.system import compile_scene

    sf = replace(reference_scene, bed=replace(reference_scene.bed, model="flexible", modes=6))
    d, _ = ensure_modes(sf, Path(tmp_path) / "m6.h5", n_modes=6, log=lambda m: None)
    system = compile_scene(sf, modes=read_modes_file(d.path))
    eq = solve_statics(system, tol=sf.solver.static_tol, sag=True)
    assert eq.success, eq.message
    tg = _check_against_differences(system, eq.y)
    assert tg.Kq.shape == (24, 24)
    # the modal block holds the bed's own stiffness (less its weight's share, nil here)
    fc = system.flex_compiled[0]
    blk = mount_graph(system).blocks[fc.slot][6:]
    assert np.all(np.diag(tg.Kq.toarray()[np.ix_(blk, blk)]) <= -np.diag(fc.eom.K)[:6] * 0.999)
    # loads on the flexible bed, at points that move with its modes
    bed = sf.scene.bodies[1].name
    loads = (BodyLoad(bed, (0.3, -1.2, 0.0), 2, _constant(-4e3)),
             BodyLoad(bed, (-0.2, 1.5, 0.0), 0, _constant(2.5e3), "body"),
             BodyLoad(bed, (0.1, 0.8, 0.0), 1, _constant(1.5e3)))
    sf = replace(sf, scene=replace(sf.scene, loads=loads))
    system = compile_scene(sf, modes=read_modes_file(d.path))
    eq = solve_statics(system, tol=sf.solver.static_tol, sag=True)
    assert eq.success, eq.message
    _check_against_differences(system, eq.y)


def _tilted(a, b):
    """Axes (rows) turned by a about x, then b about y [rad]."""
    ca, sa, cb, sb = np.cos(a), np.sin(a), np.cos(b), np.sin(b)
    Rx = np.array([[1, 0, 0], [0, ca, -sa], [0, sa, ca]])
    Ry = np.array([[cb, 0, sb], [0, 1, 0], [-sb, 0, cb]])
    return (Ry @ Rx).T


def _constant(value):
    return Curve(np.arange(4.0), np.full(4, value))


#: loads on bodies at t = 0: forces fixed in space and turning with the body
#: (whose moments turn with it), moments of both kinds
LOADS = (BodyLoad("eq", (0.2, -0.1, 0.15), 0, _constant(300.0)),
         BodyLoad("eq", (-0.1, 0.2, 0.1), 2, _constant(-500.0), "body"),
         BodyLoad("eq", (0.0, 0.0, 0.0), 1, _constant(80.0), "inertial", "moment"),
         BodyLoad("bed", (1.0, -2.0, 0.1), 1, _constant(900.0), "body"),
         BodyLoad("bed", (0.0, 0.0, 0.0), 0, _constant(-250.0), "body", "moment"))


@pytest.mark.parametrize("law", ["polynomial", "spline", "polynomial, loads on bodies"])
def test_inclined_polynomial_and_spline_mounts(law):
    if law.startswith("polynomial"):
        laws = (PolynomialLaw((0.0, 8e4, 3e6, 2e8), (0.0, 250.0, 0.0, 40.0)),
                PolynomialLaw((0.0, 9e4, -1e6, 5e8), (0.0, 300.0)),
                PolynomialLaw((0.0, 1.2e5, 4e6, 1e9), (0.0, 200.0, 10.0)))
    else:
        x = np.linspace(-0.03, 0.03, 9)
        v = np.linspace(-1.0, 1.0, 7)
        laws = tuple(CurveLaw((x, k * x + k3 * x ** 3), (v, c * v + c3 * v ** 3))
                     for k, k3, c, c3 in ((8e4, 2e8, 250.0, 30.0), (9e4, 5e8, 300.0, 0.0),
                                          (1.2e5, 1e9, 200.0, 15.0)))
    scene = bed_and_equipment(laws, axes=_tilted(0.3, -0.2), base=Base("fixed"),
                              bed_axes=_tilted(-0.1, 0.15))
    if "loads" in law:
        scene = replace(scene, loads=LOADS)
    system = System(scene)
    eq = solve_statics(system, tol=1e-11)
    assert eq.success, eq.message
    tg = _check_against_differences(system, eq.y)
    # the laws are nonlinear at the preload: the slopes are not the linear terms
    dx = tg.outputs_q["w_dx"].toarray()
    df = tg.outputs_q["w_f"].toarray()
    eq_rows = np.arange(12, 24)
    slope = (df[eq_rows] * dx[eq_rows]).sum(axis=1) / (dx[eq_rows] ** 2).sum(axis=1)
    assert np.all(np.abs(slope - np.tile([8e4, 9e4, 1.2e5], 4)) > 1.0)


def test_bump_stops_in_contact_at_the_equilibrium():
    """The equipment sits on its compression stops (gap 0.2 mm, 2 × the
    mount's stiffness): the contact's stiffness and damping are in K and C."""
    stop = BumpStop(2e5, gap_compression=2e-4, damping=50.0)
    scene = bed_and_equipment((LinearLaw(1e5, 300.0),) * 3, axes=_tilted(0.2, 0.1),
                              base=Base("fixed"))
    mounts = tuple(replace(m, stops=(None, None, stop)) if m.body_j == "eq" else m
                   for m in scene.mounts)
    system = System(replace(scene, mounts=mounts))
    eq = solve_statics(system, tol=1e-11)
    assert eq.success, eq.message
    tg = _check_against_differences(system, eq.y, hq=2e-4)
    rows = 3 * np.arange(4, 8) + 2                                  # the stops' directions
    dx = tg.outputs_q["w_dx"].toarray()[rows]
    assert np.all(system.observe(0.0, eq.y).dx[4:, 2] < -2e-4 - 3e-4)   # in contact
    slope = (tg.outputs_q["w_f"].toarray()[rows] * dx).sum(axis=1) / (dx * dx).sum(axis=1)
    assert slope == pytest.approx(3e5, rel=1e-12)
    dv = tg.outputs_v["w_dxd"].toarray()[rows]
    slope = (tg.outputs_v["w_f"].toarray()[rows] * dv).sum(axis=1) / (dv * dv).sum(axis=1)
    assert slope == pytest.approx(350.0, rel=1e-12)


# ------------------------------------------- the FRF of nearly undamped modes

MASS, J = 120.0, np.array([9.0, 14.0, 11.0])           # kg, kg m²
R0 = np.array([0.1, -0.05, 0.6])                        # m
G = np.array([0.0, 0.0, -9.81])                         # m/s²
BETA = 2e-7                                             # s: c = β k, ζ = βω/2 ≈ 1e-5
#: (body i, point on body i, point on body j [m], axes' tilt [rad], k per direction [N/m])
MOUNTS = [("base", (-0.3, -0.25, 0.12), (-0.4, -0.3, -0.5), (0.35, 0.1), (2.0e5, 1.5e5, 3.0e5)),
          ("base", (0.35, -0.3, 0.1), (0.25, -0.25, -0.5), (-0.3, 0.2), (1.8e5, 2.2e5, 2.6e5)),
          ("box", (0.3, 0.3, -0.5), (0.42, 0.27, 0.08), (0.25, -0.35), (2.4e5, 1.6e5, 3.2e5)),
          ("box", (-0.35, 0.25, -0.5), (-0.42, 0.22, 0.11), (-0.2, -0.25), (1.7e5, 2.1e5, 2.9e5))]


def _box_scene():
    bodies = (Body("base", 1e4, (1e3, 1e3, 1e3), (0.0, 0.0, 0.0)),
              Body("box", MASS, tuple(J), tuple(R0)))
    mounts = []
    for n, (bi, pi, pj, tilt, ks) in enumerate(MOUNTS):
        bj = "box" if bi == "base" else "base"
        mounts.append(Mount(f"m{n}", bi, bj, pi, pj, _tilted(*tilt),
                            tuple(LinearLaw(k, BETA * k) for k in ks)))
    return Scene(bodies, Base("fixed"), tuple(mounts), tuple(G), "box")


def _rot(th):
    """I + θ~ + θ~²/2 (complex-safe; its first derivative at 0 is θ~)."""
    S = np.zeros((3, 3), dtype=th.dtype)
    S[0, 1], S[0, 2], S[1, 2] = -th[2], th[1], -th[0]
    S[1, 0], S[2, 0], S[2, 1] = th[2], -th[1], th[0]
    return np.eye(3) + S + 0.5 * S @ S


def _rodrigues(th):
    a = np.linalg.norm(th)
    if a < 1e-300:
        return np.eye(3)
    k = th / a
    S = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(a) * S + (1 - np.cos(a)) * S @ S


def _forces(A0, r0, dq, dv):
    """The box's generalized force (inertial force, body-frame moment) at
    the pose (A0 R(θ), r0 + δr) and rates (ṙ, ω̄); complex-safe."""
    A = A0 @ _rot(dq[3:])
    r = r0 + dq[:3]
    rd, w = dv[:3], dv[3:]
    Q = np.zeros(6, dtype=complex)
    Q[:3] = MASS * G
    for bi, pi, pj, tilt, ks in MOUNTS:
        U = _tilted(*tilt)
        k = np.array(ks)
        s_box = np.array(pj if bi == "base" else pi)
        p_base = np.array(pi if bi == "base" else pj)
        P_box, Pd_box = r + A @ s_box, rd + A @ np.cross(w, s_box)
        if bi == "base":
            Ai, l, ld, sign = np.eye(3), P_box - p_base, Pd_box, -1.0
            l0 = R0 + s_box - p_base
        else:
            Ai, l, ld, sign = A, p_base - P_box, -Pd_box, 1.0
            l0 = p_base - R0 - s_box
        dx = U @ (Ai.T @ l) - U @ l0
        dxd = U @ (Ai.T @ ld)
        F = sign * (Ai @ (U.T @ (k * dx + BETA * k * dxd)))        # on the box's point
        Q[:3] += F
        Q[3:] += np.cross(s_box, A.T @ F)
    return Q


def _complex_step(fun, n=6, h=1e-30):
    return np.stack([fun(1j * h * e).imag / h for e in np.eye(n)], axis=1)


def _independent_model():
    """Equilibrium by Newton, then M, K, C of the box: all written here."""
    A0, r0 = np.eye(3), R0.copy()
    z = np.zeros(6)
    for _ in range(30):
        Q = _forces(A0, r0, z + 0j, z + 0j).real
        Kq = _complex_step(lambda d, A0=A0, r0=r0: _forces(A0, r0, d, z + 0j))
        step = np.linalg.solve(Kq, -Q)
        r0, A0 = r0 + step[:3], A0 @ _rodrigues(step[3:])
        if np.abs(step).max() < 1e-15:
            break
    K = -_complex_step(lambda d: _forces(A0, r0, d, z + 0j))
    C = -_complex_step(lambda d: _forces(A0, r0, z + 0j, d))
    M = np.diag([MASS] * 3 + list(J))
    return M, K, C, r0, A0, np.abs(_forces(A0, r0, z + 0j, z + 0j)).max()


def test_frf_at_nearly_undamped_resonances_against_an_independent_model():
    M, K, C, r_eq, A_eq, res = _independent_model()
    assert res < 1e-9                                               # N, N m
    system = System(_box_scene())
    eq = solve_statics(system, tol=1e-11)
    assert eq.success, eq.message
    pos, _ = system.poses(eq.y)
    assert np.abs(pos[1] - r_eq).max() < 1e-12
    ms = mounted_system(system, eq.y)
    assert ms.evaluations <= 2
    assert np.abs(ms.K - K).max() <= 1e-13 * np.abs(K).max()
    assert np.abs(ms.C - C).max() <= 1e-13 * np.abs(C).max()
    # resonances: the undamped frequencies (ζ ≈ 1e-5: |H| there ≈ 1/(2ζ) × static)
    w2, _ = np.linalg.eig(np.linalg.solve(M, K))
    omega = np.sort(np.sqrt(w2.real))
    zeta = BETA * omega / 2
    assert np.all((zeta > 2e-6) & (zeta < 3e-5)), zeta
    out = Outputs(np.hstack([np.zeros((6, 3)), np.eye(6)]), np.zeros((0, 6)), np.zeros((0, 6)),
                  order=0)
    worst, worst_fd = 0.0, 0.0
    ms_fd = mounted_system(system, eq.y, exact=False)
    for axis in range(3):
        G_ = K[None] - omega[:, None, None] ** 2 * M + 1j * omega[:, None, None] * C
        u = np.linalg.solve(G_, np.broadcast_to(-(M[:, axis] + 0j), (6, 6))[..., None])[..., 0]
        q = u.copy()
        q[:, axis] += -1.0 / omega ** 2                             # q = u + ι x_b
        peak = np.abs(q).max(axis=0)
        h, _ = responses(ms, omega, Input("base", axis), out)
        h_fd, _ = responses(ms_fd, omega, Input("base", axis), out)
        worst = max(worst, (np.abs(h - q).max(axis=0) / peak).max())
        worst_fd = max(worst_fd, (np.abs(h_fd - q).max(axis=0) / peak).max())
    print(f"FRF at the resonances: exact {worst:.1e}, central differences {worst_fd:.1e} "
          "of each output's peak")
    assert worst <= 1e-9
    assert worst_fd > 1e-8                      # the test tells the two apart

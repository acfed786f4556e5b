"""Issue 30: the statics, the linearisation, the stiffness check, the modes
and the frequency responses of large scenes (block-sparse by the mount
graph) give today's results.

1. The reference scene (rigid bed, and its bed flexible with 2 modes): the
   static equilibrium, the natural frequencies, damping ratios and an FRF
   equal the numbers main's code gave before the block-sparse paths
   (commit 103d1ce: ``solve_statics`` with its column-by-column Jacobian,
   ``mounted_system`` from ``linearise``, the dense FRF), stored below. They
   were computed by running, at that commit, ``solve_statics(system,
   tol=static_tol)``, ``flexbed.analyses.modal.mounted`` and
   ``frequency_response(..., frequencies=FREQS)`` on ``load_scene(None)``
   and on it with ``[bed] model = "flexible", modes = 2`` (the modes file
   made by ``ensure_modes``), and printing the floats exactly (``repr``).
   Positions to 1e-12 m, frequencies to 1e-9 relative, FRF to 1e-9 of each
   output's largest |H| over these frequencies, plus 1e-11 of the largest
   |H| of all outputs (the force on the base, 1.5e4 N/(m/s²)) for an output
   that is nearly nil (a bed mount's lateral force on the flexible bed,
   0.8 N/(m/s²) at most: 2e-8 of itself, 1e-12 of the base force); damping ratios to 1e-9
   relative or 1e-10 absolute (a ratio of 1e-3 is −Re λ/|λ| of an eigenvalue
   whose real part carries the differences' round-off of small damper
   forces against the preloads: main's own values carry that much).
2. The built-in scene tiled 2 × 2 (8 pieces of equipment): the sparse
   paths (statics' sparse LU, the Arnoldi stiffness check, the block-
   eliminated and sparse-LU FRF, the lowest modes by Arnoldi) equal the
   dense ones.
"""

import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from flexbed.analyses.frf import frequency_response
from flexbed.analyses.modal import mounted
from flexbed.bench.tiling import equipment_count, tiled_scene, tiled_text
from flexbed.dynamics.frequency import frf as dfrf
from flexbed.dynamics.frequency.modal import solve_modes
from flexbed.dynamics.frequency.mounted import mounted_system
from flexbed.dynamics.jacobian import force_jacobian, mount_graph, perturbed_positions
from flexbed.dynamics.statics import _residual, _residual_rows, solve_statics
from flexbed.dynamics.stiffness import motion_eigenvalues, stable_step
from flexbed.files.modes import read_modes_file
from flexbed.files.scene import load_scene, parse_scene
from flexbed.files.toml_text import dumps
from flexbed.stages.modes import ensure_modes
from flexbed.stages.system import compile_scene

FREQS = np.array([0.7, 1.3, 2.9, 4.1, 6.3, 11.0])
OUTPUTS = ["A top az", "B top az", "bed centre az", "M5 f1", "M9 f3", "M2 f2", "base FZ"]
#: "M5 f1" is zero by the scene's symmetry (its values are round-off): not compared
COMPARED = [0, 1, 2, 4, 5, 6]

# ----------------------------------------------------- main's numbers (103d1ce)
RIGID_Q = [
    0.0, 0.0, 0.0,
    1.885624197869094e-39, 5.083569372486731e-21, 5.084327544,
    1.0, 4.169483310393131e-18, 5.523087792079044e-35,
    -3.840941919154484e-37, 3.287603674293404e-34, -0.96,
    5.331875043999999, 1.0, 4.343093271770321e-18,
    9.557080464082044e-34, -4.38011180820399e-35, 2.600657728702621e-34,
    0.96, 5.331875043999999, 1.0,
    4.0861561423039535e-18, 7.217721050749234e-34, -2.3927211462262208e-35,
]

RIGID_FREQUENCY = [
    3.9429298942321394, 3.9566315985886162, 3.959477989344701,
    6.532275919215864, 6.797893631283953, 6.899770372190221,
    8.623143208901224, 8.717854737279438, 9.569056699500683,
    9.571089475743914, 10.403270833538102, 10.411585253640641,
    16.768091034851377, 16.76826639020408, 17.18620276805681,
    17.186204228671563, 18.145206366155527, 18.146589387519942,
]

RIGID_UNDAMPED = [
    3.942457059660346, 3.95635916431195, 3.9592461212336802,
    6.497428515527492, 6.783237162602354, 6.893238946852433,
    8.393558568104503, 9.025093584889547, 9.38987309227356,
    9.749607796198204, 10.374611286978059, 10.455862016357957,
    16.750574298369244, 16.785426161551666, 17.15592272470496,
    17.216750421914348, 18.085820702410512, 18.206156127515182,
]

RIGID_DAMPING = [
    0.0007454261244159774, 0.00046324999042559147, 0.000402686455852272,
    0.00807036344466334, 0.009553565661454086, 0.0025052218319967664,
    0.09783956248811036, 0.013678600613167948, 0.0025907546641534425,
    0.14646425793407078, 0.1586116826208334, 0.00023756671288253098,
    0.2632687407514146, 1.2320309796560393e-05, 2.5219542689601987e-05,
    0.2702187754534963, 4.701171477933826e-05, 0.286279163019772,
]

RIGID_H = np.array([
    [complex(1.0369148466856508, -9.368479038378204e-08),
     complex(1.036912398342121, -0.00011088778004775143),
     complex(1.0319002160291748, -1.105461744439934e-07),
     complex(1.4791575556772487e-22, 6.794216105494614e-21),
     complex(-25.922809963155327, 0.002772001339260588),
     complex(-6.226189145400618e-09, -2.3433015804036374e-07),
     complex(-3298.130251553321, 0.011429254328364986)],
    [complex(1.138436725406353, -2.5473328744726535e-06),
     complex(1.1384039866025744, -0.000790741161445155),
     complex(1.1194480023311737, -2.9401220672665394e-06),
     complex(9.033682672527586e-21, 2.2151563475255363e-19),
     complex(-28.460099832096926, 0.019764917577890673),
     complex(-3.255433423194428e-07, -6.490528326570508e-06),
     complex(-3580.654727783183, 0.08813510293147953)],
    [complex(2.337238301996017, -0.0006737199423983616),
     complex(2.3353221596518225, -0.019892470932704204),
     complex(2.143233531546971, -0.0006790543679135443),
     complex(3.4680676967951187e-18, 3.907533696972513e-17),
     complex(-58.38311090608939, 0.4968286295403903),
     complex(-0.0002365685433972491, -0.001913941160346562),
     complex(-6886.669119854234, 4.090522729756205)],
    [complex(-16.361531617998956, -0.2262757259069743),
     complex(-16.302649546216244, 0.19194268242052087),
     complex(-13.646553444848923, -0.18540824770094716),
     complex(-6.297362909614103e-16, -1.2441398619326386e-15),
     complex(407.56903965858515, -4.781399272213747),
     complex(-0.12234941124333046, -0.7311536170227786),
     complex(44140.57499443316, 558.7680878676857)],
    [complex(-1.0326415191426779, -0.023605215382583866),
     complex(-0.9843230579038948, 0.12245464189215215),
     complex(-0.6252704427091197, -0.005751095308988795),
     complex(-1.3968354306433108e-15, -1.4056959924821081e-14),
     complex(24.645392029391495, -2.9834879768853444),
     complex(-0.0572983984206134, -0.12687247977990931),
     complex(2074.506487707146, 7.34073801898006)],
    [complex(1.2727286678814362, 0.04324885135347849),
     complex(-0.0003596418904828458, 0.4790164901292175),
     complex(-0.21188270444716648, -0.020270204145685103),
     complex(4.527490430850936e-14, -1.2892713131561257e-14),
     complex(-0.09013629140887902, -12.291831125098874),
     complex(0.25920146807260525, 0.028042783085762808),
     complex(507.3941737614194, 8.486781308729848)],
])

FLEXIBLE_Q = [
    0.0, 0.0, 0.0,
    8.641205099655842e-19, 5.957984742314341e-19, 5.082329634991217,
    1.0, 2.236857593046767e-16, -2.1625363680694886e-16,
    -4.2548793087098107e-23, -1.2709833974154194e-16, -0.9598068866619254,
    5.329454093355975, 0.9999997928178853, -0.000643711260280866,
    -3.1241205954379183e-16, -1.8902351418610136e-19, -3.517212598160074e-16,
    0.9598068866619253, 5.3294540933559755, 0.9999997928178853,
    0.0006437112602810687, -1.0611555829834387e-15, -1.8969527027393213e-19,
    0.05472199136230524, 7.928969123464565e-15,
]

FLEXIBLE_FREQUENCY = [
    3.7327880985924433, 3.9440955394806942, 3.9566596457109515,
    6.530473807017473, 6.798025655506029, 6.848739629789556,
    8.623020117701895, 8.718286833709028, 9.567292260664143,
    9.568636457016995, 10.403614097260931, 10.411462468459915,
    16.768102885606673, 16.768277248873527, 17.166110621013654,
    17.1797279903401, 18.145340187898682, 18.146726819285703,
    24.621842509904326,
]

FLEXIBLE_UNDAMPED = [
    3.722125009172249, 3.9436285320129207, 3.9563872120767436,
    6.495566717660756, 6.783366344884783, 6.833291255312624,
    8.39338379255418, 9.02568659487809, 9.385652908808774,
    9.748798251504974, 10.374499805152142, 10.455635780547672,
    16.750581940295756, 16.785428723620797, 17.099488896868316,
    17.216537944890625, 18.08585611537081, 18.206405103374145,
    24.736896174865382, 64.61886366246145,
]

FLEXIBLE_DAMPING = [
    0.013693313634345354, 0.0007353945501837882, 0.0004631494096303303,
    0.008121846752463949, 0.00954533686149662, 0.005673931229236736,
    0.09775840838943145, 0.013720993056244952, 0.00274916846375143,
    0.14644573945492642, 0.15846001353558506, 0.00024622996883224267,
    0.2632687053198403, 1.2329355884955552e-05, 0.2705458266178361,
    0.0007342107164638057, 4.726095425288538e-05, 0.28628252463690784,
    0.683565904884273,
]

FLEXIBLE_H = np.array([
    [complex(1.042015541436547, -0.00022559597977314568),
     complex(1.0420130567861177, -0.00033693710334539115),
     complex(1.038566718030572, -0.0002948390197455133),
     complex(-9.764589883104216e-12, 4.255606055638152e-13),
     complex(-26.086852025697663, 0.009580026518299367),
     complex(1.3459544812822025e-07, 2.1494249783279672e-06),
     complex(-3311.7644085395395, 0.6142554951540045)],
    [complex(1.1593307720975854, -0.0017423019792819807),
     complex(1.1592962199013424, -0.0025449753823226294),
     complex(1.1460025643785159, -0.002214056512829402),
     complex(-2.141808459213373e-11, 1.767760437988344e-12),
     complex(-29.065015165697243, 0.06958705199286142),
     complex(5.670362860953021e-06, 4.381315263611631e-05),
     complex(-3636.5871344012226, 4.746968141531413)],
    [complex(2.7680475583156783, -0.09505102928759776),
     complex(2.764999748643916, -0.11774539208135244),
     complex(2.6032245401151615, -0.10144727208823766),
     complex(-2.333216248247335e-10, 5.046763953565448e-11),
     complex(-69.8521453636785, 3.1014677286945282),
     complex(0.003563333272107167, 0.009971156238345966),
     complex(-8050.210176367578, 259.44069649087965)],
    [complex(-5.749487530820378, -0.9846595189803082),
     complex(-5.751830772815521, -0.8339279814577434),
     complex(-5.047840251584384, -0.7984849029475981),
     complex(5.090052271978036e-10, -7.645819975555172e-11),
     complex(146.70092236342282, 20.582853068469493),
     complex(0.2305145863367279, 0.7775277634540709),
     complex(15103.200492629805, 2673.0404902533214)],
    [complex(-0.9118760900187204, -0.06394819879394778),
     complex(-0.8728161265286191, 0.06937279850604593),
     complex(-0.6157100058753875, -0.0082975846514535),
     complex(3.799533485335813e-09, -1.6278525651700204e-09),
     complex(22.719791820159593, -2.043667453794555),
     complex(0.009994556303601021, -0.03583620619210915),
     complex(1727.2653055303529, 126.49158177249595)],
    [complex(1.3117171554929168, 0.01875279899292772),
     complex(0.011800390225194702, 0.4937162726265662),
     complex(-0.2576609620078568, 0.013480132814334984),
     complex(1.1575928504959868e-10, -6.671016842287197e-11),
     complex(-0.4754796419535525, -13.190004460374293),
     complex(0.23884751417591932, 0.21481549334158467),
     complex(459.7056001716052, 45.2984655894602)],
])


# ------------------------------------------------------------------ helpers

def _compare(key, sf, system, data, q_ref, f_ref, u_ref, z_ref, h_ref, modal_slice=None):
    eq = solve_statics(system, tol=sf.solver.static_tol, sag=True)
    assert eq.success, eq.message
    lay = system.layout
    q_ref = np.array(q_ref)
    stop = lay.q_modal.start                     # the frame coordinates (modal ones: by |a|)
    assert np.abs(eq.y[:stop] - q_ref[:stop]).max() <= 1e-12
    assert np.allclose(np.abs(eq.y[stop:lay.nq]), np.abs(q_ref[stop:]), rtol=1e-9, atol=1e-14)
    mt = mounted(sf, system, y_eq=eq.y, bed_modes=data)
    md = mt.modes
    assert md.frequency == pytest.approx(f_ref, rel=1e-9, abs=0)
    assert md.undamped_frequency == pytest.approx(u_ref, rel=1e-9, abs=0)
    assert md.damping_ratio == pytest.approx(z_ref, rel=1e-9, abs=1e-10)
    fr = frequency_response(sf, mt, frequencies=FREQS)
    H = fr.H[:, [fr.names.index(n) for n in OUTPUTS]][:, COMPARED]
    ref = h_ref[:, COMPARED]
    scale = np.abs(ref).max(axis=0)
    err = np.abs(H - ref).max(axis=0)
    print(f"\n{key}: positions {np.abs(eq.y[:stop] - q_ref[:stop]).max():.1e} m, frequencies "
          f"{np.max(np.abs(md.frequency - f_ref) / np.array(f_ref)):.1e}, FRF "
          f"{np.max(err / scale):.1e} of the output's largest |H|, "
          f"{err.max() / scale.max():.1e} of the largest of all")
    assert np.all(err <= 1e-9 * scale + 1e-11 * scale.max())


def test_reference_scene_rigid_bed_unchanged(reference_scene, reference_system):
    _compare("rigid", reference_scene, reference_system, None, RIGID_Q, RIGID_FREQUENCY,
             RIGID_UNDAMPED, RIGID_DAMPING, RIGID_H)


@pytest.mark.slow
def test_reference_scene_flexible_bed_unchanged(tmp_path):
    sf0 = load_scene(None)
    sf = replace(sf0, bed=replace(sf0.bed, model="flexible", modes=2))
    d, _ = ensure_modes(sf, tmp_path / "m.h5", n_modes=2, log=lambda m: None)
    data = read_modes_file(d.path)
    system = compile_scene(sf, modes=data)
    _compare("flexible", sf, system, data, FLEXIBLE_Q, FLEXIBLE_FREQUENCY, FLEXIBLE_UNDAMPED,
             FLEXIBLE_DAMPING, FLEXIBLE_H)


# ------------------------------------------------------------- tiled scenes

@pytest.fixture(scope="module")
def tiled8():
    sf = tiled_scene(2)
    system = compile_scene(sf)
    eq = solve_statics(system, tol=sf.solver.static_tol)
    assert eq.success, eq.message
    return sf, system, eq.y


def test_tiling_counts_and_the_unit_is_the_builtin_scene():
    assert [equipment_count(c) for c in (1, 2, 4, 8)] == [2, 8, 32, 128]
    sf = tiled_scene(2)
    assert len(sf.scene.bodies) == 2 + 8 and len(sf.scene.mounts) == 48
    assert sf.bed.plate.length_x == pytest.approx(1.6)
    assert sf.bed.plate.length_y == pytest.approx(9.6)
    one = tiled_scene(1)
    ref = load_scene(None)
    assert [b.name for b in one.scene.bodies] == [b.name for b in ref.scene.bodies]
    assert [m.name for m in one.scene.mounts] == [m.name for m in ref.scene.mounts]
    with pytest.raises(ValueError, match="c must be an integer"):
        tiled_text(0)


def test_tiled_equilibrium_is_the_unit_s_repeated(tiled8, reference_equilibrium):
    """Every copy of the equipment sits as in the unit, relative to the bed,
    to the statics' tolerance (the bed carries c² times the unit's load on
    c² times its mounts: the same sag)."""
    sf, system, y = tiled8
    pos, p = system.poses(y)
    ref = load_scene(None)
    rs = compile_scene(ref)
    rpos, rp = rs.poses(reference_equilibrium)
    names = [b.name for b in sf.scene.bodies]
    assert np.abs(pos[1] - rpos[1]).max() < 1e-6 and np.abs(p[1] - rp[1]).max() < 1e-6
    for k, unit in ((2, "equipment A"), (3, "equipment B")):
        for ix in range(2):
            for iy in range(2):
                b = names.index(f"{unit} {ix}.{iy}")
                shift = np.array([0.8 * (ix - 0.5), 4.8 * (iy - 0.5), 0.0])
                assert np.abs(pos[b] - shift - rpos[k]).max() < 1e-6


def test_colour_class_jacobian_equals_column_by_column_differences(tiled8):
    """The Jacobian of the statics' residual by colour classes equals the
    central differences taken one column at a time (as main's statics did)."""
    sf, system, y = tiled8
    g = mount_graph(system, modal=False)
    assert len(g.classes) == 2                    # the bed; the pieces of equipment
    h = 1e-6
    steps = np.full(g.n, h)
    fj = force_jacobian(system, y, lambda dY, Y: _residual_rows(system, dY, Y, True),
                        lambda DU: perturbed_positions(system, y, DU), steps, modal=False,
                        capture=())
    assert fj.evaluations == 2 * 2 * 6
    J = np.empty((g.n, g.n))
    for c in range(g.n):
        e = np.zeros(g.n)
        e[c] = h
        Yp = perturbed_positions(system, y, np.stack([e, -e]))
        J[:, c] = (_residual(system, Yp[0]) - _residual(system, Yp[1])) / (2 * h)
    scale = np.abs(J).max()
    assert np.abs(fj.R.toarray() - J).max() <= 1e-9 * scale
    # block-sparse: no entry between two pieces of equipment (the bed's 6 are first)
    R = fj.R.toarray()
    for a in range(1, 9):
        for b in range(1, 9):
            if a != b:
                assert not R[6 * a:6 * a + 6, 6 * b:6 * b + 6].any()


def test_sparse_statics_equal_dense(tiled8):
    sf, system, y = tiled8
    dense = solve_statics(system, tol=sf.solver.static_tol, sparse=False)
    sparse = solve_statics(system, tol=sf.solver.static_tol, sparse=True)
    assert dense.success and sparse.success
    assert np.abs(dense.y - sparse.y).max() <= 1e-12


def test_sparse_statics_name_a_free_direction():
    """A piece of equipment whose four mounts carry nothing along x: the
    sparse path names it as the dense one does."""
    data = tomllib.loads(tiled_text(2))
    for m in data["mount"]:
        if m["body_j"] == "equipment A 1.0":
            del m["k"], m["c"]
            m["law"] = "polynomial"
            m["stiffness"] = [[0.0], [0.0, 1.0e5], [0.0, 1.0e5]]
    sf = parse_scene(dumps(data), Path("free.toml"))
    system = compile_scene(sf)
    for sparse in (False, True):
        eq = solve_statics(system, sparse=sparse)
        assert not eq.success
        assert "body 'equipment A 1.0' is free in x" in eq.message


def test_arnoldi_stiffness_check_equals_the_dense_one(tiled8):
    sf, system, y = tiled8
    y0 = system.initial_state(y)
    dense = motion_eigenvalues(system, y0, sparse=False)
    sparse = motion_eigenvalues(system, y0, sparse=True)
    assert np.abs(sparse).max() == pytest.approx(np.abs(dense).max(), rel=1e-7)
    for method in ("rk4", "dop853"):
        hd, rd = stable_step(method, dense)
        hs, rs = stable_step(method, sparse)
        assert hs == pytest.approx(hd, rel=1e-7) and rs == pytest.approx(rd, rel=1e-7)


def test_block_and_sparse_frf_equal_the_dense_solve(tiled8, monkeypatch):
    sf, system, y = tiled8
    ms = mounted_system(system, y)
    assert ms.n == 54
    forces, rates = dfrf.mount_outputs(ms)
    rng = np.random.default_rng(3)
    out = dfrf.Outputs(rng.normal(size=(6, 3 + ms.n)), forces, rates)
    omega = 2 * np.pi * np.geomspace(1.0, 30.0, 150)
    for inp in (dfrf.Input("base", 2), dfrf.Input("force", 0, rng.normal(size=ms.n))):
        monkeypatch.setattr(dfrf, "DENSE_LIMIT", 100)
        dense = dfrf.responses(ms, omega, inp, out)               # 54 ≤ 100: dense
        monkeypatch.undo()
        assert np.array_equal(dfrf.responses(ms, omega, inp, out)[1],
                              dfrf._responses_sparse(ms, omega, inp, out)[1])
        blocks = dfrf._responses_sparse(ms, omega, inp, out)
        monkeypatch.setattr(dfrf, "_plan", lambda ms: None)
        lu = dfrf._responses_sparse(ms, omega, inp, out)
        monkeypatch.undo()
        for a, b, c in zip(dense, blocks, lu):
            # per output against its largest |H|, plus round-off of the largest
            # output (the base force) for outputs nil by symmetry
            tol = 1e-10 * np.abs(a).max(axis=0) + 1e-14 * np.abs(a).max()
            assert np.all(np.abs(b - a).max(axis=0) <= tol)
            assert np.all(np.abs(c - a).max(axis=0) <= tol)


def test_lowest_modes_by_arnoldi_equal_the_dense_ones(tiled8):
    """12 lowest modes (a gap in the spectrum follows the 12th): the same
    frequencies, damping ratios and effective masses, on the exact
    matrices (dynamics/tangent.py), where the equipment's 8.031 Hz mode is
    exactly 4-fold (SciPy's default Krylov size found 2 of its 4 copies)."""
    sf, system, y = tiled8
    ms = mounted_system(system, y)
    full = solve_modes(ms)
    low = solve_modes(ms, count=12)
    assert low.frequency.size == 12
    assert low.frequency == pytest.approx(full.frequency[:12], rel=1e-10)
    assert low.undamped_frequency == pytest.approx(full.undamped_frequency[:12], rel=1e-10)
    assert low.damping_ratio == pytest.approx(full.damping_ratio[:12], rel=0, abs=1e-12)
    assert np.abs(low.effective_mass - full.effective_mass[:12]).max() <= 1e-9 * ms.moving_mass


@pytest.mark.slow
def test_growth_exponent_and_one_row_of_the_scaling_table():
    from flexbed.bench.scaling import growth_exponent, stage_times

    assert growth_exponent(32, 1.0, 128, 4.0) == pytest.approx(1.0)
    assert growth_exponent(32, 1.0, 128, 16.0) == pytest.approx(2.0)
    assert np.isnan(growth_exponent(32, 0.0, 128, 1.0))
    row = stage_times(1)
    assert row["N"] == 2 and row["coordinates"] == 18
    assert all(row[s] > 0.0 for s in ("statics", "static", "simulate", "modal", "frf"))
    assert row["static"] >= row["statics"]


def test_mounted_system_by_colour_classes_equals_column_by_column(tiled8):
    """The large systems' path of the mounted system (colour classes, 2 × 2
    × 6 right-hand sides per kind) against today's (every column): the same
    matrices to round-off, hence the same modes."""
    sf, system, y = tiled8
    dense = mounted_system(system, y, sparse=False, exact=False)
    sparse = mounted_system(system, y, sparse=True, exact=False)
    assert sparse.evaluations < dense.evaluations / 4
    for name in ("M", "K", "C", "D", "Dv", "Fq", "Fv", "Bq", "Bv", "k_tangent", "c_tangent"):
        a, b = getattr(dense, name), getattr(sparse, name)
        assert np.abs(a - b).max() <= 1e-11 * max(np.abs(a).max(), 1e-300), name
    fd, fs = solve_modes(dense).frequency, solve_modes(sparse).frequency
    assert fs == pytest.approx(fd, rel=1e-10)


def test_large_systems_undamped_modes_by_the_standard_problem(tiled8, monkeypatch):
    """Above DENSE_LIMIT the undamped modes come from M⁻¹K (QR) and V⁻¹: on
    the 2 × 2 tiling (forced onto that path) the frequencies and the
    effective masses equal the generalized QZ's, the left and right shapes
    are biorthogonal in M over the whole set — within the clusters of equal
    frequencies its identical pieces make too — and each is an eigenvector."""
    from flexbed.dynamics.frequency import modal

    sf, system, y = tiled8
    ms = mounted_system(system, y)
    qz = solve_modes(ms)
    monkeypatch.setattr(modal, "DENSE_LIMIT", 0)
    qr = solve_modes(ms)
    assert qr.undamped_frequency == pytest.approx(qz.undamped_frequency, rel=1e-11)
    assert np.abs(qr.effective_mass - qz.effective_mass).max() <= 1e-11 * ms.moving_mass
    f, phi, psi, _ = modal._undamped(ms)
    T = psi.conj() @ ms.M @ phi.T
    assert np.abs(T - np.eye(ms.n)).max() < 1e-9
    w2 = (2 * np.pi * f) ** 2
    residual = phi @ ms.K.T - w2[:, None] * (phi @ ms.M.T)
    assert np.abs(residual).max() <= 1e-9 * np.abs(phi @ ms.K.T).max()

"""Mount layout optimisation (issue 27): a closed-form optimum recovered to
1e-6 from several starts; the log reused by a re-run; bad input refused
in one line before anything runs; an infeasible problem reported as such
(exit 1) with its best point kept; the layout metrics on exact cases.

The closed form. A body on four mounts at (±b, ±a) in plan, h below its
centre of mass, each inclined by ±α about x (focal: the compression axes
meet above), axial rate k_p and shear rate k_q in the y-z plane. A lateral
translation y of the body loads each mount by K_yy y along y and K_yz y
along z, with K_yy = k_p sin²α + k_q cos²α and K_yz = ∓(k_p − k_q) sin α
cos α; the moment of these about the centre of mass (x axis) vanishes —
the elastic centre is at the centre of mass, rocking decoupled from
lateral translation — when h (k_p sin²α + k_q cos²α) = a (k_p − k_q)
sin α cos α, i.e. h k_p t² − a (k_p − k_q) t + h k_q = 0, t = tan α. With
gravity off, the linearisation is about the mounts' unloaded geometry, so
this holds exactly for the mounted system's modes: the lateral mode is
all y and the rocking mode all roll.
"""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

import flexbed
from flexbed.cli import main
from flexbed.optimization.problem import make_problem
from flexbed.optimization.spec import read_optimize
from flexbed.study.layout_metrics import direction_shares, rigid_modes
from scene_text import base_and_body

A, H, B = 0.2, 0.1, 0.25          # half-spans [m], mounts below the centre of mass [m]
KP, KQ = 1.0e5, 2.0e4             # axial and shear rates [N/m]


def focal_angle() -> float:
    """The closed-form inclination [deg] (the root within 0-30 deg)."""
    disc = math.sqrt(A * A * (KP - KQ) ** 2 - 4.0 * H * H * KP * KQ)
    return math.degrees(math.atan((A * (KP - KQ) - disc) / (2.0 * H * KP)))


def inclined_scene(angle: float = 10.0) -> str:
    text = base_and_body("inclined", gravity=0.0, mass=50.0, inertia="[2.0, 3.0, 4.0]")
    for i, (x, y) in enumerate([(-B, -A), (B, -A), (-B, A), (B, A)], 1):
        text += f"""
[[mount]]
name = "M{i}"
body_i = "base"
body_j = "mass"
point_i = [{x}, {y}, {0.5 - H}]
point_j = [{x}, {y}, {-H}]
axes_deg = [{angle if y > 0 else -angle}, 0.0, 0.0]
law = "linear"
k = [3.0e4, {KQ}, {KP}]
c = [0.0, 0.0, 0.0]
"""
    return text + "\n[solver]\nt_end = 0.1\n"


ANGLE = """
[[variable]]
path = "mount.M3.axes_deg[0]"
tie = ["mount.M4.axes_deg[0]"]
mirror = ["mount.M1.axes_deg[0]", "mount.M2.axes_deg[0]"]
low = 0.0
high = 30.0
"""

DECOUPLE = """
[[objective]]
kind = "decoupling"
directions = ["y", "roll"]
sense = "maximize"
"""


def write(tmp_path, head: str, body: str = ANGLE + DECOUPLE):
    (tmp_path / "inclined.toml").write_text(inclined_scene())
    path = tmp_path / "opt.toml"
    path.write_text(f'[optimize]\nscene = "inclined.toml"\n{head}\n{body}')
    return path


@pytest.fixture(scope="module")
def cluster():
    from distributed import LocalCluster

    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                      dashboard_address=":0") as c:
        yield c


@pytest.fixture()
def client(cluster):
    from distributed import Client

    with Client(cluster) as c:
        yield c


@pytest.mark.slow
def test_the_focal_inclination_is_found_to_1e_6_from_several_starts(tmp_path, client):
    path = write(tmp_path, 'method = "slsqp"\ndifferences = "central"\ntolerance = 1e-14\n'
                           'starts = 3\nseed = 4\n')
    opt = flexbed.optimize(path, scheduler=client)
    exact = focal_angle()
    assert 5.0 < exact < 10.0
    problem = opt.problem
    assert len(opt.outcomes) == 3
    for o in opt.outcomes:
        assert abs(o.best.x[0] - exact) < 1e-6, (o.start, o.best.x[0], exact, o.message)
    assert abs(opt.values["mount.M3.axes_deg[0]"] - exact) < 1e-6
    assert opt.values["mount.M1.axes_deg[0]"] == -opt.values["mount.M3.axes_deg[0]"]
    assert opt.feasible and opt.best.result.values == pytest.approx((1.0, 1.0), abs=1e-12)
    # the first start is the scene's 10 deg
    assert problem.values(problem.u0)[0] == 10.0


@pytest.mark.slow
def test_a_rerun_reuses_the_log_and_finds_the_same_optimum(tmp_path, client):
    path = write(tmp_path, 'method = "slsqp"\n')
    out = tmp_path / "out"
    one = flexbed.optimize(path, scheduler=client, output=out, plots=False)
    assert one.evaluations > 3 and (out / "optimum.toml").is_file()
    with (out / "evaluations.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == one.evaluations
    assert {r["status"] for r in rows} == {"ok"}
    two = flexbed.optimize(path, scheduler=client, output=out, plots=False)
    assert two.evaluations == 0 and two.reused > 0
    assert two.values == one.values
    with (out / "evaluations.csv").open() as fh:
        assert len(list(csv.DictReader(fh))) == one.evaluations
    again = flexbed.load_scene(out / "optimum.toml")
    assert again.digest == one.scene.digest


@pytest.mark.parametrize("head, body, message", [
    ("", ANGLE.replace("mount.M3.axes", "mount.M7.axes") + DECOUPLE,
     "variable 1 (mount.M7.axes_deg[0]) = 0.0: variant path 'mount.M7.axes_deg[0]': no entry "
     "named 'M7'"),
    ("", ANGLE.replace("low = 0.0\nhigh = 30.0", "low = 30.0\nhigh = 0.0") + DECOUPLE,
     "variable 1 (mount.M3.axes_deg[0]): low = 30.0 must be below high = 0.0"),
    ("", ANGLE + DECOUPLE.replace('kind = "decoupling"', 'kind = "decoupled"'),
     "objective 1: unknown metric kind 'decoupled'"),
    ("", ANGLE + '[[constraint]]\nkind = "natural_frequenzy"\nupper = 8.0\n',
     "constraint 1: unknown metric kind 'natural_frequenzy'"),
    ("", ANGLE + DECOUPLE.replace('directions = ["y", "roll"]', 'directions = ["sideways"]'),
     "objective 1 (decoupling): directions = ['sideways'] must be a list of distinct"),
    ('method = "newton"\n', ANGLE + DECOUPLE, "[optimize] method = 'newton' must be one of"),
])
def test_bad_input_is_one_line_and_nothing_is_written(tmp_path, capsys, head, body, message):
    path = write(tmp_path, head, body)
    out = tmp_path / "out"
    assert main(["optimize", str(path), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("flexbed optimize: opt.toml: ") and message in err, err
    assert err.count("\n") == 1
    assert not out.exists()


def test_no_feasible_point_exits_1_and_keeps_the_best(tmp_path, capsys, cluster):
    # every mode below 1 Hz on these rates is out of the variable's reach
    body = ANGLE + DECOUPLE + '[[constraint]]\nkind = "highest_frequency"\nupper = 1.0\n'
    path = write(tmp_path, 'method = "slsqp"\nmax_evaluations = 60\n', body)
    out = tmp_path / "out"
    code = main(["optimize", str(path), "-o", str(out), "--scheduler",
                 cluster.scheduler_address, "--no-plots"])
    cap = capsys.readouterr()
    assert code == 1, cap.err
    assert "opt.toml: no feasible point found" in cap.err and cap.err.count("\n") == 1
    # one line per variable, not per path it sets (here 1 tied and 2 mirrored)
    listed = [line for line in cap.out.splitlines() if line.startswith("  ")]
    assert len(listed) == 1 and listed[0].startswith("  mount.M3.axes_deg[0] = ") and \
        listed[0].endswith(" (and 3 paths set with it)"), cap.out
    text = (out / "optimum.toml").read_text()
    assert "NOT feasible" in text.splitlines()[0]
    assert flexbed.load_scene(out / "optimum.toml").scene.mounts[0].name == "M1"


def test_direction_shares_sum_bodies_and_keep_elastic_apart():
    labels = ("bed x", "bed roll", "A x", "A roll", "bed mode 1")
    energy = np.array([[0.5, 0.0, 0.3, 0.0, 0.2],
                       [0.0, 0.6, 0.0, 0.4, 0.0],
                       [0.1, 0.0, 0.0, 0.0, 0.9]])
    by_dir = direction_shares(energy, labels)
    assert by_dir.shape == (3, 7)
    np.testing.assert_array_equal(by_dir[:, 0], [0.8, 0.0, 0.1])       # x
    np.testing.assert_array_equal(by_dir[:, 3], [0.0, 1.0, 0.0])       # roll
    np.testing.assert_array_equal(by_dir[:, 6], [0.2, 0.0, 0.9])       # elastic
    by_coord = direction_shares(energy, labels, "coordinate")
    np.testing.assert_array_equal(by_coord[1], [0.0, 0.6, 0.0, 0.4, 0.0])

    class M:                                        # a mode dominated by the bed's elasticity
        pass
    m = M()
    m.energy, m.labels = energy, labels
    idx, shares = rigid_modes(m)
    np.testing.assert_array_equal(idx, [0, 1])
    np.testing.assert_array_equal(shares, [0.8, 1.0])


def test_the_focal_layout_decouples_in_the_modal_analysis(tmp_path):
    """The closed form checked by itself, without the optimiser: at the
    focal angle the lateral and rocking modes hold all their energy in y
    and in roll; at 10 deg they do not."""
    path = write(tmp_path, "")
    problem = make_problem(read_optimize(path))
    for angle, exact in ((focal_angle(), True), (10.0, False)):
        m = flexbed.modal(problem.scene([angle]))
        shares = direction_shares(np.asarray(m.energy), tuple(m.labels))
        y = shares[np.argmax(shares[:, 1]), 1]
        roll = shares[np.argmax(shares[:, 3]), 3]
        if exact:
            assert y == pytest.approx(1.0, abs=1e-13) and roll == pytest.approx(1.0, abs=1e-13)
        else:
            assert y < 1.0 - 1e-4 and roll < 1.0 - 1e-4


def test_a_catalogue_variable_ends_on_a_catalogue_value(tmp_path, client):
    body = ANGLE.replace("low = 0.0\nhigh = 30.0", "values = [0.0, 5.0, 7.5, 10.0, 20.0]") + \
        DECOUPLE
    opt = flexbed.optimize(write(tmp_path, 'method = "slsqp"\n', body), scheduler=client)
    assert opt.values["mount.M3.axes_deg[0]"] == 7.5          # the nearest to 7.78 deg


@pytest.mark.slow
def test_a_pareto_front_runs_from_one_objective_to_the_other(tmp_path, client):
    body = ANGLE + DECOUPLE + '[[objective]]\nkind = "highest_frequency"\nscale = 10.0\n'
    out = tmp_path / "out"
    opt = flexbed.optimize(write(tmp_path, "pareto = 3\n", body), scheduler=client,
                           output=out, plots=False)
    assert len(opt.pareto) == 3
    # w = 0: the highest frequency alone, lowest at the upper bound; w = 1: decoupling alone
    assert opt.pareto[0].x[0] == 30.0
    assert abs(opt.pareto[-1].x[0] - focal_angle()) < 1e-3
    rows = (out / "pareto.csv").read_text().splitlines()
    assert len(rows) == 4 and rows[0].startswith("w,mount.M3.axes_deg[0],objective1")


def test_rigid_frequencies_and_the_highest_are_the_modal_frequencies(tmp_path):
    from flexbed.study.metrics import KINDS
    from flexbed.study.spec import MetricTable

    problem = make_problem(read_optimize(write(tmp_path, "")))
    scene = problem.scene([10.0])
    m = flexbed.modal(scene)
    every = KINDS["rigid_frequencies"].build(MetricTable(1, "rigid_frequencies", ()), scene, "t")
    top = KINDS["highest_frequency"].build(MetricTable(2, "highest_frequency", ()), scene, "t")
    dec = KINDS["decoupling"].build(MetricTable(3, "decoupling", ()), scene, "t")
    assert every.columns[0] == "rigid_frequency.mode1" and len(every.columns) == 6
    assert every.values({"modal": m}) == tuple(float(f) for f in m.frequency)
    assert top.values({"modal": m}) == (float(m.frequency.max()),)
    shares = dec.values({"modal": m})
    assert len(shares) == 6 and all(0.5 < s <= 1.0 for s in shares)
    assert shares[2] == pytest.approx(1.0, abs=1e-12)          # yaw, alone by symmetry

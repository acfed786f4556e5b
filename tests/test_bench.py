"""``flexbed bench``: the work-precision report is written whole, and its
numbers mean what they say (reference far more accurate than the ladders,
RK4 converging at 4th order, truncation error falling as modes are added).

The report runs once, quick, over a shortened run (0–0.5 s), in the bench's
test profile (``FLEXBED_BENCH_PROFILE=test``, :data:`flexbed.bench.context.TEST_PROFILE`:
its two ``element_size = "auto"`` beds meshed to 2 % rather than 0.5 %) to
keep the suite fast; every section still runs and writes its table and
figures. Those beds at the default 0.5 % are checked against the 3D solid by
tests/test_accuracy.py (the reference bed) and tests/test_stiffener_model.py
(the stiffened bed). No assertion is on a timing.
"""

import math

import numpy as np
import pytest

from flexbed.dynamics.integrate import Run, Settings, Stats
from flexbed.bench.dynamics import (Measurement, classify, fastest_reaching, observed_orders,
                                     run_ladders)
from flexbed.bench.report import SECTIONS, write_report
from flexbed.cli import main

#: every test here is a bench test; those on the report (about a minute) are slow too
pytestmark = pytest.mark.bench

T_END = 0.5
PNG = b"\x89PNG\r\n\x1a\n"


#: files in the report's folder before it runs: another report's PNG, a note
FOREIGN = {"bench-retired-section.png": PNG + b"an earlier report's", "notes.txt": b"mine"}


def _build_report(tmp_path, monkeypatch):
    monkeypatch.setenv("FLEXBED_BENCH_PROFILE", "test")
    out = tmp_path / "bench"
    out.mkdir()
    for name, data in FOREIGN.items():
        (out / name).write_bytes(data)
    return write_report(out, quick=True, t_end=T_END)


def _files_the_report_did_not_write_are_left_alone(report):
    out = report.path.parent
    for name, data in FOREIGN.items():
        assert (out / name).read_bytes() == data
    assert report.stale == [out / "bench-retired-section.png"]
    assert sorted(out.iterdir()) == sorted([report.path] + report.figures +
                                           [out / name for name in FOREIGN])


def _report_and_every_figure_are_written(report):
    text = report.path.read_text()
    assert report.path.name == "benchmarks.md"
    for title in ("## One right-hand side", "## Integrators", "## Against the aims",
                  "## Modes kept", "## Mesh density", "## Invariants"):
        assert title in text
    assert "quick" in text.splitlines()[0] and "Python" in text and "SciPy" in text
    assert len(report.figures) >= 4
    for png in report.figures:
        assert png.read_bytes()[:8] == PNG
        assert f"]({png.name})" in text
    # the aims are not claimed for a run that is not the scene's 0-3 s
    assert "not comparable" in text


def _every_integrator_ran_on_every_quick_case(report):
    rows = report.ctx.results["integrators"]
    assert set(rows) == {"rigid", "flexible"}
    for case_rows in rows.values():
        assert {m.method for m in case_rows if m.ok} == {"rk4", "adams", "bdf", "radau",
                                                         "dop853"}
        for m in case_rows:
            assert m.ok and 0 < m.position_error < 1e-4 and 0 < m.force_error < 10.0


def _reference_is_far_more_accurate_than_the_ladders(report):
    for key, ref in report.ctx.results["references"].items():
        ok = [m for m in report.ctx.results["integrators"][key] if m.ok]
        assert 0 < ref.position_error < 0.05 * min(m.position_error for m in ok), key
        assert 0 < ref.force_error < 0.05 * min(m.force_error for m in ok), key


def _rk4_converges_at_fourth_order(report):
    for key in ("rigid", "flexible"):
        orders = observed_orders(report.ctx.results["integrators"][key])
        assert orders and all(3.6 < p < 4.4 for p in orders), (key, orders)


def _truncation_error_falls_as_modes_are_kept(report):
    runs = report.ctx.results["modes_count"]["runs"]
    for attr in ("position_error", "motion_error", "force_error"):
        e = [getattr(r, attr) for r in runs]
        assert all(b <= 1.01 * a for a, b in zip(e, e[1:])), (attr, e)
        assert e[-1] < 0.5 * e[0], (attr, e)


def _mesh_error_falls_with_refinement(report):
    rows = report.ctx.results["mesh"]
    errs = [r.error for r in rows]
    assert errs[-1] == 0.0 and all(b < a for a, b in zip(errs, errs[1:]))


def _first_order_invariants_differ_slightly_from_full(report):
    full, first = report.ctx.results["invariants"]["flexible"]
    assert full.position_error < 1e-7                     # the integrator's own error
    d = float(np.max(np.abs(first.samples.r - full.samples.r)))
    assert 0 < d < 1e-6


def _aims_name_the_fastest_setting_reaching_each_error(report):
    verdicts = report.ctx.results["aims"]
    assert set(verdicts) == {(k, e) for k in ("rigid", "flexible") for e in (1e-6, 1e-9)}
    rows = report.ctx.results["integrators"]["rigid"]
    best, _ = verdicts[("rigid", 1e-6)]
    assert best is not None and best.position_error <= 1e-6
    assert best.wall_time == min(m.wall_time for m in rows if m.ok and m.position_error <= 1e-6)


def _settings_over_budget_are_skipped_with_the_prediction(report):
    ctx = report.ctx
    rows = run_ladders(ctx.case("rigid"), ctx.reference("rigid"),
                       {"rk4": (1e-5, 5e-6), "dop853": (1e-6, 1e-7)}, output_dt=ctx.output_dt,
                       budget=1e-6)
    rk4 = [m for m in rows if m.method == "rk4"]
    assert all(m.status == "skipped" and "predicted" in m.note for m in rk4)
    dop = [m for m in rows if m.method == "dop853"]
    # nothing to predict the first setting from: it runs; the next is predicted from it
    assert dop[0].ok and dop[1].status == "skipped" and "previous" in dop[1].note


def _run(message: str, complete: bool = False) -> Run:
    return Run(t=np.zeros(1), y=np.zeros((1, 1)), complete=complete, message=message,
               stats=Stats(method="rk4"), settings=Settings("rk4"), t_reached=0.0)


def test_refused_and_failed_runs_are_classified():
    assert classify(_run("completed", True)) == ("ok", "")
    status, note = classify(_run("stiff scene: the fastest rate 1.7e+04 1/s limits rk4 ..."))
    assert status == "stiff: refused" and note.startswith("stiff scene")
    assert classify(_run("rk4: the state became non-finite at t = 0.1 s"))[0] == "unstable"
    assert classify(_run("diverged at t = 0.2 s: body 'A' is 3e+04 m from where it "
                         "started"))[0] == "unstable"
    assert classify(_run("the maximum number of steps was reached"))[0] == "failed"


def test_fastest_reaching_and_observed_order_on_made_up_rows():
    rows = [Measurement("c", "rk4", 2e-3, wall_time=1.0, position_error=1.6e-7),
            Measurement("c", "rk4", 1e-3, wall_time=2.0, position_error=1e-8),
            Measurement("c", "dop853", 1e-6, wall_time=0.5, position_error=5e-7),
            Measurement("c", "bdf", 1e-6, status="stiff: refused", wall_time=0.01)]
    assert fastest_reaching(rows, 1e-6).method == "dop853"
    assert fastest_reaching(rows, 1e-8).value == 1e-3
    assert fastest_reaching(rows, 1e-9) is None
    assert observed_orders(rows) == [pytest.approx(4.0)]
    assert math.isnan(Measurement("c", "rk4", 1e-3).position_error)


def test_the_test_profile_is_the_quick_one_but_for_the_auto_beds(monkeypatch):
    """``flexbed bench --quick`` is the quick profile unless the environment
    asks for the test profile, which differs only in the auto beds'
    tolerance (2 %, not the default 0.5 %)."""
    from dataclasses import replace

    from flexbed.bench.context import QUICK, TEST_PROFILE, quick_profile
    monkeypatch.delenv("FLEXBED_BENCH_PROFILE", raising=False)
    assert quick_profile() is QUICK and QUICK.auto_tolerance == 0.005
    monkeypatch.setenv("FLEXBED_BENCH_PROFILE", "quick")
    assert quick_profile() is QUICK
    monkeypatch.setenv("FLEXBED_BENCH_PROFILE", "test")
    assert quick_profile() is TEST_PROFILE and TEST_PROFILE.auto_tolerance == 0.02
    assert replace(TEST_PROFILE, auto_tolerance=0.005) == QUICK


def test_sections_are_a_named_list():
    names = [s.name for s in SECTIONS]
    assert names[:3] == ["rhs", "integrators", "aims"] and len(set(names)) == len(names)
    with pytest.raises(ValueError, match="unknown section"):
        write_report("unused", sections=["nonsense"])


@pytest.mark.slow
def test_bench_rigid_sub_report_through_the_command(tmp_path, capsys, monkeypatch):
    """Run from a project's root, bench writes into ./flexbed-bench and
    leaves docs/ (the project's own report) alone."""
    docs = tmp_path / "docs"
    docs.mkdir()
    (docs / "benchmarks-rigid.md").write_text("the project's report")
    (docs / "bench-integrators-rigid.png").write_bytes(PNG + b"tracked")
    monkeypatch.chdir(tmp_path)
    code = main(["bench", "rigid", "--quick", "--t-end", "0.2"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert (docs / "benchmarks-rigid.md").read_text() == "the project's report"
    assert (docs / "bench-integrators-rigid.png").read_bytes() == PNG + b"tracked"
    folder = tmp_path / "flexbed-bench"
    report = folder / "benchmarks-rigid.md"
    assert report.is_file() and (folder / "bench-integrators-rigid.png").is_file()
    assert not (folder / "benchmarks.md").exists()
    rows = [line for line in out.splitlines() if line.startswith("| ")
            and "integrator" not in line]
    assert {r.split("|")[1].strip() for r in rows} == {"rk4", "adams", "bdf", "radau", "dop853"}
    assert "flexbed bench rigid --quick --t-end 0.2" in report.read_text()


def test_bench_positionals_target_then_scene(capsys):
    from flexbed.commands.bench import target_and_scene
    assert target_and_scene("rigid", None) == ("rigid", None)
    assert target_and_scene("rigid", "s.toml") == ("rigid", "s.toml")
    assert target_and_scene("my.toml", None) == ("all", "my.toml")
    assert main(["bench", "nonsense"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "target 'nonsense' is not one of all, modes" in err[0]


def _frequency_section_times_modal_and_frf_on_both_beds(report):
    res = report.ctx.results["frequency"]
    assert "## The mounted system in the frequency domain" in report.path.read_text()
    rigid, flexible = res["rigid bed"], res["flexible bed, 6 modes"]
    assert (rigid["coordinates"], flexible["coordinates"]) == (18, 24)
    # 5 scene points (3, and 2 relative to the bed) × 3 axes, 12 mounts × 3 axes, the base
    assert rigid["outputs"] == flexible["outputs"] == 15 + 36 + 3
    assert flexible["adaptive_frequencies"] > 400


def _beds_section_puts_both_theories_against_the_3d_solid(report):
    from flexbed.bench.beds import SOLID, SOLID_IN_PLANE
    res = report.ctx.results["beds"]
    assert "## Beds as built" in report.path.read_text()
    kirchhoff, auto, mindlin = (res["matched"][r.label] for r in res["accuracy"])
    # the Mindlin default, element_size = "auto": within its tolerance of the solid (the
    # test profile's 2 %; the default 0.5 %: tests/test_accuracy.py)
    tol = report.ctx.profile.auto_tolerance
    assert tol == 0.02 and res["accuracy"][1].bed.accuracy.tolerance == tol
    assert all(abs(f / s - 1) < tol for f, s in zip(auto, SOLID)), auto
    assert kirchhoff[SOLID_IN_PLANE] is None                    # no in-plane mode
    err_k = [f / s - 1 for f, s in zip(kirchhoff, SOLID) if f is not None]
    err_m = [f / s - 1 for f, s in zip(mindlin, SOLID)]
    # the shell theory removes the torsion error (issue 14: +4.2 %, +4.3 %)
    assert err_k[2] > 0.04 and err_k[4] > 0.04 and err_m[2] < 0.012 and err_m[4] < 0.012
    assert abs(err_m[SOLID_IN_PLANE]) < 0.002 and all(0 < e < 0.012 for e in err_m)
    grid, quads, tris, split = res["size"]
    # the same grid read from a file as quads: the same model
    assert quads.elements == grid.elements and np.allclose(
        quads.bed.modes.frequency, grid.bed.modes.frequency, rtol=1e-9)
    # two triangles per quad, the triangle element: the same bed on its own nodes
    # (a coarse 10 x 20 grid halved: within 3 % of the 3D solid, from above)
    assert tris.elements == 2 * 10 * 20 and tris.dofs == 5 * 11 * 21
    err_t = tris.bed.modes.frequency[:6] / np.array(SOLID[:6]) - 1
    assert np.all((err_t > 0) & (err_t < 0.03)), err_t
    # the same triangles split in three quads each (the route before)
    assert split.elements == 3 * 2 * 10 * 20
    assert np.allclose(split.bed.modes.frequency[:6], grid.bed.modes.frequency[:6], rtol=0.003)


def _beds_section_meets_the_stiffened_bed_s_tolerance(report):
    """The stiffened bed with element_size = "auto" (the test profile's 2 %
    tolerance on the discretisation error met), every one of its first ten
    modes within that of the solid. At the default 0.5 % (0.0492 m), within
    0.5 %: tests/test_stiffener_model.py, on ``stiffened_run(1)`` itself."""
    run, err = report.ctx.results["beds"]["stiffened"]
    acc, tol = run.bed.accuracy, report.ctx.profile.auto_tolerance
    assert acc.tolerance == tol and acc.worst <= tol
    assert "stiffeners along mesh lines" in acc.mesh
    assert np.all(np.abs(err) < tol), err


CHECKS = (_files_the_report_did_not_write_are_left_alone,
          _report_and_every_figure_are_written,
          _every_integrator_ran_on_every_quick_case,
          _reference_is_far_more_accurate_than_the_ladders,
          _rk4_converges_at_fourth_order,
          _truncation_error_falls_as_modes_are_kept,
          _mesh_error_falls_with_refinement,
          _first_order_invariants_differ_slightly_from_full,
          _aims_name_the_fastest_setting_reaching_each_error,
          _settings_over_budget_are_skipped_with_the_prediction,
          _frequency_section_times_modal_and_frf_on_both_beds,
          _beds_section_puts_both_theories_against_the_3d_solid,
          _beds_section_meets_the_stiffened_bed_s_tolerance)


@pytest.mark.slow
def test_the_quick_report(tmp_path, monkeypatch):
    """One quick report (test profile, about a minute of CPU), built once and
    checked by every function of CHECKS: one test rather than a module
    fixture, which each pytest-xdist worker would build again."""
    report = _build_report(tmp_path, monkeypatch)
    failed = []
    for check in CHECKS:            # every check runs; the failures are reported together
        try:
            check(report)
        except AssertionError as exc:
            failed.append(f"{check.__name__[1:]}: {exc}")
    assert not failed, "\n".join(failed)


def test_a_section_that_raises_leaves_the_others_and_one_line(tmp_path, monkeypatch, capsys):
    """A section's internal fault: the report is written with the other
    sections and, in the failed one's place, the error and its traceback;
    ``flexbed bench`` then ends with one line naming it, exit 1 (it ended
    with a traceback and no report before)."""
    from flexbed.bench import report as bench_report
    from flexbed.bench.report import Section
    from flexbed.commands import bench as bench_command

    def broken(ctx):
        raise ValueError("a bug in the section")

    sections = [Section("rhs", lambda ctx: "## First\n\nfine"), Section("integrators", broken),
                Section("aims", lambda ctx: "## Third\n\nfine too")]
    monkeypatch.setattr(bench_report, "SECTIONS", sections)
    monkeypatch.setitem(bench_command.TARGETS, "rigid", (["rhs", "integrators", "aims"], None))
    out = tmp_path / "b"
    assert main(["bench", "rigid", "--quick", "-o", str(out)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1] == (f"flexbed bench: 1 section failed (integrators): ValueError: a bug in the "
                       f"section; the report holds the other sections and the traceback: "
                       f"{out / 'benchmarks-rigid.md'}")
    assert not any("Traceback" in line for line in err)
    text = (out / "benchmarks-rigid.md").read_text()
    assert "## First" in text and "## Third" in text
    assert "## Section integrators: failed" in text and "Traceback (most recent call last)" in text

"""The worked shock verdict (docs/shock-verdict.md): its scene, its script,
whose output the page quotes, and its ``flexbed bench verdict`` entry."""

from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

from flexbed.bench.verdict import skid_scene
from flexbed.cli import main

ROOT = Path(__file__).resolve().parents[1]
PAGE = (ROOT / "docs" / "shock-verdict.md").read_text()


def test_the_skid_scene_carries_every_kind_of_limit():
    sf = skid_scene()
    lim = sf.limits
    shock = [lim.mount(f"S{i}") for i in range(1, 5)]
    assert all(m.compression == (0.035, 0.035, 0.05) and m.rated_load == 2000.0 for m in shock)
    assert all(m.stops[2].gap_compression == 0.04 and m.stops[:2] == (None, None)
               for m in shock)
    assert [m.stops for m in sf.scene.mounts[:4]] == [m.stops for m in shock]   # the dynamics'
    assert [lim.mount(f"P{i}").max_force for i in range(1, 5)] == [18000.0] * 4
    assert {f.body: f.given for f in lim.fragility} == {"pump": 15.0, "motor": 15.0}
    assert [c.name for c in lim.clearances] == ["pump to bulkhead"]


@pytest.mark.slow
def test_the_script_prints_what_the_page_quotes(tmp_path, forked_flexbed, forked_python):
    """The script run whole, forked from a server that has imported flexbed
    (conftest's ``forked_python``)."""
    cp = subprocess.run([forked_python, str(ROOT / "docs" / "shock_verdict.py")],
                        cwd=tmp_path, capture_output=True, text=True, timeout=600,
                        env=forked_flexbed)
    assert cp.returncode == 0, cp.stderr
    lines = cp.stdout.splitlines()
    ranking = lines[:8]          # the rigid verdict, what comes closest, what bottoms
    assert ranking[0] == "rigid bed: FAIL"
    assert "\n".join(ranking) in PAGE
    quoted = [ln for ln in lines if ln.startswith((
        "| all |", "| S1 | peak force", "| S1 | bump-stop contacts", "| S1 | peak contact",
        "| P2 | peak force", "| pump top", "| pump to bulkhead"))]
    assert len(quoted) == 7
    for ln in quoted:
        assert ln in PAGE, ln
    reasons = [ln.split(": ", 1)[1] for ln in lines if ln.startswith("rigid: ")]
    assert reasons and all(f"- {r}" in PAGE for r in reasons)
    assert not any(ln.startswith(("flexible: ", "damped: ")) for ln in lines)   # they pass


@pytest.mark.slow
def test_bench_verdict_reports_the_three_parts(tmp_path, capsys):
    assert main(["bench", "verdict", "--quick", "-o", str(tmp_path)]) == 0
    text = (tmp_path / "benchmarks-verdict.md").read_text()
    assert "## The shock verdict" in text and "verdict FAIL" in text
    for part in ("static equilibrium", "transient (", "2 contact events", "verdict (extremes",
                 "**total**", "without the bump stops ("):
        assert part in text

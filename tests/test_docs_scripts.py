"""The documentation's scripts print the figures their pages show
(issue 29): docs/validation.py's rows are the validation page's. Each
script runs whole, as ``python SCRIPT``, forked from the server that has
imported flexbed (conftest's ``forked_python``; one BLAS thread, as the
environment asks)."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_validation_page_shows_what_its_script_computes(tmp_path, forked_flexbed, forked_python):
    env = dict(forked_flexbed, OPENBLAS_NUM_THREADS="1")
    cp = subprocess.run([forked_python, str(ROOT / "docs" / "validation.py")], cwd=tmp_path,
                        capture_output=True, text=True, timeout=600, env=env)
    assert cp.returncode == 0, cp.stderr[-2000:]
    page = (ROOT / "docs" / "validation.md").read_text().replace("−", "-")
    rows = [r for r in cp.stdout.splitlines() if r.startswith("| ") and "---" not in r]
    assert len(rows) == 4
    statics, mindlin, energy = (r.replace("−", "-") for r in rows[1:])
    assert statics in page and mindlin in page
    # the energy drift is round-off: its order of magnitude is the page's
    drift = float(energy.split("drift ")[1].split()[0])
    assert drift < 1e-9
    assert energy.split("drift ")[0] in page
    assert not list(tmp_path.iterdir())          # the script leaves nothing behind


def _run_script(python: str, env: dict, name: str, cwd: Path, *args: str) -> str:
    """``python docs/NAME ARGS`` with one BLAS thread, by ``python`` (conftest's
    ``forked_python``, in its environment ``env``); its stdout."""
    cp = subprocess.run([python, str(ROOT / "docs" / name), *args], cwd=cwd,
                        capture_output=True, text=True, timeout=900,
                        env=dict(env, OPENBLAS_NUM_THREADS="1"))
    assert cp.returncode == 0, cp.stderr[-2000:]
    return cp.stdout


def _shown_output(page: str, command: str) -> list[str]:
    """The lines of the plain block that follows ``command``'s console block
    on ``page``, without the rows the page elides (``...``)."""
    text = (ROOT / "docs" / page).read_text()
    after = text.split(f"$ {command}\n", 1)[1].split("```\n", 1)[1]   # past its console block
    block = re.search(r"^```\n(.*?)^```", after, flags=re.S | re.M).group(1)
    return [ln for ln in block.splitlines() if ln.strip() and ln.strip() != "..."]


@pytest.mark.slow
def test_random_vibration_page_shows_what_its_script_prints(tmp_path, forked_flexbed,
                                                           forked_python):
    out = _run_script(forked_python, forked_flexbed, "random_vibration.py", tmp_path,
                      "random-out").splitlines()
    shown = _shown_output("random-vibration.md", "python docs/random_vibration.py random-out")
    assert len(shown) >= 15
    first = shown[0].split("; solve ")[0]
    assert out[0].split("; solve ")[0] == first          # the solve time varies from run to run
    for row in shown[1:]:
        assert row in out, row
    names = {p.name for p in (tmp_path / "random-out").iterdir()}
    assert {"random-lee1999.h5", "random-lee1999-acceleration.png",
            "random-lee1999-deflection.png"} <= names


@pytest.mark.slow
def test_the_optimisation_tutorial_runs_on_a_small_budget(tmp_path, forked_flexbed,
                                                          forked_python):
    out = _run_script(forked_python, forked_flexbed, "optimize.py", tmp_path, "try-out",
                      "--max-evaluations", "4")
    heads = [ln for ln in out.splitlines() if " bed: " in ln]
    assert [h.split(" bed:")[0] for h in heads] == ["rigid", "flexible"], out
    for tag in ("rigid", "flexible"):
        folder = tmp_path / "try-out" / f"optimize-out-{tag}"
        assert {"evaluations.csv", "optimum.toml", "comparison.md", "convergence.png",
                "transmissibility.png"} <= {p.name for p in folder.iterdir()}
        rows = (folder / "evaluations.csv").read_text().splitlines()
        assert len(rows) >= 1 + 4                      # header and at least the budget
        assert (tmp_path / "try-out" / f"optimize-convergence-{tag}.png").is_file()
    assert "$ python docs/optimize.py try-out --max-evaluations 4" in (
        ROOT / "docs" / "optimize.md").read_text()

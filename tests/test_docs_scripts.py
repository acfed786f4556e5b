"""The documentation's scripts print the figures their pages show
(issue 29): docs/validation.py's rows are the validation page's."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_validation_page_shows_what_its_script_computes(tmp_path):
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    cp = subprocess.run([sys.executable, str(ROOT / "docs" / "validation.py")], cwd=tmp_path,
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

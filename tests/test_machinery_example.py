"""The worked example of docs/machinery-loads.md runs and gives the figures
the page quotes (so the page cannot drift from the code), and the page's
command lines run on the scene it wrote."""

import importlib.util
import subprocess
from pathlib import Path

import numpy as np
import pytest

from doc_pages import commands

EXAMPLE = Path(__file__).resolve().parents[1] / "docs" / "machinery_loads.py"


@pytest.mark.slow
def test_the_machinery_example_gives_the_documented_levels(tmp_path, capsys, forked_flexbed):
    spec = importlib.util.spec_from_file_location("machinery_loads", EXAMPLE)
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    forces = example.main(tmp_path, tmp_path / "example.png")
    rigid, flexible = forces.values()
    il = flexible.insertion_loss(rigid)
    bands = list(rigid.bands.nominal)
    # the page's table: 25 Hz −8.2 / 7.5 dB (IL −15.7), 63 Hz −48.3 / −79.5 dB (IL 31.3)
    b25, b63 = bands.index(25.0), bands.index(63.0)
    assert np.allclose([rigid.band_levels[b25, 2], flexible.band_levels[b25, 2]], [-8.2, 7.5],
                       atol=0.05)
    assert np.allclose([il[b25, 2], il[b63, 2]], [-15.7, 31.3], atol=0.05)
    assert (tmp_path / "example.png").stat().st_size > 10_000
    # the page's command lines, in the folder the example filled (its machinery.toml)
    page = EXAMPLE.parent / "machinery-loads.md"
    lines = commands(page.read_text())
    assert len(lines) >= 4
    for cmd, expected in lines:
        cp = subprocess.run(["bash", "-c", "set -o pipefail; " + cmd], cwd=tmp_path,
                            env=forked_flexbed, capture_output=True, text=True, timeout=600)
        assert cp.returncode == expected, f"`{cmd}` exited {cp.returncode}:\n{cp.stderr[-2000:]}"
    assert 'model = "rigid"' in (tmp_path / "machinery-rigid.toml").read_text()

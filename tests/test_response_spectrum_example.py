"""The worked example of docs/response-spectrum.md: its script prints the
tables the page quotes, and the library calls it uses refuse bad input in
one line."""

import subprocess
from importlib import resources
from pathlib import Path

import pytest

import flexbed
from flexbed.errors import InputError

ROOT = Path(__file__).resolve().parents[1]
PAGE = (ROOT / "docs" / "response-spectrum.md").read_text()
SPECTRUM = ROOT / "docs" / "response-spectrum-deck.toml"


@pytest.mark.slow
def test_the_script_prints_what_the_page_quotes(tmp_path, forked_flexbed, forked_python):
    """The script run whole, forked from a server that has imported flexbed
    (conftest's ``forked_python``)."""
    cp = subprocess.run([forked_python, str(ROOT / "docs" / "response_spectrum.py"),
                         str(tmp_path)], cwd=tmp_path, capture_output=True, text=True,
                        timeout=900, env=forked_flexbed)
    assert cp.returncode == 0, cp.stderr
    rows = [ln for ln in cp.stdout.splitlines() if ln.startswith((
        "| M1 d3 |", "| M5 d3 |", "| M9 d3 |", "| M1 f3 |", "| A top uz |", "| base FZ |",
        "| A top az |", "| bed centre az |", "| bed centre uz |", "| A top uy |",
        "| A top ay |", "| M5 f3 |"))]
    assert len(rows) == 27                         # 8 per RSA table, 11 in the comparison
    for ln in rows:
        assert ln in PAGE, ln
    assert (tmp_path / "response-spectrum-motion.png").stat().st_size > 10_000


def test_api_refuses_bad_input_in_one_line():
    scene = flexbed.load_scene(resources.files("flexbed") / "scenes" / "skid.toml")
    with pytest.raises(InputError, match=r"damping = 0\.02 asked, but the spectrum is given "
                                         r"for damping = 0\.05"):
        flexbed.response_spectrum(scene, SPECTRUM, damping=0.02)
    with pytest.raises(InputError, match=r"flexbed\.response_spectrum: spectrum = 3 must be a "
                                         r"design spectrum file"):
        flexbed.response_spectrum(scene, 3)
    with pytest.raises(InputError, match=r"no spectrum for axis x \(it gives z\)"):
        flexbed.synthesise(SPECTRUM, axis="x")
    with pytest.raises(InputError, match=r"flexbed\.synthesise: axis = 'w' must be one of"):
        flexbed.synthesise(SPECTRUM, axis="w")

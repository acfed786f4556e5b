"""The README and the documentation site are true in every command line and
code block they show, and the site builds without a warning (issues 11, 29).

Each page (the README and every Markdown page under ``docs/``) is run on its
own, in its own scratch folder, as a reader following that page would: every
line of a ```console block that starts with ``$ `` is run in the order the
page shows them, with bash and this interpreter's ``flexbed`` first on the
PATH, and must exit with 0, or with N where the line ends in a comment
``# exit N`` (e.g. a verdict of FAIL). A ```toml block whose first line is a
comment naming a file (``# stiffness.toml``) is that file: it is written into
the scratch folder first, as the reader would save it. The project's
``pipeline`` and ``docs`` folders are linked into the scratch folder, so a
page may name a scene or an input shipped with flexbed by its path in the
repository (``pipeline/scenes/skid.toml``, ``docs/response-spectrum-deck.toml``);
a page writes its outputs into the scratch folder, never under ``docs/``.
Each ``flexbed`` of those lines runs whole, in a process of its own, but
forked from a server that has imported flexbed once (``command_server``,
conftest's ``forked_flexbed``): its arguments, folder, environment, streams
and exit status are its own; the second of imports is not paid again. The
tour's ``flexbed run``, ``compare`` and ``sweep``, which other tests check
too, run once per pytest run (conftest's ``shared_command``), forked from
that server too.
Every ```python block runs, in a folder holding the page's named files too,
as ``python -c BLOCK`` forked from that server too (``forked_python``).
The quick start
is exactly two commands, and ``.ci/run`` runs the second.
"""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from doc_pages import blocks, commands, named_files

pytestmark = pytest.mark.readme

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()
PAGES = [ROOT / "README.md"] + sorted((ROOT / "docs").rglob("*.md"))


def _id(page: Path) -> str:
    return str(page.relative_to(ROOT))


#: tutorial scripts that tests/test_docs_scripts.py runs and checks against
#: the output their page shows: not run a second time here
CHECKED_BY_THEIR_OWN_TEST = ("python docs/random_vibration.py", "python docs/optimize.py")
#: pages whose command lines run in the folder their worked example's own
#: test has filled (the example's outputs are their inputs)
PAGES_RUN_BY_THEIR_EXAMPLE = {"docs/machinery-loads.md": "tests/test_machinery_example.py"}
RUNNABLE = [p for p in PAGES if commands(p.read_text())
            and str(p.relative_to(ROOT)) not in PAGES_RUN_BY_THEIR_EXAMPLE]
WITH_PYTHON = [p for p in PAGES if blocks(p.read_text(), "python")]


def test_quick_start_is_two_commands_and_ci_runs_the_second():
    quick = README.split("## Quick start", 1)[1].split("\n## ", 1)[0]
    found = re.findall(r"^```bash\n(.*?)^```", quick, flags=re.S | re.M)
    assert len(found) == 2 and all(len(b.strip().splitlines()) == 1 for b in found)
    assert found[0].strip().endswith("&& flexbed run")
    ci = (ROOT / ".ci" / "run").read_text()
    assert found[1].strip() in ci


def test_readme_is_short_and_every_page_is_in_the_site():
    assert len(README.splitlines()) <= 250
    index = (ROOT / "docs" / "index.md").read_text()
    listed = set(re.findall(r"^([\w/.-]+)$", index, flags=re.M))
    pages = {str(p.relative_to(ROOT / "docs").with_suffix("")) for p in PAGES[1:]}
    assert pages - {"index"} <= listed, sorted(pages - {"index"} - listed)


def test_the_pages_show_runnable_commands():
    assert sum(len(commands(p.read_text())) for p in PAGES) >= 10
    assert all(name.endswith(".toml") for p in PAGES for name in named_files(p.read_text()))


def _env() -> dict:
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    return env


@pytest.mark.slow
@pytest.mark.parametrize("page", RUNNABLE, ids=_id)
def test_every_command_line_runs(page, tmp_path, shared_command, forked_flexbed):
    """A line that other tests check too (conftest's ``SHARED_COMMANDS``:
    the tour's ``flexbed run``, ``compare`` and ``sweep``) is run once per
    pytest run, the same way, in a folder of its own; its outputs are copied
    here for the lines after."""
    text = page.read_text()
    for name, body in named_files(text).items():
        (tmp_path / name).write_text(body)
    for shipped in ("pipeline", "docs"):
        (tmp_path / shipped).symlink_to(ROOT / shipped)
    env = forked_flexbed
    for cmd, expected in commands(text):
        if cmd.startswith(CHECKED_BY_THEIR_OWN_TEST):
            continue
        cp = shared_command(cmd)
        if cp is not None:
            for made in cp.cwd.iterdir():
                copy = shutil.copytree if made.is_dir() else shutil.copy2
                copy(made, tmp_path / made.name)
        else:
            cp = subprocess.run(["bash", "-c", "set -o pipefail; " + cmd], cwd=tmp_path,
                                env=env, capture_output=True, text=True, timeout=600)
        assert cp.returncode == expected, (
            f"{_id(page)}: `{cmd}` exited {cp.returncode}, not {expected}:\n{cp.stderr[-2000:]}")


@pytest.mark.slow
@pytest.mark.parametrize("page", WITH_PYTHON, ids=_id)
def test_every_python_block_runs(page, tmp_path, forked_flexbed, forked_python):
    """Each block run as ``python -c BLOCK``, forked from the server that has
    imported flexbed (conftest's ``forked_python``)."""
    text = page.read_text()
    for name, body in named_files(text).items():     # the page's files, as for its commands
        (tmp_path / name).write_text(body)
    for shipped in ("pipeline", "docs"):
        (tmp_path / shipped).symlink_to(ROOT / shipped)
    for code in blocks(text, "python"):
        cp = subprocess.run([forked_python, "-c", code], cwd=tmp_path, capture_output=True,
                            text=True, timeout=600, env=forked_flexbed)
        assert cp.returncode == 0, f"{_id(page)}: python block failed:\n{code}\n{cp.stderr[-2000:]}"


@pytest.mark.slow
def test_the_site_builds_without_a_warning(tmp_path):
    sphinx = shutil.which("sphinx-build", path=str(Path(sys.executable).parent))
    assert sphinx, "sphinx-build is a test extra: pip install '.[test]'"
    cp = subprocess.run([sphinx, "-W", "--keep-going", "-q", "-b", "html", str(ROOT / "docs"),
                         str(tmp_path / "html")], capture_output=True, text=True, timeout=900,
                        env=_env())
    assert cp.returncode == 0, cp.stderr[-4000:]
    assert (tmp_path / "html" / "index.html").is_file()
    assert (tmp_path / "html" / "reference" / "cli.html").is_file()

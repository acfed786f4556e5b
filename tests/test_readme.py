"""The README is true in every command line it shows (issue 11).

Every line of a ```console block that starts with ``$ `` is run, in the
order the README shows them, in one scratch folder (as a reader following
the tour would), with bash and this interpreter's ``flexbed`` first on the
PATH; each must exit with 0. A ```toml block whose first line is a comment
naming a file (``# stiffness.toml``) is that file: it is written into the
scratch folder first, as the reader would save it. The quick start is exactly two commands, and
``.ci/run`` runs the second.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.readme

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()


def blocks(lang: str) -> list[str]:
    return re.findall(rf"^```{lang}\n(.*?)^```", README, flags=re.S | re.M)


def commands() -> list[str]:
    cmds = []
    for block in blocks("console"):
        lines = block.splitlines()
        i = 0
        while i < len(lines):
            line = lines[i]
            if line.startswith("$ "):
                cmd = line[2:]
                while cmd.endswith("\\") and i + 1 < len(lines):      # continued lines
                    i += 1
                    cmd = cmd[:-1] + " " + lines[i].strip()
                cmds.append(cmd)
            i += 1
    return cmds


def test_quick_start_is_two_commands_and_ci_runs_the_second():
    quick = README.split("## Quick start", 1)[1].split("\n## ", 1)[0]
    found = re.findall(r"^```bash\n(.*?)^```", quick, flags=re.S | re.M)
    assert len(found) == 2 and all(len(b.strip().splitlines()) == 1 for b in found)
    assert found[0].strip().endswith("&& flexbed run")
    ci = (ROOT / ".ci" / "run").read_text()
    assert found[1].strip() in ci


def named_files() -> dict[str, str]:
    """The ```toml blocks that name their file on their first line."""
    files = {}
    for block in blocks("toml"):
        m = re.match(r"# ([\w.-]+\.toml)\n", block)
        if m:
            files[m.group(1)] = block
    return files


@pytest.mark.slow
def test_every_command_line_runs(tmp_path):
    for name, text in named_files().items():
        (tmp_path / name).write_text(text)
    cmds = commands()
    assert len(cmds) >= 10
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"
    for cmd in cmds:
        cp = subprocess.run(["bash", "-c", "set -o pipefail; " + cmd], cwd=tmp_path, env=env,
                            capture_output=True, text=True, timeout=600)
        assert cp.returncode == 0, f"README: `{cmd}` exited {cp.returncode}:\n{cp.stderr[-2000:]}"


@pytest.mark.slow
def test_every_python_block_runs(tmp_path):
    found = blocks("python")
    assert found
    for code in found:
        cp = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True,
                            text=True, timeout=600)
        assert cp.returncode == 0, f"README python block failed:\n{code}\n{cp.stderr[-2000:]}"

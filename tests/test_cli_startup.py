"""The command line starts light: a command imports what it needs only
(checked in fresh interpreters through ``sys.modules``, not by timing), the
help still lists every command and each command's options, and a closed
output pipe ends a command quietly with status 141."""

import io
import subprocess
import sys

import pytest

from flexbed.cli import COMMANDS, EXIT_PIPE, build_parser, main

HEAVY = ("numba", "scipy", "matplotlib", "h5py", "skfem", "meshio", "dask", "distributed")

#: runs flexbed's main() in a fresh interpreter, then prints on stderr the
#: heavy packages it imported
PROBE = """
import sys
from flexbed.cli import main
try:
    code = main(sys.argv[1:])
except SystemExit as exc:
    code = exc.code
heavy = [m for m in {heavy!r} if m in sys.modules]
sys.stderr.write("\\nIMPORTED:" + ",".join(heavy) + "\\n")
sys.exit(code)
"""


def probe(*argv, cwd=None, watch=HEAVY):
    """(exit code, stdout, the modules of ``watch`` imported) of ``flexbed argv``."""
    p = subprocess.run([sys.executable, "-c", PROBE.format(heavy=watch), *argv], cwd=cwd,
                       capture_output=True, text=True, timeout=300)
    line = [s for s in p.stderr.splitlines() if s.startswith("IMPORTED:")]
    assert line, p.stderr
    imported = set(filter(None, line[-1][len("IMPORTED:"):].split(",")))
    return p.returncode, p.stdout, imported


@pytest.mark.parametrize("argv", [["--version"], ["--help"], ["scene"], []])
def test_version_help_and_scene_import_nothing_heavy(argv):
    code, out, imported = probe(*argv)
    assert imported == set(), imported
    assert code == (2 if not argv else 0)
    if argv == ["--version"]:
        assert out.startswith("flexbed ")
    if argv == ["scene"]:
        assert "[[mount]]" in out


@pytest.mark.slow
def test_simulate_does_not_import_plotting_or_fem(tmp_path):
    code, out, imported = probe("simulate", "-o", str(tmp_path / "r.h5"), "--t-end", "0.05",
                                "--no-progress", cwd=tmp_path)
    assert code == 0 and "wrote" in out
    assert not imported & {"matplotlib", "skfem", "meshio", "dask", "distributed"}, imported


@pytest.mark.slow
def test_a_whole_simulate_of_the_built_in_scene_skips_scipy_integrate_and_interpolate(tmp_path):
    """The built-in scene's run (auto → dop853, curve data through our own
    spline) needs neither scipy.integrate's package (the DOP853
    coefficients are flexbed's own) nor scipy.interpolate: the
    two cost about 0.3 s of CPU to import."""
    code, out, imported = probe("simulate", "-o", str(tmp_path / "r.h5"), "--no-progress",
                                cwd=tmp_path, watch=("scipy.integrate", "scipy.interpolate",
                                                     "scipy.optimize", "h5py"))
    assert code == 0 and "wrote" in out and "dop853" in out
    assert imported == {"h5py"}, imported   # h5py: the probe sees imports


def test_help_lists_every_command_and_each_commands_options(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--help"])
    assert exc.value.code == 0
    out = capsys.readouterr().out
    for name, summary in COMMANDS.items():
        assert name in out and summary in out
    expected = {"simulate": "--integrator", "compare": "--t-end", "run": "--integrator",
                "post": "--modes-file", "bench": "--quick", "modes": "--fmax",
                "static": "--tol", "scene": "--output", "modal": "--equilibrium",
                "frf": "--relative-to", "random": "--psd",
                "srs": "--per-octave", "qualify": "--results",
                "sweep": "--scheduler", "transmitted": "--reference",
                "optimize": "--scheduler", "rsa": "--spectrum", "synthesise": "--band",
                "stress": "--xdmf"}
    assert set(expected) == set(COMMANDS)
    for name, option in expected.items():
        with pytest.raises(SystemExit):
            main([name, "--help"])
        assert option in capsys.readouterr().out, name


def test_a_parser_for_one_command_knows_the_others_by_name():
    parser = build_parser(["post"])
    args = parser.parse_args(["post", "r.h5", "--mounts"])
    assert args.command == "post" and args.mounts


class ClosedPipe(io.StringIO):
    """A stdout whose reader went away."""

    def write(self, s):
        raise BrokenPipeError(32, "Broken pipe")

    def flush(self):
        raise BrokenPipeError(32, "Broken pipe")


def test_a_closed_pipe_ends_any_command_with_141(monkeypatch, capsys):
    monkeypatch.setattr(sys, "stdout", ClosedPipe())
    assert main(["scene"]) == EXIT_PIPE
    assert main(["compare", "--t-end", "-1"]) == 2      # errors still go to stderr
    assert capsys.readouterr().err.count("\n") == 1


def test_a_closed_pipe_leaves_no_traceback():
    """``flexbed scene | head -0``: the reader is gone before the first write."""
    p = subprocess.Popen([sys.executable, "-m", "flexbed.cli", "scene"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    p.stdout.close()                          # no reader left
    err = p.stderr.read().decode()
    assert p.wait(timeout=60) == EXIT_PIPE
    assert err == ""

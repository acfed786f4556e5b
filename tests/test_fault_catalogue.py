"""The catalogue of bad inputs and faults (issue 12): every one ends in its
exit code and exactly one line on stderr naming the file, the entry or the
option, leaves no file behind in the folders involved (no ``.tmp``, no
partial output) and replaces nothing that was there.

Each case builds its inputs in the test's folder and gives the command
line; most run ``flexbed.cli.main`` in-process; the few where the process
matters (standard output on a full device, a file size limit, the compiled
cache's location) run a child process.
"""

from __future__ import annotations

import hashlib
import os
import resource
import signal
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import h5py
import numpy as np
import pytest

from flexbed.cli import main

from scene_text import body_on_four_mounts as scene

_DRIVE = """
[base]
motion = "driven"

[[base.drive]]
direction = "z"
"""


_SPECTRUM = ('damping = 0.05\nunits = "g"\n[z]\ndisplacement = 0.05\nvelocity = 1.5\n'
             'acceleration = 50.0\nband = [3.0, 300.0]\n')


@dataclass(frozen=True)
class Case:
    """One fault: ``setup(folder)`` makes the inputs in ``folder`` and
    returns the command line; ``code`` the exit code; ``words`` what the
    one line on stderr must hold; ``writes`` the files an exit 0 may add."""

    name: str
    setup: Callable[[Path], list]
    code: int
    words: tuple
    writes: tuple = ()


def _static(text: str | bytes, *more: str, out: str = "out/eq.h5", name: str = "s.toml"):
    def setup(d: Path) -> list:
        p = d / name
        p.write_bytes(text if isinstance(text, bytes) else text.encode())
        return ["static", str(p), "-o", str(d / out), *more]
    return setup


def _scene_case(name, code, words, **kw):
    return Case(name, _static(scene(**kw)), code, words)


def _extra_case(name, extra, words, code=2):
    return Case(name, _static(scene(extra=extra)), code, words)


def _with_files(files: dict, argv: Callable[[Path], list]):
    def setup(d: Path) -> list:
        for rel, content in files.items():
            p = d / rel
            p.parent.mkdir(parents=True, exist_ok=True)
            p.write_bytes(content if isinstance(content, bytes) else content.encode())
        return argv(d)
    return setup


def _curve_file(content: bytes):
    extra = _DRIVE + 'shape = "curve"\nfile = "drive.csv"\n'
    return _with_files({"s.toml": scene(extra=extra), "drive.csv": content},
                       lambda d: ["static", str(d / "s.toml"), "-o", str(d / "out/eq.h5")])


def _output(kind: str):
    """static with -o naming something that is not a plain new file."""
    def setup(d: Path) -> list:
        (d / "s.toml").write_text(scene())
        target = d / "target.h5"
        target.write_bytes(b"keep me")
        out = {
            "dir": lambda: (d / "adir").mkdir() or d / "adir",
            "device": lambda: Path(os.devnull),
            "symlink": lambda: (d / "link.h5").symlink_to(target) or d / "link.h5",
            "dangling": lambda: (d / "dangling.h5").symlink_to(d / "none.h5") or d / "dangling.h5",
            "fifo": lambda: os.mkfifo(d / "fifo.h5") or d / "fifo.h5",
            "input": lambda: d / "s.toml",
            "input-dotted": lambda: d / "sub" / ".." / "s.toml",
            "parent-is-file": lambda: target / "eq.h5",
            "folder-is-file": lambda: d / "target.h5" / "deeper" / "eq.h5",
        }[kind]()
        if kind == "input-dotted":
            (d / "sub").mkdir()
        return ["static", str(d / "s.toml"), "-o", str(out)]
    return setup


CASES = [
    # scene values out of range: overflow, underflow, huge integers
    _scene_case("mass-1e308", 2, ("s.toml", "mass = 1e+308", "out of range"), mass="1e308"),
    _scene_case("gravity-1e308", 2, ("s.toml", "gravity[2]", "out of range"), gravity="1e308"),
    _scene_case("mass-subnormal", 2, ("mass = 5e-324", "out of range"), mass="5e-324"),
    _scene_case("mass-huge-int", 2, ("mass", "out of range"), mass=str(10 ** 400)),
    _scene_case("k-2**63-1", 1, ("s.toml", "rounding", "double precision"), k=str(2 ** 63 - 1)),
    _scene_case("inertia-1e308", 2, ("inertia[0]", "out of range"), inertia="[1e308, 3.0, 4.0]"),
    _scene_case("inertia-triangle", 2, ("body 'mass'", "triangle inequality"),
                inertia="[1.0, 1.0, 4.0]"),
    _scene_case("inertia-not-definite", 2, ("body 'mass'", "positive definite"),
                inertia="[[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]]"),
    _scene_case("mass-negative", 2, ("mass = -50.0", "> 0"), mass="-50.0"),
    _scene_case("mass-zero", 2, ("mass = 0.0",), mass="0.0"),
    _scene_case("mass-string", 2, ("mass = '50'", "number"), mass='"50"'),
    _scene_case("mass-nan", 2, ("mass = nan", "finite"), mass="nan"),
    _scene_case("mass-inf", 2, ("mass = inf", "finite"), mass="inf"),
    _scene_case("mass-bool", 2, ("mass = True", "number"), mass="true"),
    _scene_case("k-zero", 2, ("mount 'M1'", "k[0] = 0.0"), k="0.0"),
    _scene_case("k-array", 2, ("mount 'M1'", "k[0]"), k="[1.0]"),
    _scene_case("gravity-string", 2, ("gravity[2]",), gravity='"down"'),
    _scene_case("point-out-of-range", 2, ("mount 'M1'", "point_j[2]", "out of range"),
                point_j_z="1e101"),
    _extra_case("step-count-300-digits", "[solver]\nt_end = 1" + "0" * 300 + "\n",
                ("solver", "t_end", "out of range")),
    _extra_case("static-tol-inf", "[solver]\nstatic_tol = inf\n", ("static_tol = inf",)),
    _extra_case("static-tol-negative", "[solver]\nstatic_tol = -1e-6\n", ("static_tol",)),
    _extra_case("output-dt-1e-12", "[solver]\noutput_dt = 1e-12\n",
                ("solver", "output_dt", "3e+12 output samples", "limit is 1e+07")),
    _extra_case("integrator-unknown", '[solver]\nintegrator = "euler"\n', ("integrator",)),
    _extra_case("solver-unknown-key", "[solver]\nfoo = 1\n", ("solver", "unknown key 'foo'")),
    _extra_case("top-unknown-key", "[banana]\nx = 1\n", ("unknown key 'banana'",)),
    _extra_case("sample-1e-12", _DRIVE + 'shape = "sinusoid"\namplitude = 1.0\nfrequency = 5.0\n'
                "duration = 1.0\nsample = 1e-12\n", ("base.drive 1", "sample", "limit is 1e+07")),
    _extra_case("drive-frequency-negative", _DRIVE + 'shape = "sinusoid"\namplitude = 1.0\n'
                "frequency = -5.0\n", ("base.drive 1", "frequency")),
    _extra_case("drive-unknown-direction", _DRIVE.replace('"z"', '"w"')
                + 'shape = "sinusoid"\namplitude = 1.0\nfrequency = 5.0\n', ("direction",)),
    _extra_case("point-unknown-body", '[[point]]\nname = "p"\nbody = "ghost"\n'
                "position = [0.0, 0.0, 0.0]\n", ("point 'p'", "ghost")),
    _extra_case("bed-nx-1e30", "[bed]\nnx = 1e30\n", ("bed", "nx")),
    _extra_case("bed-nx-10**30", f"[bed]\nnx = {10 ** 30}\n", ("bed", "nx")),
    _extra_case("bed-nx-10000-ny-10", "[bed]\nnx = 10000\nny = 10\n",
                ("bed", "nx = 10000, ny = 10", "degrees of freedom", "250,000")),
    _extra_case("bed-length-1e308", "[bed]\nlength_x = 1e308\n",
                ("bed", "length_x", "out of range")),
    _extra_case("bed-poisson-0.5", "[bed]\npoisson = 0.5\n", ("bed", "poisson")),
    Case("toml-nested-2000", _static("a = " + "[" * 2000 + "]" * 2000 + "\n"), 2,
         ("s.toml", "nested too deeply")),
    Case("toml-invalid", _static("[scene\nname = 1\n"), 2, ("s.toml", "not valid TOML")),
    Case("scene-not-utf8", _static(b"[scene]\nname = \"\xff\xfe\"\n"), 2, ("s.toml", "UTF-8")),
    Case("scene-missing", lambda d: ["static", str(d / "none.toml"), "-o", str(d / "o.h5")], 2,
         ("none.toml", "cannot read")),
    Case("scene-is-a-folder", lambda d: ["static", str(d), "-o", str(d / "o.h5")], 2,
         ("cannot read",)),
    Case("scene-no-body", _static("[scene]\nname = \"x\"\n"), 2, ("s.toml", "[[body]]")),
    Case("body-missing-mass", _static(scene().replace("mass = 50.0\n", "", 1)), 2,
         ("body 'mass'", "'mass' is required")),
    Case("body-name-line-break", _static(scene().replace('name = "mass"', 'name = "ma\\rss"', 1)),
         2, ("body 'ma\\rss'", "name = 'ma\\rss'", "control character")),
    Case("mount-unknown-law", _static(scene().replace('law = "linear"', 'law = "magic"', 1)), 2,
         ("mount 'M1'", "law = 'magic'")),
    Case("mount-unknown-body", _static(scene().replace('body_j = "mass"', 'body_j = "x"', 1)), 2,
         ("mount 'M1'", "body_j = 'x'")),
    Case("curve-not-utf8", _curve_file(b"t,v\n0,0\n\xff\xfe,1\n"), 2,
         ("s.toml", "base.drive 1", "drive.csv", "line 3", "UTF-8")),
    Case("curve-missing", _with_files({"s.toml": scene(extra=_DRIVE + 'shape = "curve"\n'
                                                        'file = "none.csv"\n')},
                                      lambda d: ["static", str(d / "s.toml"), "-o",
                                                 str(d / "out/eq.h5")]), 2,
         ("none.csv", "cannot read")),
    Case("curve-three-columns", _curve_file(b"0,0,0\n1,1,1\n"), 2, ("drive.csv", "3 columns")),
    Case("curve-text-row", _curve_file(b"0,0\n1,x\n"), 2, ("drive.csv", "line 2")),
    # command-line options
    Case("tol-inf", _static(scene(), "--tol", "inf"), 2, ("--tol = inf", "finite")),
    Case("tol-nan", _static(scene(), "--tol", "nan"), 2, ("--tol = nan",)),
    Case("tol-negative", _static(scene(), "--tol", "-1"), 2, ("--tol = -1.0",)),
    Case("tol-not-a-number", _static(scene(), "--tol", "abc"), 2, ("--tol", "abc")),
    Case("unknown-option", _static(scene(), "--frobnicate"), 2, ("--frobnicate",)),
    # outputs
    Case("out-directory", _output("dir"), 2, ("adir", "is a directory")),
    Case("out-device", _output("device"), 2, (os.devnull, "character device")),
    Case("out-symlink", _output("symlink"), 2, ("link.h5", "symbolic link")),
    Case("out-dangling-symlink", _output("dangling"), 2, ("dangling.h5", "symbolic link")),
    Case("out-fifo", _output("fifo"), 2, ("fifo.h5", "FIFO")),
    Case("out-is-the-scene", _output("input"), 2, ("s.toml", "input file")),
    Case("out-is-the-scene-by-another-path", _output("input-dotted"), 2, ("s.toml", "input file")),
    Case("out-parent-is-a-file", _output("parent-is-file"), 2, ("target.h5", "cannot")),
    Case("out-grandparent-is-a-file", _output("folder-is-file"), 2, ("target.h5", "cannot")),
    Case("scene-out-exists", _with_files({"s.toml": "keep"},
                                         lambda d: ["scene", "-o", str(d / "s.toml")]), 2,
         ("s.toml", "already exists")),
    Case("scene-out-directory", lambda d: ["scene", "-o", str(d)], 2, ("already exists",)),
    Case("modes-out-is-the-scene",
         _with_files({"s.toml": scene()}, lambda d: ["modes", str(d / "s.toml"), "-o",
                                                     str(d / "s.toml")]), 2,
         ("s.toml", "input file")),
    Case("simulate-results-over-4-GiB",
         lambda d: ["simulate", "--output-dt", "1e-6", "-o", str(d / "r.h5"), "--no-progress"],
         2, ("3e+06 output samples", "GiB", "the limit is 4 GiB")),
    Case("simulate-output-dt-option-1e-12",
         _with_files({"s.toml": scene()}, lambda d: ["simulate", str(d / "s.toml"),
                                                     "--output-dt", "1e-12", "-o",
                                                     str(d / "r.h5")]), 2,
         ("output_dt = 1e-12", "3e+12 output samples", "limit is 1e+07")),
    Case("simulate-out-is-the-scene",
         _with_files({"s.toml": scene()}, lambda d: ["simulate", str(d / "s.toml"), "-o",
                                                     str(d / "s.toml")]), 2,
         ("s.toml", "input file")),
    Case("run-out-is-a-file",
         _with_files({"s.toml": scene(), "taken": "keep"},
                     lambda d: ["run", str(d / "s.toml"), "-o", str(d / "taken")]), 2,
         ("-o", "taken", "not a folder")),
    Case("compare-out-is-a-file",
         _with_files({"s.toml": scene(), "taken": "keep"},
                     lambda d: ["compare", str(d / "s.toml"), "-o", str(d / "taken")]), 2,
         ("-o", "taken", "not a folder")),
    # session 35: every numeric option under the scene's range rule, names never empty,
    # counts bounded, options that do nothing refused, side files checked as files
    Case("option-subnormal", _static(scene(), "--tol", "5e-324"), 2,
         ("--tol", "5e-324", "out of range")),
    Case("option-1e308", _with_files({"s.toml": scene()},
                                     lambda d: ["simulate", str(d / "s.toml"), "-o",
                                                str(d / "r.h5"), "--t-end", "1e308"]), 2,
         ("--t-end", "1e308", "out of range")),
    Case("output-empty-name", _with_files({"s.toml": scene()},
                                          lambda d: ["frf", str(d / "s.toml"), "-o", "",
                                                     "--no-plots"]), 2,
         ("-o", "empty name")),
    Case("frf-force-at-with-a-base-input",
         _with_files({"s.toml": scene()},
                     lambda d: ["frf", str(d / "s.toml"), "-o", str(d / "o/f"), "--no-plots",
                                "--force-at", "mass:0,0,0"]), 2,
         ("--force-at", "applies to --input force only")),
    Case("sweep-workers-1e6", _with_files({"st.toml": "[study]\n"},
                                          lambda d: ["sweep", str(d / "st.toml"), "--workers",
                                                     "1000000"]), 2,
         ("--workers", "from 1 to 1,024")),
    Case("sweep-batch-0", _with_files({"st.toml": "[study]\n"},
                                      lambda d: ["sweep", str(d / "st.toml"), "--batch", "0"]),
         2, ("--batch", "from 1 to 10,000")),
    Case("optimize-workers-5000", _with_files({"o.toml": "[optimize]\n"},
                                              lambda d: ["optimize", str(d / "o.toml"),
                                                         "--workers", "5000"]), 2,
         ("--workers", "from 1 to 1,024")),
    Case("bench-t-end-0", lambda d: ["bench", "--quick", "-o", str(d / "b"), "--t-end", "0"], 2,
         ("--t-end 0", "from 0.02 s")),
    Case("bench-t-end-nan", lambda d: ["bench", "--quick", "-o", str(d / "b"), "--t-end", "nan"],
         2, ("--t-end nan",)),
    Case("bench-t-end-1e9", lambda d: ["bench", "--quick", "-o", str(d / "b"), "--t-end", "1e9"],
         2, ("--t-end 1e+09", "100000 s")),
    Case("psd-file-is-a-fifo",
         _with_files({"s.toml": scene()},
                     lambda d: os.mkfifo(d / "p.toml") or ["random", str(d / "s.toml"), "--psd",
                                                           str(d / "p.toml"), "-o",
                                                           str(d / "o/r"), "--no-plots"]), 2,
         ("p.toml", "cannot read the PSD file", "FIFO")),
    Case("psd-level-1e308",
         _with_files({"s.toml": scene(), "p.toml": "[z]\ntable = [[5, 1e308], [10, 1]]\n"},
                     lambda d: ["random", str(d / "s.toml"), "--psd", str(d / "p.toml"), "-o",
                                str(d / "o/r"), "--no-plots"]), 2,
         ("p.toml", "[z] table row 1", "level 1e+308", "out of range")),
    Case("psd-frequency-past-10-MHz",
         _with_files({"s.toml": scene(), "p.toml": "[z]\ntable = [[5, 0.01], [1e8, 0.01]]\n"},
                     lambda d: ["random", str(d / "s.toml"), "--psd", str(d / "p.toml"), "-o",
                                str(d / "o/r"), "--no-plots"]), 2,
         ("p.toml", "row 2", "frequency 1e+08 Hz", "1e+07")),
    Case("psd-coherence-one-number-list",
         _with_files({"s.toml": scene(), "p.toml": "[z]\ntable = [[5, 0.01], [100, 0.01]]\n"
                      "[x]\ntable = [[5, 0.01], [100, 0.01]]\n[coherence]\nxz = [0.5]\n"},
                     lambda d: ["random", str(d / "s.toml"), "--psd", str(d / "p.toml"), "-o",
                                str(d / "o/r"), "--no-plots"]), 2,
         ("p.toml", "xz = [0.5]", "[re, im]")),
    Case("spectrum-file-is-a-fifo",
         _with_files({"s.toml": scene()},
                     lambda d: os.mkfifo(d / "sp.toml") or ["rsa", str(d / "s.toml"),
                                                            "--spectrum", str(d / "sp.toml"),
                                                            "-o", str(d / "o/r")]), 2,
         ("sp.toml", "cannot read the spectrum file", "FIFO")),
    Case("rsa-damping-nan",
         _with_files({"s.toml": scene(), "sp.toml": _SPECTRUM},
                     lambda d: ["rsa", str(d / "s.toml"), "--spectrum", str(d / "sp.toml"),
                                "-o", str(d / "o/r"), "--damping", "nan"]), 2,
         ("sp.toml", "damping = nan")),
    Case("synthesise-seed-negative",
         _with_files({"sp.toml": _SPECTRUM},
                     lambda d: ["synthesise", str(d / "sp.toml"), "-o", str(d / "o/s"),
                                "--seed", "-1"]), 2,
         ("--seed -1", "from 0")),
    # accepted, with what the README promises
    Case("scene-out-missing-folder", lambda d: ["scene", "-o", str(d / "new" / "dir" / "x.toml")],
         0, (), writes=("new/dir/x.toml",)),
    Case("mount-point-far-from-its-body",
         _static(scene().replace("-0.2]", "-1000.0]", 1)), 0,
         ("warning", "s.toml", "mount 'M1'", "point_j", "body 'mass'"), writes=("out/eq.h5",)),
]


def _snapshot(folder: Path) -> dict:
    """Every regular file under ``folder`` (not following links) and a hash
    of its content."""
    out = {}
    for root, _, files in os.walk(folder):
        for f in files:
            p = Path(root) / f
            if p.is_file() and not p.is_symlink():
                out[p.relative_to(folder).as_posix()] = hashlib.sha256(p.read_bytes()).hexdigest()
    return out


def _check_folder(folder: Path, before: dict, writes: tuple) -> None:
    after = _snapshot(folder)
    assert not [f for f in after if f.endswith(".tmp")], after
    for f, digest in before.items():
        assert after.get(f) == digest, f"{f} was replaced or removed"
    assert set(after) - set(before) == set(writes)


@pytest.mark.parametrize("case", CASES, ids=[c.name for c in CASES])
def test_fault(case, tmp_path, capsys):
    argv = case.setup(tmp_path)
    before = _snapshot(tmp_path)
    try:
        code = main(argv)
    except SystemExit as exc:            # argparse's own refusals
        code = exc.code
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert code == case.code, err
    if case.code == 0 and not case.words:
        assert lines == []
    else:
        assert len(lines) == 1, err
        assert len(lines[0]) < 400, lines[0]
        for w in case.words:
            assert w in lines[0], (w, lines[0])
    _check_folder(tmp_path, before, case.writes)


def test_the_catalogue_holds_sixty_faults():
    assert len(CASES) + len(_RESULTS_FAULTS) + len(_POST_OPTIONS) + 4 >= 60


# --- results files given to post -------------------------------------------------------

@pytest.fixture(scope="module")
def results_file(tmp_path_factory):
    folder = tmp_path_factory.mktemp("catalogue")
    (folder / "s.toml").write_text(scene())
    out = folder / "r.h5"
    assert main(["simulate", str(folder / "s.toml"), "-o", str(out), "--t-end", "0.01",
                 "--output-dt", "0.005", "--no-progress"]) == 0
    return out


def _replace(name, value):
    def change(f):
        attrs = dict(f[name].attrs)
        del f[name]
        d = f.create_dataset(name, data=value)
        d.attrs.update(attrs)
    return change


def _delete(name):
    def change(f):
        del f[name]
    return change


def _schema(f):
    f.attrs["schema"] = "flexbed.other"


_RESULTS_FAULTS = {
    "time-as-strings": (_replace("time", np.array([b"0", b"0.005", b"0.01"], dtype=object)
                                 .astype(h5py.string_dtype())), ("'time'", "text")),
    "position-as-strings": (_replace("bodies/position", "somewhere"),
                            ("'bodies/position'", "text")),
    "zero-samples": (_replace("time", np.zeros(0)), ("'time'", "no samples")),
    "position-wrong-shape": (_replace("bodies/position", np.zeros((3, 2, 2))),
                             ("'bodies/position'", "shape")),
    "velocity-one-sample-short": (_replace("bodies/velocity", np.zeros((2, 2, 3))),
                                  ("'bodies/velocity'", "shape")),
    "force-wrong-shape": (_replace("mounts/force", np.zeros((3, 4))), ("'mounts/force'", "shape")),
    "time-decreasing": (_replace("time", np.array([0.01, 0.005, 0.0])), ("'time'",)),
    "time-nan": (_replace("time", np.array([0.0, np.nan, 0.01])), ("'time'",)),
    "euler-missing": (_delete("bodies/euler_parameters"), ("'bodies/euler_parameters'",)),
    "other-schema": (_schema, ("schema",)),
}


@pytest.mark.parametrize("fault", list(_RESULTS_FAULTS))
def test_post_refuses_a_damaged_results_file(fault, results_file, tmp_path, capsys):
    change, words = _RESULTS_FAULTS[fault]
    bad = tmp_path / "bad.h5"
    bad.write_bytes(results_file.read_bytes())
    with h5py.File(bad, "r+") as f:
        change(f)
    before = _snapshot(tmp_path)
    code = main(["post", str(bad), "--mounts", "--csv", str(tmp_path / "csv")])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(err) == 1 and "bad.h5" in err[0], err
    for w in words:
        assert w in err[0], (w, err[0])
    _check_folder(tmp_path, before, ())


_SHOCK_OPTIONS = {   # session 35: extreme floats and outputs checked before the work
    "srs-fmin-subnormal": (["srs", "--fmin", "5e-324"], ("--fmin", "out of range")),
    "srs-fmin-below-1e-6": (["srs", "--fmin", "1e-9"], ("--fmin", "1e-06 Hz")),
    "srs-q-overdamped": (["srs", "--q", "0.4"], ("--q 0.4", "above 0.5")),
    "srs-hdf5-a-folder": (["srs", "--hdf5", "{d}"], ("is a directory",)),
    "srs-csv-a-file": (["srs", "--csv", "{d}/taken"], ("--csv", "taken", "not a folder")),
    "transmitted-fmax-half-hertz": (["transmitted", "--fmax", "0.5"],
                                    ("--fmax 0.5", "at least 1 Hz")),
    "transmitted-fmax-1e-50": (["transmitted", "--fmax", "1e-50"], ("--fmax 1e-50",)),
    "transmitted-plot-a-folder": (["transmitted", "--plot", "{d}"], ("is a directory",)),
    "srs-modes-file-of-a-rigid-run": (["srs", "--modes-file", "{d}/taken"],
                                      ("--modes-file", "bed is rigid")),
    "post-modes-file-of-a-rigid-run": (["post", "--modes-file", "{d}/taken", "--mounts"],
                                       ("--modes-file", "bed is rigid")),
}


@pytest.mark.parametrize("fault", list(_SHOCK_OPTIONS))
def test_shock_commands_refuse_before_the_work(fault, results_file, tmp_path, capsys):
    """One line, no warning before it (the spectrum was not computed), nothing written."""
    argv, words = _SHOCK_OPTIONS[fault]
    (tmp_path / "taken").write_text("keep")
    before = _snapshot(tmp_path)
    more = [a.replace("{d}", str(tmp_path)) for a in argv[1:]]
    more += ["--point", "top=mass:0,0,0.1"] if argv[0] == "srs" else []
    try:
        code = main([argv[0], str(results_file), *more])
    except SystemExit as exc:            # argparse's own refusals
        code = exc.code
    _refused_in_one_line(code, capsys, words, tmp_path, before)


def _refused_in_one_line(code, capsys, words: tuple, folder: Path, before: dict) -> None:
    """Exit 2, one stderr line holding every one of ``words``, and
    ``folder`` as it was (``before``: its :func:`_snapshot`)."""
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(err) == 1, err
    for w in words:
        assert w in err[0], (w, err[0])
    _check_folder(folder, before, ())


def _post_csv_on_file(d: Path) -> list:
    (d / "taken").write_text("keep")
    return ["--csv", str(d / "taken")]


_POST_OPTIONS = {
    "csv-onto-a-file": (_post_csv_on_file, ("--csv", "taken", "not a folder")),
    "plot-onto-a-device": (lambda d: ["--plot", os.devnull], ("--plot", os.devnull)),
    "csv-under-a-file": (lambda d: (d / "f").write_text("x") and ["--csv", str(d / "f" / "x")],
                         ("f",)),
    "point-malformed": (lambda d: ["--point", "nonsense"], ("nonsense",)),
    "point-unknown-body": (lambda d: ["--point", "p=ghost:0,0,0"], ("ghost",)),
    "relative-to-unknown": (lambda d: ["--relative-to", "ghost"], ("ghost",)),
    "results-missing": (lambda d: ["--mounts"], ("no such file",)),
    "results-not-hdf5": (lambda d: ["--mounts"], ("not a readable HDF5",)),
}


@pytest.mark.parametrize("fault", list(_POST_OPTIONS))
def test_post_refuses_bad_options(fault, results_file, tmp_path, capsys):
    make, words = _POST_OPTIONS[fault]
    results = tmp_path / "r.h5"
    if fault == "results-not-hdf5":
        results.write_text("not hdf5")
    elif fault != "results-missing":
        results.write_bytes(results_file.read_bytes())
    more = make(tmp_path)
    before = _snapshot(tmp_path)
    code = main(["post", str(results), *more])
    _refused_in_one_line(code, capsys, words, tmp_path, before)


# --- faults where the process matters ---------------------------------------------------

def _child(argv, cwd, *, env=None, preexec_fn=None, stdout=subprocess.PIPE):
    return subprocess.run([sys.executable, "-m", "flexbed.cli", *argv], cwd=cwd, env=env,
                          stdout=stdout, stderr=subprocess.PIPE, text=True, timeout=120,
                          preexec_fn=preexec_fn)


def test_standard_output_on_a_full_device(tmp_path):
    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full on this system")
    with open("/dev/full", "w") as full:
        r = _child(["scene"], tmp_path, stdout=full)
    err = r.stderr.strip().splitlines()
    assert r.returncode == 2
    assert err == ["flexbed scene: cannot write to standard output (No space left on device; "
                   "the device is full: free some space or write elsewhere)"]


def _limit_file_size(limit: int):
    def preexec():
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
    return preexec


@pytest.mark.slow
def test_a_full_disk_leaves_nothing_and_says_what_to_do(tmp_path):
    """A file size limit (RLIMIT_FSIZE, as a full disk would: the write
    fails with EFBIG) while the equilibrium file is written: one line, exit
    2, the temporary file removed, the old file in place."""
    (tmp_path / "s.toml").write_text(scene())
    out = tmp_path / "out"
    out.mkdir()
    (out / "eq.h5").write_bytes(b"old")
    before = _snapshot(tmp_path)
    r = _child(["static", "s.toml", "-o", "out/eq.h5"], tmp_path,
               preexec_fn=_limit_file_size(4096))
    err = r.stderr.strip().splitlines()
    assert r.returncode == 2, r.stderr
    assert len(err) == 1, err
    assert "out/eq.h5: cannot write it (File too large" in err[0]
    assert "nothing was written" in err[0]
    _check_folder(tmp_path, before, ())


def test_a_read_only_folder(tmp_path, capsys):
    """A folder one may not write in. Run as root, permissions do not stop a
    write, so a folder that refuses writes to root too is used: ``/sys``
    (sysfs), where creating a file fails; skipped if neither is at hand."""
    (tmp_path / "s.toml").write_text(scene())
    if os.geteuid() != 0:
        folder = tmp_path / "ro"
        folder.mkdir()
        folder.chmod(0o555)
    else:
        folder = Path("/sys")
        probe = folder / "flexbed-probe"
        try:
            probe.write_text("x")
        except OSError:
            pass
        else:                                     # pragma: no cover - a writable /sys
            probe.unlink()
            pytest.skip("running as root and /sys is writable: no folder refuses a write")
    before = _snapshot(tmp_path)
    try:
        code = main(["static", str(tmp_path / "s.toml"), "-o", str(folder / "eq.h5")])
    finally:
        if folder != Path("/sys"):
            folder.chmod(0o755)
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2
    assert len(err) == 1, err
    assert f"{folder}/eq.h5: cannot write in {folder}" in err[0]
    assert "choose a folder you may write in" in err[0] or "read-only" in err[0]
    _check_folder(tmp_path, before, ())


def test_an_unwritable_compiled_cache_falls_back_to_a_temporary_folder(tmp_path):
    """No cache location numba may use (NUMBA_CACHE_DIR in /sys, and numba
    told to try only that one, as when the package's folder is read-only
    and there is no writable home): one line naming the folder used
    instead, and numba caches there."""
    code = ("from flexbed.dynamics import jitcache\n"
            "jitcache.refresh()\n"
            "print(jitcache.cache_dir(jitcache._source(jitcache.COMPILED[0])))\n")
    env = dict(os.environ, NUMBA_CACHE_DIR="/sys/flexbed-cache",
               NUMBA_CACHE_LOCATOR_CLASSES="UserProvidedCacheLocator", TMPDIR=str(tmp_path))
    r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 0, r.stderr
    spare = tmp_path / f"flexbed-numba-{os.getuid()}"
    assert r.stderr.strip().splitlines() == [
        f"flexbed: note: NUMBA_CACHE_DIR = /sys/flexbed-cache is not writable; compiled code "
        f"is cached in {spare} (set NUMBA_CACHE_DIR to a writable folder to choose)"]
    assert r.stdout.strip().startswith(str(spare))
    assert oct(spare.stat().st_mode & 0o777) == "0o700"


def test_floating_point_warnings_become_the_cause_in_one_line(capsys):
    """NumPy's RuntimeWarnings are not printed; a numerical failure that
    follows names the first of them as its cause."""
    import types
    import argparse

    from flexbed.console import run_command
    from flexbed.errors import NumericalError

    def run(args):
        with np.errstate(over="warn"):
            np.float64(1e308) * np.float64(10.0)
            np.float64(1e308) * np.float64(10.0)
        raise NumericalError("no static equilibrium")

    module = types.SimpleNamespace(run=run)
    with pytest.raises(NumericalError) as caught:
        run_command(module, argparse.Namespace(command="static"))
    assert str(caught.value) == ("no static equilibrium (after a floating-point error: "
                                 "overflow encountered in scalar multiply)")
    assert capsys.readouterr().err == ""

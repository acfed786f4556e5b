"""Every file flexbed reads must be a regular file: a FIFO would block the
read for ever and a folder or a device is no file of flexbed's; each is
refused at once in one line naming it and what it is (issue 28)."""

from __future__ import annotations

import os

import pytest

from flexbed.cli import main


@pytest.mark.parametrize("kind", ["fifo", "folder"])
@pytest.mark.parametrize("args, what", [
    (["static", "{}"], "scene file"),
    (["simulate", "{}"], "scene file"),
    (["post", "{}"], "results file"),
    (["srs", "{}"], "results file"),
    (["sweep", "{}"], "study file"),
])
def test_a_file_that_is_not_a_regular_file_is_refused(tmp_path, capsys, monkeypatch, kind,
                                                      args, what):
    monkeypatch.chdir(tmp_path)
    path = tmp_path / "input"
    if kind == "fifo":
        os.mkfifo(path)
    else:
        path.mkdir()
    code = main([a.format(path) for a in args])
    err = capsys.readouterr().err
    name = "a FIFO" if kind == "fifo" else "a directory"
    assert code == 2 and err.count("\n") == 1, err
    assert f"{path}: cannot read the {what}: it is {name}, not a file" in err, err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["input"]

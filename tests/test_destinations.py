"""Nothing but a regular file is ever replaced, and every write is atomic
(issue 12: ``-o /dev/full`` renamed a file over the device node; a symlink
given as output was replaced by a regular file). Only objects made in the
test's own folder are used (a FIFO stands for a device), so a broken check
cannot touch the system."""

from __future__ import annotations

import os
import stat

import pytest

from flexbed.cli import main
from flexbed.errors import InputError
from flexbed.files.destination import atomic_write, write_text


def _kinds(tmp_path):
    target = tmp_path / "target.txt"
    target.write_text("keep me")
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    link = tmp_path / "link.txt"
    link.symlink_to(target)
    dangling = tmp_path / "dangling.txt"
    dangling.symlink_to(tmp_path / "nowhere.txt")
    folder = tmp_path / "folder"
    folder.mkdir()
    return target, {"a FIFO": fifo, "a symbolic link": link, "a symbolic link ": dangling,
                    "a directory": folder}


def _state(tmp_path):
    return sorted((p.name, stat.S_IFMT(os.lstat(p).st_mode)) for p in tmp_path.iterdir())


def test_only_regular_files_are_replaced(tmp_path):
    target, others = _kinds(tmp_path)
    before = _state(tmp_path)
    for what, path in others.items():
        with pytest.raises(InputError) as err:
            write_text(path, "x")
        assert str(path) in str(err.value) and what.strip() in str(err.value)
    assert _state(tmp_path) == before                       # nothing replaced, no temporary
    assert target.read_text() == "keep me"
    assert not (tmp_path / "nowhere.txt").exists()


def test_a_regular_file_is_replaced_atomically(tmp_path):
    path = tmp_path / "out.csv"
    path.write_text("old")
    write_text(path, "new\n")
    assert path.read_text() == "new\n"
    umask = os.umask(0)
    os.umask(umask)
    assert stat.S_IMODE(os.stat(path).st_mode) == 0o666 & ~umask

    def broken(tmp):
        tmp.write_text("half")
        raise RuntimeError("disk full")

    with pytest.raises(RuntimeError):
        atomic_write(path, broken)
    assert path.read_text() == "new\n"                      # untouched
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv"]   # no temporary left


@pytest.mark.parametrize("argv", [["static", "-o", "{fifo}"], ["scene", "-o", "{dangling}"],
                                  ["simulate", "--t-end", "0.01", "-o", "{link}"]])
def test_commands_refuse_in_one_line(tmp_path, argv, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    target, others = _kinds(tmp_path)
    names = {"fifo": others["a FIFO"], "link": others["a symbolic link"],
             "dangling": others["a symbolic link "]}
    before = _state(tmp_path)
    code = main([a.format(**names) for a in argv])
    err = capsys.readouterr().err
    assert code == 2
    assert len(err.strip().splitlines()) == 1 and "regular file" in err
    assert _state(tmp_path) == before
    assert target.read_text() == "keep me"

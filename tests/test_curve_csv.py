"""A curve's CSV file: the compiled fast path and the line-by-line reader
give the same numbers, and every file the fast path leaves alone is still
read (or refused) by the line-by-line reader."""

from pathlib import Path

import numpy as np
import pytest

import flexbed.files.drives as drives
from flexbed.errors import InputError
from flexbed.files.drives import ShapeReader, _two_columns


def _line_by_line(text: str, monkeypatch):
    """What the line-by-line reader alone makes of ``text``."""
    with monkeypatch.context() as m:
        m.setattr(drives, "_two_columns", lambda _text: None)
        Path("c.csv").write_text(text, newline="")
        return ShapeReader("s.toml", Path(".")).csv_file("base.force 1", "c.csv")


def test_fast_path_equals_the_line_by_line_reader_to_the_bit(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    rng = np.random.default_rng(7)
    t = np.sort(rng.uniform(0.0, 3.0, 5000))
    v = rng.standard_normal(5000) * 10.0 ** rng.integers(-30, 30, 5000)
    body = "".join(f"{a!r}, {b:.17g}\n" for a, b in zip(t.tolist(), v.tolist()))
    for text in ("time, value\n" + body, "# a comment\n\ntime,value\n" + body,
                 body.replace("\n", "\r\n"), body + "\n\n"):
        fast = _two_columns(text)
        assert fast is not None
        slow = _line_by_line(text, monkeypatch)
        assert np.array_equal(fast[0], slow[0]) and np.array_equal(fast[1], slow[1])
        assert np.array_equal(fast[0], t)


@pytest.mark.parametrize("text", [
    "0,1\n# a comment among the data\n1,2\n",      # comments: line by line
    "0,1\n1_0,2\n",                                # Python's float takes 1_0
    "0,1\r1,2\r",                                  # old Mac line breaks
    "0,1,2\n1,2,3\n",                              # three columns: refused by name
    "0,1\n1,x\n",                                  # a text cell: refused by line
    "time,value\n",                                # no data
])
def test_files_the_fast_path_leaves_to_the_line_by_line_reader(text):
    assert _two_columns(text) is None


def test_a_file_without_a_line_of_numbers_is_refused_by_name(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    Path("c.csv").write_text("time,value\nnp.float64(0.0), 1\n")
    with pytest.raises(InputError, match=r"s\.toml: base\.force 1: file = 'c\.csv': no line of "
                                         r"two numbers"):
        ShapeReader("s.toml", Path(".")).csv_file("base.force 1", "c.csv")


def test_underscored_numbers_and_comments_still_read_line_by_line(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    Path("c.csv").write_text("t,v\n0,1\n# note\n1_0,2\n")
    assert ShapeReader("s.toml", Path(".")).csv_file("w", "c.csv") == ([0.0, 10.0], [1.0, 2.0])

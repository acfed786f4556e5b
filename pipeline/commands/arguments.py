"""Arguments several subcommands share (not a subcommand itself).

:func:`number` is the type of every numeric option: the scene file's range
rule (magnitudes from :data:`~flexbed.files.table_reader.SMALLEST` to
:data:`~flexbed.files.table_reader.LARGEST`, or 0) applied as the option is
parsed, so that ``--fmin 5e-324`` or ``--t-end 1e308`` is refused in one
line before any work instead of overflowing later. ``nan`` and ``inf`` pass
as floats: each command's own check names them with its rule
(``--tol = inf must be finite``). :func:`count` is the type of the options
that size a cluster or a batch, with the limits the API has;
:func:`file_name` that of ``-o`` (never empty). :func:`output_folder` and
:func:`unused_modes_file` check, before any work, an output folder option
and a ``--modes-file`` that a rigid run would ignore.
"""

from __future__ import annotations

import argparse
import math

__all__ = ["add_scene_arg", "number", "count", "file_name", "output_folder",
           "unused_modes_file"]


def add_scene_arg(parser: argparse.ArgumentParser) -> None:
    """The optional positional SCENE: a scene file, else the built-in scene."""
    parser.add_argument("scene", nargs="?", default=None,
                        help="scene file (TOML); default: the built-in reference scene")


def number(text: str) -> float:
    """A numeric option's value: a float within the scene file's range.

    Raises
    ------
    argparse.ArgumentTypeError
        Not a number, or a finite magnitude outside [1e-100, 1e100] (not 0).
    """
    from flexbed.files.table_reader import LARGEST, SMALLEST, out_of_range
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number") from None
    if math.isfinite(value) and out_of_range(value):
        raise argparse.ArgumentTypeError(f"{text} is out of range (magnitudes from "
                                         f"{SMALLEST:g} to {LARGEST:g}, or 0)")
    return value


def count(maximum: int):
    """The type of an integer option from 1 to ``maximum`` (``--workers``,
    ``--batch``)."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"{text!r} is not an integer") from None
        if not 1 <= value <= maximum:
            raise argparse.ArgumentTypeError(f"{text} must be from 1 to {maximum:,}")
        return value
    parse.__name__ = "count"
    return parse


def file_name(text: str) -> str:
    """The type of the options that name a file, a folder or a prefix
    (``-o``): an empty name is refused, not read as "the default" nor as
    the current folder."""
    if not text.strip():
        raise argparse.ArgumentTypeError(f"{text!r}: an empty name (give a file or folder "
                                         f"name, or leave the option out for the default)")
    return text


def output_folder(option: str, value: str | None):
    """An output folder option (``--csv DIR``, ``--plot DIR``), checked
    before any work: absent or a folder, else InputError naming it."""
    from pathlib import Path

    from flexbed.errors import InputError
    if value is None:
        return None
    path = Path(value)
    if path.exists() and not path.is_dir():
        raise InputError(f"{option} {value}: is not a folder (it names an existing file or "
                         f"device); give a folder for the output files")
    return path


def unused_modes_file(run, modes_file: str | None) -> None:
    """``--modes-file`` given for a run whose bed is rigid: refused (the
    file would be ignored without a word)."""
    from flexbed.errors import InputError
    if modes_file is not None and run.bed_model != "flexible":
        raise InputError(f"--modes-file {modes_file}: {run.path}'s bed is rigid: no modes file "
                         f"is read (leave the option out)")

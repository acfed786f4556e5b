"""``flexbed scene [-o FILE]``: print (or write) the built-in reference scene
as TOML, a starting point for a scene of your own."""

from __future__ import annotations

import argparse
from pathlib import Path

from flexbed.commands.arguments import file_name
from flexbed.files.destination import write_text
from flexbed.errors import InputError
from flexbed.files.builtin import builtin_scene_text


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = "Print the built-in reference scene (Lee, Kim & Jeong 1999) as TOML."
    parser.add_argument("-o", "--output", type=file_name, default=None, metavar="FILE",
                        help="write it to FILE, with [scene] name = FILE's stem, instead of "
                             "printing it (refuses to overwrite)")


def run(args: argparse.Namespace) -> int:
    text = builtin_scene_text(None if args.output is None else Path(args.output).stem)
    if args.output is None:
        print(text, end="")
        return 0
    path = Path(args.output)
    if path.exists():
        raise InputError(f"{path}: already exists; choose another name")
    write_text(path, text)
    print(f"wrote {path}")
    return 0

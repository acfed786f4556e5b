"""``flexbed scene [-o FILE]``: print (or write) the built-in reference scene
as TOML, a starting point for a scene of your own."""

from __future__ import annotations

import argparse
from importlib import resources
from pathlib import Path

from flexbed.errors import InputError


def add_args(parser: argparse.ArgumentParser) -> None:
    parser.description = "Print the built-in reference scene (Lee, Kim & Jeong 1999) as TOML."
    parser.add_argument("-o", "--output", default=None, metavar="FILE",
                        help="write it to FILE instead of printing it (refuses to overwrite)")


def run(args: argparse.Namespace) -> int:
    # the packaged file itself (flexbed.files.scene.builtin_scene_path), read
    # without importing the scene reader and the dynamics behind it
    text = (resources.files("flexbed") / "scenes" / "lee1999.toml").read_text()
    if args.output is None:
        print(text, end="")
        return 0
    path = Path(args.output)
    if path.exists():
        raise InputError(f"{path}: already exists; choose another name")
    path.write_text(text)
    print(f"wrote {path}")
    return 0

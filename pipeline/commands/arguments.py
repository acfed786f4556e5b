"""Arguments several subcommands share (not a subcommand itself)."""

from __future__ import annotations

import argparse

__all__ = ["add_scene_arg"]


def add_scene_arg(parser: argparse.ArgumentParser) -> None:
    """The optional positional SCENE: a scene file, else the built-in scene."""
    parser.add_argument("scene", nargs="?", default=None,
                        help="scene file (TOML); default: the built-in reference scene")

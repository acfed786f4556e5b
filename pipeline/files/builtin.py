"""The built-in reference scene (Lee, Kim & Jeong 1999, section 5), as a file
of the package; light to import (``flexbed scene`` reads nothing else)."""

from __future__ import annotations

import json
import re
from importlib import resources
from pathlib import Path

__all__ = ["BUILTIN", "builtin_scene_path", "builtin_scene_text"]

BUILTIN = "lee1999.toml"


def builtin_scene_path() -> Path:
    """Path of the built-in reference scene."""
    return Path(str(resources.files("flexbed") / "scenes" / BUILTIN))


def builtin_scene_text(name: str | None = None) -> str:
    """The built-in reference scene as TOML, with ``[scene] name`` set to
    ``name`` (e.g. the stem of the file it is written to) when given."""
    text = builtin_scene_path().read_text(encoding="utf-8")
    if name is None:
        return text
    new, n = re.subn(r'^name = "lee1999"$', lambda _: f"name = {json.dumps(name)}", text,
                     count=1, flags=re.M)
    assert n == 1, "the built-in scene has no [scene] name line"
    return new

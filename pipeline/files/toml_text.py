"""TOML text from parsed TOML data (the inverse of :func:`tomllib.loads` for
what a scene file holds: tables, arrays of tables, inline tables inside
arrays, strings, booleans, integers, floats and arrays)."""

from __future__ import annotations

import functools
import json
import math
import re
from typing import Any

from flexbed.dynamics.bounded_cache import BoundedCache
from flexbed.files.scene_text import table_key

__all__ = ["dumps"]

_BARE = re.compile(r"^[A-Za-z0-9_-]+$")

#: the text of recently written top-level tables (a ``[bed]``, one
#: ``[[mount]]``) by their name and :func:`table_key`: a study's variants
#: share all but the tables they change, and those alone are written again
_WRITTEN = BoundedCache(512)


def _key(k: str) -> str:
    return k if _BARE.match(k) else json.dumps(k, ensure_ascii=False)


def _value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        text = repr(v)
        return text if any(c in text for c in ".eEn") else text + ".0"
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + "}"
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if hasattr(v, "tolist"):                       # NumPy scalars and arrays
        return _value(v.tolist())
    raise TypeError(f"cannot write {type(v).__name__} {v!r} as TOML")


def _is_table_array(v: Any) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


def _table(lines: list[str], prefix: str, table: dict) -> None:
    for k, v in table.items():
        if not (isinstance(v, dict) or _is_table_array(v)):
            lines.append(f"{_key(k)} = {_value(v)}")
    for k, v in table.items():
        name = f"{prefix}.{_key(k)}" if prefix else _key(k)
        if isinstance(v, dict):
            lines.append("")
            lines.append(f"[{name}]")
            _table(lines, name, v)
        elif _is_table_array(v):
            for item in v:
                lines.append("")
                lines.append(f"[[{name}]]")
                _table(lines, name, item)


def _top(name: str, table: dict, array: bool) -> str:
    """The lines of one top-level table (``[name]``, or one ``[[name]]``),
    with the blank line before it."""
    lines = ["", f"[[{name}]]" if array else f"[{name}]"]
    _table(lines, name, table)
    return "\n".join(lines)


def dumps(data: dict) -> str:
    """TOML text whose :func:`tomllib.loads` equals ``data``.

    >>> import tomllib
    >>> d = {"a": 1.5, "t": {"x": [1, 2]}, "row": [{"name": "M1", "k": [1e6, 2.0]}]}
    >>> tomllib.loads(dumps(d)) == d
    True
    """
    lines = [f"{_key(k)} = {_value(v)}" for k, v in data.items()
             if not (isinstance(v, dict) or _is_table_array(v))]
    for k, v in data.items():
        if isinstance(v, dict) or _is_table_array(v):
            name, array = _key(k), not isinstance(v, dict)
            for item in (v if array else [v]):
                key = table_key(item)
                write = functools.partial(_top, name, item, array)
                lines.append(write() if key is None else _WRITTEN.get((name, array, key), write))
    return "\n".join(lines).lstrip("\n") + "\n"

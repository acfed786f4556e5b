"""A scene's TOML text parsed once: the parses of the last few texts kept, so
that a run's stages, a study's points and the post-processing do not parse
the same scene again (~5 ms each). Light on purpose (``tomllib`` and
``pickle`` only): the post-processing of a results file imports it without
the scene reader and the compiled dynamics behind it."""

from __future__ import annotations

import marshal
import pickle
import tomllib

__all__ = ["scene_data", "keep", "table_key"]

#: the last few scene texts checked or used → their data, pickled (the most
#: recently used last)
_PARSED: dict = {}


def keep(text: str, data: dict) -> bytes:
    _PARSED.pop(text, None)
    raw = _PARSED[text] = pickle.dumps(data, protocol=pickle.HIGHEST_PROTOCOL)
    while len(_PARSED) > 4:
        del _PARSED[next(iter(_PARSED))]
    return raw


def scene_data(text: str) -> dict:
    """``tomllib.loads(text)`` of a scene's TOML (a fresh copy each call;
    ``tomllib.TOMLDecodeError`` as it raises): the parse of the last few
    texts checked or used is kept, so that a run's stages do not parse the
    same scene again (~5 ms each)."""
    raw = _PARSED.pop(text, None)
    if raw is None:
        return pickle.loads(keep(text, tomllib.loads(text)))
    _PARSED[text] = raw
    return pickle.loads(raw)


def table_key(value) -> bytes | None:
    """A key of parsed TOML data (a table, an array, a value) that two
    values share only when they are equal, types included (``1``, ``1.0``
    and ``true`` apart; floats by their bits): what the scene reader and
    writer keep their recent results by. ``marshal``'s version 2 (no
    references between objects, so equal data give equal bytes; ~5× faster
    than ``repr``), or ``pickle`` for what marshal does not take (TOML's
    dates and times); None for what neither takes (a value no TOML holds,
    given through the API: it is then checked, and refused, every time),
    or for a table longer than :data:`KEY_BYTES` (a long inline curve:
    read again rather than kept)."""
    try:
        key = marshal.dumps(value, 2)
    except ValueError:
        try:
            key = pickle.dumps(value, protocol=pickle.HIGHEST_PROTOCOL)
        except Exception:                   # noqa: BLE001 - not a TOML value
            return None
    return key if len(key) <= KEY_BYTES else None


#: the longest table (its key's bytes) the reader and writer keep: with
#: 512 entries each, what they hold stays within some tens of MB whatever
#: a study varies
KEY_BYTES = 16384

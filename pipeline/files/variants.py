"""Variants of a scene by the path of an entry in its TOML: ``bed.thickness``,
``solver.t_end``, ``mount.M5.k``, ``body.equipment A.mass``,
``base.force[0].amplitude``.

A path is a dotted list of steps. A step into a table is a key; a step into
an array of tables (``body``, ``mount``, ``point``, ``base.drive``,
``base.force``) is an entry's ``name`` or an index in brackets (0-based);
``key[i]`` also indexes an array value. The variant is checked as a whole,
exactly as a scene file is (:func:`flexbed.files.scene.parse_scene`): its
text, digests and every rule are those of the file it would be. The
entries it leaves unchanged are not checked again: the reader keeps what it
checked by the entries' tables, so they are the base scene's own objects
(what a study's points share, :func:`flexbed.study.point.shared_parts`).
"""

from __future__ import annotations

import re
from typing import Any, Mapping

from flexbed.errors import InputError
from flexbed.files.scene import SceneFile, parse_scene, scene_data
from flexbed.files.table_reader import short_repr
from flexbed.files.toml_text import dumps

__all__ = ["vary", "split_path"]

_STEP = re.compile(r"^([^\[\]]*)((?:\[\d+\])*)$")


def split_path(path: str) -> list[str | int]:
    """``"base.force[0].amplitude"`` → ``["base", "force", 0, "amplitude"]``."""
    steps: list[str | int] = []
    for part in str(path).split("."):
        m = _STEP.match(part)
        if not m or (not m.group(1) and not m.group(2)):
            raise InputError(f"variant path {path!r}: step {part!r} is not a key, a name "
                             f"or key[index]")
        if m.group(1):
            steps.append(m.group(1))
        steps.extend(int(i) for i in re.findall(r"\[(\d+)\]", m.group(2)))
    return steps


def _step(node: Any, step: str | int, path: str, create: bool) -> Any:
    if isinstance(node, dict):
        if isinstance(step, int):
            raise InputError(f"variant path {path!r}: [{step}] indexes a table")
        if step not in node:
            if not create:
                raise InputError(f"variant path {path!r}: no entry {step!r} "
                                 f"(entries: {', '.join(map(str, node)) or 'none'})")
            node[step] = {}
        return node[step]
    if isinstance(node, list):
        if isinstance(step, int):
            if not 0 <= step < len(node):
                raise InputError(f"variant path {path!r}: index [{step}] out of range "
                                 f"({len(node)} entries)")
            return node[step]
        named = [x for x in node if isinstance(x, dict) and x.get("name") == step]
        if len(named) != 1:
            names = [str(x.get("name")) for x in node if isinstance(x, dict)]
            raise InputError(f"variant path {path!r}: no entry named {step!r} "
                             f"(names: {', '.join(names) or 'none'})")
        return named[0]
    raise InputError(f"variant path {path!r}: {step!r} steps into a value, not a table")


def _set(data: dict, path: str, value: Any) -> None:
    steps = split_path(path)
    node: Any = data
    for step, after in zip(steps[:-1], steps[1:]):
        if isinstance(after, int) and isinstance(node, dict) and step not in node:
            whole = path[:path.rindex(f"{step}[") + len(step)]
            raise InputError(f"variant path {path!r}: the scene gives no {step!r} to index; "
                             f"set the whole array ({whole} = [...])")
        node = _step(node, step, path, create=True)
    last = steps[-1]
    if isinstance(node, dict) and isinstance(last, str):
        node[last] = value
    elif isinstance(node, list) and isinstance(last, int) and 0 <= last < len(node):
        node[last] = value
    else:
        _step(node, last, path, create=False)           # raises with the reason
        raise InputError(f"variant path {path!r}: cannot set {last!r} here")


def _plain(value: Any) -> Any:
    """NumPy scalars and arrays as Python numbers and lists."""
    if hasattr(value, "tolist"):
        return value.tolist()
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    return value


def vary(scene: SceneFile, changes: Mapping[str, Any], *, name: str | None = None) -> SceneFile:
    """The scene with the entries at ``changes``' paths set to their values.

    Parameters
    ----------
    scene : SceneFile
    changes : mapping path → value
        E.g. ``{"bed.thickness": 0.12, "mount.M5.k": [2e6, 2e6, 1e6]}``; a
        value in the scene file's units (SI; ``_deg`` keys in degrees).
    name : str, optional
        The variant's ``[scene] name`` (default: unchanged).

    Returns
    -------
    SceneFile
        Checked as a scene file is; its ``text`` is the variant's TOML.

    Raises
    ------
    InputError
        A path that names nothing, or a value the scene file refuses; the
        message names the path and the entry.
    """
    _check_call(scene, changes, name)
    data = scene_data(scene.text)
    for path, value in changes.items():
        _set(data, path, _plain(value))
    if name is not None:
        _set(data, "scene.name", str(name))
    elif "name" not in data.get("scene", {}):
        data.setdefault("scene", {})["name"] = scene.scene.name
    return parse_scene(dumps(data), scene.source, data=data)


def _check_call(scene: Any, changes: Any, name: Any) -> None:
    """The arguments' types, refused in the API's one line (as
    :class:`flexbed.api.arguments.Arguments` words them)."""
    def bad(key: str, value: Any, expected: str):
        raise InputError(f"flexbed.vary: {key} = {short_repr(value)} must be {expected}")
    if not isinstance(scene, SceneFile):
        bad("scene", scene, "a scene from flexbed.load_scene or flexbed.vary")
    if not isinstance(changes, Mapping):
        bad("changes", changes, "a mapping of scene paths to values, "
                                "e.g. {'bed.thickness': 0.12}")
    for path in changes:
        if not isinstance(path, str):
            bad("changes", changes, "keyed by scene paths (strings such as 'bed.thickness'), "
                                    f"not {short_repr(path)}")
    if name is not None and not isinstance(name, str):
        bad("name", name, "a string, or None")

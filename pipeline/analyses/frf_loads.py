"""A scene's loads as frequency-response inputs: ``"load NAME"`` names a
``[[load]]`` or an ``[[unbalance]]`` table of the scene file (issue 25,
part 1).

- A ``[[load]]``: the response per unit of the load, Re(e^{iωt}) newtons
  (or newton metres for a moment) along its direction, at its point, in its
  frame (a body-frame axis taken at the equilibrium); its shape, amplitude
  and phase play no part.
- An ``[[unbalance]]``: the response per newton of its rotating force
  m·e·Ω², ``cos(ωt) e₁ + sin(ωt) e₂`` (the unbalance along e₁ at t = 0, its
  phase left out), which in complex amplitudes is ``e₁ − i e₂``: the
  generalized force ``Q = Q₁ − i Q₂`` of its two body-frame components.
  An unbalance that runs up has no single speed and is refused.

The generalized force of each component comes from the one right-hand side
(:func:`flexbed.dynamics.frequency.load_inputs.load_input`).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass

import numpy as np

from flexbed.dynamics.frequency.frf import Input
from flexbed.dynamics.frequency.load_inputs import load_input
from flexbed.errors import InputError

__all__ = ["SceneLoad", "load_name", "scene_load", "load_frf_input", "per_unit_load"]

_AXES = "xyz"
#: e₁, e₂ of a spin axis, (e₁, e₂, axis) right-handed (as
#: :func:`flexbed.dynamics.body_loads.unbalance` spins)
_PLANE = {0: (1, 2), 1: (2, 0), 2: (0, 1)}


@dataclass(frozen=True)
class SceneLoad:
    """A scene file's load table resolved against its compiled loads.

    name : str; kind : "load" or "unbalance"; body : str; quantity :
    "force" or "moment"; per : the input's unit, "N" or "N m"; names :
    (1,) or (2,) the compiled loads' names (an unbalance's e₁ then e₂
    component); directions : their axes (0, 1, 2); running : [Hz] the
    frequency it runs at (an unbalance's speed, a harmonic's order ×
    speed) or None; amplitude : [N or N m] its force there (m·e·Ω², a
    harmonic's amplitude) or None.
    """

    name: str
    kind: str
    body: str
    quantity: str
    per: str
    names: tuple
    directions: tuple
    running: float | None = None
    amplitude: float | None = None

    @property
    def label(self) -> str:
        if self.kind == "unbalance":
            return (f"unbalance {self.name!r}: unit rotating force [N] in the {self.body} "
                    f"frame's {_AXES[self.directions[0]]}{_AXES[self.directions[1]]} plane")
        return (f"load {self.name!r}: unit {self.quantity} [{self.per}] along "
                f"{_AXES[self.directions[0]]} on {self.body}")


def load_name(text: str) -> str | None:
    """NAME of an input ``"load NAME"``, None for any other input."""
    words = text.split(None, 1)
    if not words or words[0] != "load":
        return None
    return words[1].strip() if len(words) == 2 else ""


def scene_load(sf, name: str, entry: str) -> SceneLoad:
    """The ``[[load]]`` or ``[[unbalance]]`` table named ``name`` of the
    scene file ``sf``; InputError starting ``entry`` if there is none, or
    if it is an unbalance that runs up."""
    data = tomllib.loads(sf.text)
    loads = [t for t in data.get("load", []) if isinstance(t, dict)]
    unbalances = [t for t in data.get("unbalance", []) if isinstance(t, dict)]
    # the default names are the scene reader's (flexbed.files.loads)
    load_names = [t.get("name", f"load {i + 1}") for i, t in enumerate(loads)]
    unb_names = [t.get("name", f"unbalance {i + 1}") for i, t in enumerate(unbalances)]
    if not name:
        raise InputError(f"{entry}: expected 'load NAME', NAME a [[load]] or [[unbalance]] "
                         f"of {sf.source.name}")
    if name in load_names:
        t = loads[load_names.index(name)]
        quantity = t.get("quantity", "force")
        per = "N" if quantity == "force" else "N m"
        running = amplitude = None
        if t.get("shape") == "harmonic":
            running, amplitude = float(t["order"]) * float(t["speed"]), float(t["amplitude"])
        return SceneLoad(name, "load", t["body"], quantity, per, (name,),
                         (_AXES.index(t["direction"]),), running, amplitude)
    if name in unb_names:
        t = unbalances[unb_names.index(name)]
        if isinstance(t["speed"], list):
            raise InputError(f"{entry}: unbalance {name!r} runs up (speed = {t['speed']!r} Hz); "
                             f"a frequency response needs a steady rotor: give one speed")
        e1, e2 = _PLANE[_AXES.index(t["axis"])]
        f = float(t["speed"])
        return SceneLoad(name, "unbalance", t["body"], "force", "N",
                         (f"{name} {_AXES[e1]}", f"{name} {_AXES[e2]}"), (e1, e2), f,
                         float(t["mass_radius"]) * (2.0 * math.pi * f) ** 2)
    have = "; ".join(part for part in (
        f"loads: {', '.join(load_names)}" if load_names else "",
        f"unbalances: {', '.join(unb_names)}" if unb_names else "") if part)
    raise InputError(f"{entry}: {sf.source.name} has no [[load]] or [[unbalance]] named "
                     f"{name!r} ({have or 'it has none'})")


def per_unit_load(unit: str, per: str) -> str:
    """A force input's output unit (``"m/s^2/N"``, ``"1"`` [N/N]) per
    ``per`` ("N" or "N m") instead."""
    if per == "N":
        return unit
    return f"N/({per})" if unit == "1" else f"{unit.removesuffix('/N')}/({per})"


def load_frf_input(ms, system, load: SceneLoad) -> Input:
    """The FRF input of ``load`` per unit (:class:`SceneLoad`): Q (n,),
    complex for an unbalance. An unbalance's components are the last
    compiled loads of their names (a scene compiles its [[load]] tables
    before its unbalances), a [[load]]'s the first of its name (each term
    of its shape a load of that name at the same point and axis: the same
    column)."""
    compiled = system.scene.loads
    columns = []
    for name, d in zip(load.names, load.directions):
        found = [i for i, ld in enumerate(compiled) if ld.name == name and ld.direction == d]
        if not found:
            raise RuntimeError(f"the scene's compiled loads hold no {name!r} along "
                               f"{_AXES[d]}")
        index = found[-1] if load.kind == "unbalance" else found[0]
        columns.append(load_input(ms, system, index).load)
    if load.kind == "unbalance":
        Q = columns[0] - 1j * columns[1]
    else:
        Q = columns[0]
    return Input("force", load.directions[0], np.ascontiguousarray(Q))

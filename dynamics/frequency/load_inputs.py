"""Loads on bodies as frequency-response inputs (issue 25, part 1).

A scene's load on a body (:class:`flexbed.dynamics.body_loads.BodyLoad`),
taken at unit value and harmonic, ``e^{iωt}``, drives the mounted system
``G(ω) q = Q`` with the base at rest (:func:`flexbed.dynamics.frequency.frf.responses`,
input kind "force"). Its generalized force ``Q`` (n,) is read from the one
right-hand side: the rates' response to the load alone at 1 N (or N m) at
the equilibrium (:func:`flexbed.dynamics.linear.model.load_column`), times
the mass matrix, ``Q = M Δq̈``: on a rigid body the force and its moment
about the centre of mass, on the flexible bed also the modal forces
``Φ(s̄)ᵀ F̄`` at the point. A body-frame load's axis is taken at the
equilibrium (its turning with the body is of second order about a
harmonic load of zero mean).
"""

from __future__ import annotations

import numpy as np

from ..linear.model import load_column
from ..system import System
from .frf import Input
from .mounted import MountedSystem

__all__ = ["load_input", "load_inputs"]


def load_input(ms: MountedSystem, system: System, index: int) -> Input:
    """The FRF input of the scene's load ``index`` (0-based in
    ``system.scene.loads``) at unit value: ``Input("force", direction,
    load=Q)``, Q (n,) [N, N m, N kg^-1/2 per unit load]."""
    loads = system.scene.loads
    if not 0 <= index < len(loads):
        raise IndexError(f"load index {index} out of range (the scene has {len(loads)} loads)")
    co = ms.coords
    col = load_column(system, co, ms.y_eq, index)
    first_rate = co.n_pos + co.base_index.size
    Q = ms.M @ col[first_rate:]
    return Input("force", int(loads[index].direction), np.ascontiguousarray(Q))


def load_inputs(ms: MountedSystem, system: System) -> tuple:
    """:func:`load_input` of every load on a body of the scene, in order."""
    return tuple(load_input(ms, system, i) for i in range(len(system.scene.loads)))

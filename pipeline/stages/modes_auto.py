"""``[bed] modes = "auto"``: keep the bed modes the scene's loads can reach.

The rule
--------
A bed mode is excited through the mounts, by the base's inputs and by the
rigid-body motions of the bodies those inputs set going. So

    f_cut = auto_factor × max(f_input, f_suspension)

and every elastic mode below ``f_cut`` is kept (at least one), where

- ``f_input`` [Hz] is the highest significant frequency of the base's
  inputs and of the loads on bodies: the drives' accelerations or the
  loads' forces, summed per axis (each load on a body alone),
  sampled finely over 0 – t_end; it is the lowest frequency below which a
  fraction ``1 − AUTO_ENERGY`` (99.9 %) of their spectral energy lies (of
  the axis with the highest such frequency). The spectrum is that of the
  samples followed by their mirror image, u(2 t_end − t) on t_end – 2 t_end,
  then zeros: the run never sees the input after t_end, so the end of the
  run must not read as the input dropping to zero there. (Zeros straight
  after t_end made a load still on at t_end a step: the reference scene's
  5 Hz load cut at t_end = 0.02 s gave f_input = 5.1 kHz and kept 280 modes
  of a Mindlin bed; mirrored, 75 Hz.) A switch-on at t = 0 or a switch-off
  before t_end is seen as it is;
- ``f_suspension`` [Hz] is the highest natural frequency of the scene with a
  rigid bed, linearised about its static equilibrium
  (:mod:`flexbed.dynamics.linear.model`): the modes of the bodies on their mounts.

``auto_factor`` (default 2) is a scene key; the report of ``flexbed bench``
shows the error of this choice against keeping many more modes.
"""

from __future__ import annotations

import math

import numpy as np

from flexbed.dynamics.scene import Scene
from flexbed.dynamics.system import System

__all__ = ["AUTO_ENERGY", "input_frequency", "suspension_frequency", "cutoff"]

AUTO_ENERGY = 1e-3
_MAX_SAMPLES = 1 << 20


def input_frequency(scene: Scene, t_end: float) -> float:
    """Highest significant frequency of the base's inputs on 0 – t_end [Hz]
    (0 when the scene has none)."""
    base = scene.base
    inputs = base.loads if base.motion == "free" else base.drives if base.motion == "driven" \
        else ()
    inputs = tuple(inputs) + tuple(scene.loads)     # a load on a body: an "axis" of its own
    if not inputs:
        return 0.0
    funcs = [(d.direction if i < len(inputs) - len(scene.loads) else 3 + i, d.shape.compile())
             for i, d in enumerate(inputs)]
    spacing = [t_end / 200.0]
    for d in inputs:
        f = d.shape.compile()
        kn = np.asarray(getattr(f.value, "breaks", f.breakpoints), dtype=float)
        if kn.size > 1:
            spacing.append(float(np.min(np.diff(kn))))
        if hasattr(d.shape, "frequency"):
            spacing.append(1.0 / float(d.shape.frequency))
    dt = max(min(spacing) / 8.0, t_end / _MAX_SAMPLES)
    n = int(math.ceil(t_end / dt)) + 1
    t = np.linspace(0.0, t_end, n)
    f_hi = 0.0
    for axis in sorted({k for k, _ in funcs}):
        u = sum((f.values(t) for k, f in funcs if k == axis), np.zeros(n))
        if not np.any(u):
            continue
        u = np.concatenate([u, u[-2::-1]])                    # mirrored about t_end
        power = np.abs(np.fft.rfft(u, n=2 * u.size)) ** 2     # zero-padded: finer bins
        freq = np.fft.rfftfreq(2 * u.size, d=t[1] - t[0])
        cum = np.cumsum(power)
        k = int(np.searchsorted(cum, (1.0 - AUTO_ENERGY) * cum[-1]))
        f_hi = max(f_hi, float(freq[min(k, freq.size - 1)]))
    return f_hi


def suspension_frequency(system: System, y_eq: np.ndarray) -> float:
    """Highest natural frequency of the linearised scene [Hz]."""
    from flexbed.dynamics.linear.model import linearise
    lam = np.linalg.eigvals(linearise(system, y_eq).A)
    return float(np.max(np.abs(lam.imag), initial=0.0)) / (2 * math.pi)


def cutoff(scene: Scene, t_end: float, factor: float, static_tol: float) -> tuple:
    """(f_cut, f_input, f_suspension) [Hz] for a scene with a rigid bed.

    Raises
    ------
    RuntimeError
        When the rigid scene has no static equilibrium (message says why).
    """
    from flexbed.dynamics.statics import solve_statics
    system = System(scene)
    eq = solve_statics(system, tol=static_tol)
    if not eq.success:
        raise RuntimeError(eq.message)
    f_in = input_frequency(scene, t_end)
    f_sus = suspension_frequency(system, eq.y)
    return factor * max(f_in, f_sus), f_in, f_sus

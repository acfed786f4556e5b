"""The method ``integrator = "auto"`` runs: radau or dop853.

:func:`auto_method` asks whether dop853 would be *stability-bound* on the
scene: the stable step of its linearisation at the start
(:func:`flexbed.dynamics.stiffness.stable_step_at_start`, the linear
stability analysis the stiffness check also uses) against the output
spacing and ``stiff_steps``. It chooses, it never refuses a run;
:func:`flexbed.dynamics.integrate.integrate` calls it before the first step
and reports the choice and its reason in the run's statistics.

A module of its own beside the integration: its subject is the choice
among the integrators (a policy over measured costs), not the stability
analysis it builds on, and not one compiled stepper (the room
:mod:`flexbed.dynamics.steppers` holds compiled code only).
"""

from __future__ import annotations

import math

import numpy as np

from .stiffness import stable_step_at_start
from .system import System

__all__ = ["auto_method", "AUTO_STEP_FRACTION"]


#: ``auto`` takes radau when dop853's stable step is below this fraction of
#: the output spacing (see :func:`auto_method`).
AUTO_STEP_FRACTION = 0.5


def auto_method(system: System, y0: np.ndarray, settings) -> tuple[str, str]:
    """The method ``integrator = "auto"`` runs, and why (one line).

    dop853 is *stability-bound* when the stable step h of its linearisation
    at the start (:func:`flexbed.dynamics.stiffness.stable_step_at_start`)
    is below half the output spacing (:data:`AUTO_STEP_FRACTION`), or
    forces more than ``settings.stiff_steps`` steps (when that is not 0):
    then radau, else dop853. At the default tolerances dop853 takes steps longer than the
    output spacing on the reference scene (rigid and flexible bed: 195 and
    684 steps for 3,000 samples), so a stable step below half of it
    means many times the steps its accuracy needs; there radau is the
    cheaper (measured: 20 damped modes, h = 1.8e-5 s: dop853 112,481 steps,
    12.4 s, radau 682 steps, 0.06 s; 1e9 N/m mounts under 10 kg,
    h = 1.5e-4 s: dop853 3,697 steps, 0.11 s, radau 6 steps), while above it
    dop853 is (the flexible reference bed is stability-bound in the
    literal sense, h = 4.2e-3 s, and dop853 still costs half of radau).

    Parameters
    ----------
    system : System
    y0 : (ny,) array
        Start state (see :mod:`flexbed.dynamics.layout`).
    settings : flexbed.dynamics.integrate.Settings
        t_end, output_dt and stiff_steps are used.

    Returns
    -------
    (method, reason) : ("radau" or "dop853", str)
    """
    h, rate = stable_step_at_start(system, y0, settings.t_end, "dop853")
    if not math.isfinite(h):
        return "dop853", "auto: no eigenvalue limits dop853's step"
    steps = math.ceil(settings.t_end / h)
    limit = f"the fastest rate {rate:.1e} 1/s limits dop853 to steps below {h:.1e} s"
    if h < AUTO_STEP_FRACTION * settings.output_dt:
        return "radau", (f"auto: dop853 would be stability-bound ({limit}, under half the output "
                         f"spacing {settings.output_dt:g} s)")
    if settings.stiff_steps and steps > settings.stiff_steps:
        return "radau", (f"auto: dop853 would be stability-bound ({limit}: {steps} steps for "
                         f"{settings.t_end:g} s, more than stiff_steps = {settings.stiff_steps})")
    return "dop853", (f"auto: dop853 is not stability-bound ({limit}, not under half the output "
                      f"spacing {settings.output_dt:g} s)")

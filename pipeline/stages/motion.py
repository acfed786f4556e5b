"""One place that turns a compiled scene and its start into a motion: the
nonlinear integrators, the linear fast path, or the choice between them.

``model``:

- ``nonlinear``: :func:`flexbed.dynamics.integrate.integrate` with the settings;
- ``linear``: :func:`flexbed.dynamics.linear.run_linear` about the static
  equilibrium, whatever its estimated error (which is reported);
- ``auto``: the linear path first (cheap); kept when its estimated position
  error against the nonlinear model is at most ``linear_tol`` [m] and the
  estimate is reliable (small against the motion), else the nonlinear
  integrator. The choice and the reason are reported.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from flexbed.dynamics.integrate import Run, Settings, integrate
from flexbed.dynamics.linear import LinearRun, run_linear
from flexbed.errors import InputError
from flexbed.dynamics.system import System

__all__ = ["Motion", "solve_motion"]


@dataclass(frozen=True)
class Motion:
    """A finished (or stopped) motion.

    run : Run; model : "linear" | "nonlinear" (what produced run);
    requested : the model asked for; reason : one line saying why;
    linear : LinearRun or None (when the linear path was tried);
    linear_tol : float [m].
    """

    run: Run
    model: str
    requested: str
    reason: str
    linear: LinearRun | None
    linear_tol: float

    @property
    def estimated_error(self) -> float:
        """The linear model's estimated position error [m] (nan if not tried)."""
        return self.linear.estimate.position if self.linear is not None else float("nan")

    def attrs(self) -> dict:
        """What the results file records about the model."""
        est = self.linear.estimate if self.linear is not None else None
        return {"model": self.model, "model_requested": self.requested,
                "model_reason": self.reason, "linear_tol": self.linear_tol,
                "linear_estimated_error": est.position if est else float("nan"),
                "linear_estimate_reliable": bool(est.reliable) if est else False}


def solve_motion(system: System, y_eq: np.ndarray | None, y0: np.ndarray, settings: Settings,
                 *, model: str = "nonlinear", linear_tol: float = 1e-6,
                 progress=None) -> Motion:
    """Run the motion from ``y0`` (ny,) with the requested model.

    Parameters
    ----------
    system : System
    y_eq : (ny,) array or None
        The static equilibrium (needed for ``linear`` and ``auto``).
    y0 : (ny,) array
        The state at t = 0.
    settings : Settings
        The nonlinear integrator's settings; t_end and output_dt also set
        the linear path's grid.
    model : {"nonlinear", "linear", "auto"}
    linear_tol : float
        Position error [m] below which ``auto`` keeps the linear model.
    progress : callable(t), optional
        Passed to the nonlinear integrator.
    """
    if model == "nonlinear":
        run = integrate(system, y0, settings, progress=progress)
        return Motion(run, "nonlinear", model, "requested", None, linear_tol)
    if system.laws.stopped.size:                # a contact is no linear motion
        mount = system.scene.mounts[int(system.laws.stopped[0]) // 3].name
        if model == "linear":
            raise InputError(f"model = 'linear' cannot follow a bump stop's contact (mount "
                             f"{mount!r} has one): use 'nonlinear' or 'auto'")
        run = integrate(system, y0, settings, progress=progress)
        return Motion(run, "nonlinear", model, f"nonlinear: mount {mount!r} has a bump stop "
                      f"(contact is not linear)", None, linear_tol)
    if system.scene.maxwell:                    # the linear model has no internal states
        run = integrate(system, y0, settings, progress=progress)
        return Motion(run, "nonlinear", model, f"nonlinear: mount "
                      f"{system.scene.maxwell[0].mount!r} is an elastomer (the linear model "
                      f"has no Maxwell states)", None, linear_tol)
    if y_eq is None:
        raise ValueError("the linear model needs the static equilibrium")
    lin = run_linear(system, y_eq, y0, settings)
    est = lin.estimate
    if not lin.run.complete:                # an unstable equilibrium: nothing propagated
        if model == "linear":
            return Motion(lin.run, "linear", model, f"requested; {lin.run.message}", lin,
                          linear_tol)
        run = integrate(system, y0, settings, progress=progress)
        return Motion(run, "nonlinear", model, f"nonlinear: {lin.run.message}", lin,
                      linear_tol)
    if model == "linear":
        return Motion(lin.run, "linear", model,
                      f"requested; estimated error {est.position:.2e} m", lin, linear_tol)
    if est.position <= linear_tol and est.reliable:
        reason = (f"linear: its estimated error {est.position:.2e} m is below "
                  f"linear_tol = {linear_tol:g} m")
        return Motion(lin.run, "linear", model, reason, lin, linear_tol)
    why = (f"{est.position:.2e} m > linear_tol = {linear_tol:g} m" if est.position > linear_tol
           else f"{est.position:.2e} m is not small against the motion "
                f"({est.motion:.2e} m), so the estimate is unreliable")
    run = integrate(system, y0, settings, progress=progress)
    return Motion(run, "nonlinear", model,
                  f"nonlinear: the linear model's estimated error {why}", lin, linear_tol)

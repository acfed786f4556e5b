"""Everything a results file stores, evaluated along a run.

:func:`history` calls :meth:`System.observe` (the same physics as the
right-hand side) at every stored sample and stacks the results.
"""

from __future__ import annotations

import numpy as np

from .layout import N_WORK
from .rotation import angles_from_p
from .system import System

__all__ = ["history"]


def history(system: System, t: np.ndarray, y: np.ndarray) -> dict[str, np.ndarray]:
    """Stacked observations at times t (k,) [s] for states y (k, ny).

    Returns
    -------
    dict of arrays, k = number of samples, nb bodies, M mounts:
    ``position`` (k, nb, 3) [m], ``euler_parameters`` (k, nb, 4),
    ``orientation`` (k, nb, 3) [rad] roll/pitch/yaw, ``velocity`` (k, nb, 3)
    [m/s], ``angular_velocity`` (k, nb, 3) [rad/s] body frame,
    ``acceleration`` (k, nb, 3) [m/s²], ``angular_acceleration`` (k, nb, 3)
    [rad/s²], ``deflection``, ``rate``, ``force`` (k, M, 3) [m, m/s, N] along
    the mount axes, ``force_i``, ``force_j`` (k, M, 3) [N] inertial,
    ``kinetic`` (k, nb) [J], ``gravity_potential`` (k, nb) [J],
    ``mount_potential`` (k, M) [J], ``strain`` (k, nb) [J], ``modal``,
    ``modal_rate``, ``modal_acceleration`` (k, n_modal), ``work`` (k, 4) [J] (mount, external,
    drive, structural damping), ``power`` (k, 4) [W], ``balance`` (k,) [J] =
    kinetic + gravity potential + strain − works (constant for an exact
    solution).
    """
    k = len(t)
    nb, M = system.nb, system.M
    out = {
        "position": np.zeros((k, nb, 3)), "euler_parameters": np.zeros((k, nb, 4)),
        "velocity": np.zeros((k, nb, 3)), "angular_velocity": np.zeros((k, nb, 3)),
        "acceleration": np.zeros((k, nb, 3)), "angular_acceleration": np.zeros((k, nb, 3)),
        "deflection": np.zeros((k, M, 3)), "rate": np.zeros((k, M, 3)), "force": np.zeros((k, M, 3)),
        "force_i": np.zeros((k, M, 3)), "force_j": np.zeros((k, M, 3)),
        "kinetic": np.zeros((k, nb)), "gravity_potential": np.zeros((k, nb)),
        "mount_potential": np.zeros((k, M)), "strain": np.zeros((k, nb)),
        "modal": np.zeros((k, system.layout.n_modal)),
        "modal_rate": np.zeros((k, system.layout.n_modal)),
        "modal_acceleration": np.zeros((k, system.layout.n_modal)),
        "work": np.zeros((k, N_WORK)), "power": np.zeros((k, N_WORK)),
    }
    for n in range(k):
        o = system.observe(float(t[n]), y[n])
        out["position"][n] = o.r
        out["euler_parameters"][n] = o.p
        out["velocity"][n] = o.rd
        out["angular_velocity"][n] = o.w
        out["acceleration"][n] = o.rdd
        out["angular_acceleration"][n] = o.wd
        out["deflection"][n] = o.dx
        out["rate"][n] = o.dxd
        out["force"][n] = o.f
        out["force_i"][n] = o.force_i
        out["force_j"][n] = o.force_j
        out["kinetic"][n] = o.kinetic
        out["gravity_potential"][n] = o.gravity_potential
        out["mount_potential"][n] = o.mount_potential
        out["strain"][n] = o.strain
        out["modal"][n] = o.a
        out["modal_rate"][n] = o.ad
        out["modal_acceleration"][n] = o.add
        out["work"][n] = o.work
        out["power"][n] = o.power
    out["orientation"] = angles_from_p(out["euler_parameters"]) if k else np.zeros((0, nb, 3))
    out["balance"] = (out["kinetic"].sum(axis=1) + out["gravity_potential"].sum(axis=1)
                      + out["strain"].sum(axis=1) - out["work"].sum(axis=1))
    return out

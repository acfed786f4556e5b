"""Everything the physics gives at one (t, y), for outputs and checks.

:func:`observe` evaluates the compiled right-hand side once at the state
(the same physics as :meth:`flexbed.dynamics.system.System.rhs`, not
counted in ``System.nfev``) and reads what it left in its work arrays
(mount deflections, rates and forces, accelerations, the base's motion),
then adds the energies. Many samples at once: :mod:`flexbed.dynamics.history`.
"""

from __future__ import annotations

import math

import numpy as np

from .rotation import A as rotation_matrix

__all__ = ["Observation", "observe"]


class Observation:
    """Everything the physics gives at one (t, y); plain attributes.

    r (nb, 3) [m], p (nb, 4), rd (nb, 3) [m/s], w (nb, 3) [rad/s] body frame,
    rdd (nb, 3) [m/s²], wd (nb, 3) [rad/s²]; dx, dxd, f (M, 3) [m, m/s, N];
    force_i, force_j (M, 3) [N] inertial; kinetic, gravity_potential,
    mount_potential [J]; strain (nb,) [J] elastic energy of flexible bodies;
    a, ad, add (n_modal,) modal coordinates, rates and accelerations; work (4,) [J] (mount,
    external, drive, structural damping); power (4,) [W], their rates.
    """

    __slots__ = ("t", "r", "p", "rd", "w", "rdd", "wd", "dx", "dxd", "f", "force_i", "force_j",
                 "kinetic", "gravity_potential", "mount_potential", "strain", "a", "ad", "add",
                 "work", "power")


def observe(system, t: float, y: np.ndarray, seg_end: float = math.inf) -> Observation:
    """Everything at one (t, y) of a compiled system.

    Parameters
    ----------
    system : System
        :class:`flexbed.dynamics.system.System`.
    t : float
        Time [s].
    y : (ny,) array
        State (:mod:`flexbed.dynamics.layout`).
    seg_end : float
        End of the segment [s] whose one-sided limits the base's inputs
        give (inf: right-continuous), as for the right-hand side.

    Returns
    -------
    Observation
    """
    y = np.ascontiguousarray(y, dtype=np.float64)
    dydt = np.empty(system.ny)
    system.rhs_into(t, y, dydt, seg_end)
    d = system.data
    nb, M = system.nb, system.M
    lay = system.layout
    o = Observation()
    o.t = float(t)
    parts = lay.split(y)
    o.r = np.zeros((nb, 3))
    o.r[0] = d.w_base[0]
    o.r[1:] = parts["r"]
    o.p = np.zeros((nb, 4))
    o.p[0, 0] = 1.0
    o.p[1:] = parts["p"] / np.linalg.norm(parts["p"], axis=1, keepdims=True)
    o.rd = np.zeros((nb, 3))
    o.rd[0] = d.w_base[1]
    o.rd[1:] = parts["rd"]
    o.w = np.zeros((nb, 3))
    o.w[1:] = parts["w"]
    o.rdd = d.w_acc[:, :3].copy()
    if system.base_motion == "fixed":
        o.rdd[0] = 0.0
    o.wd = d.w_acc[:, 3:].copy()
    o.wd[0] = 0.0
    o.dx = d.w_dx.copy()
    o.dxd = d.w_dxd.copy()
    o.f = d.w_f.copy()
    o.force_i = d.w_F.copy()
    o.force_j = -o.force_i
    rd = o.rd
    ke = 0.5 * system.mass * np.sum(rd * rd, axis=1)
    ke[1:] += 0.5 * np.einsum("ni,nij,nj->n", o.w[1:], system.J, o.w[1:])
    o.kinetic = ke
    o.gravity_potential = -system.mass * (o.r @ system.g)
    o.strain = np.zeros(nb)
    o.a = np.array(parts["a"], dtype=float)
    o.ad = np.array(parts["ad"], dtype=float)
    o.add = dydt[lay.v_modal].copy()
    for fc in system.flex_compiled:
        a, ad = y[fc.qa], y[fc.va]
        A = rotation_matrix(o.p[fc.body])
        o.kinetic[fc.body] = fc.eom.kinetic_energy(A, o.w[fc.body], a, o.rd[fc.body], ad)
        S = fc.eom.I2 + fc.eom.I3 @ a
        o.gravity_potential[fc.body] -= float((A @ S) @ system.g)
        o.strain[fc.body] = fc.eom.strain_energy(a)
    o.mount_potential = system.laws.spring_potential(o.dx.reshape(-1)).reshape(M, 3).sum(axis=1)
    o.work = np.array(parts["work"], dtype=float)
    o.power = dydt[lay.work].copy()
    return o

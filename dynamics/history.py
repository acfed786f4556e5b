"""Everything a results file stores, evaluated along a run.

:func:`history` evaluates the compiled right-hand side at every stored
sample in one compiled call (:meth:`System.rhs_batch`), keeping what the
kernel leaves in its work arrays at each sample (base motion,
accelerations, mount deflections, rates and forces, and each flexible
body's mass matrix as its Cholesky factor), and computes the energies from
these with array operations over all samples at once. It gives what
stacking :meth:`System.observe` at every sample gives, to round-off (the
flexible bodies' kinetic energy is ½|Lᵀ v̄|² with M̄(a) = L Lᵀ the kernel's
own body-frame mass matrix, v̄ = [Aᵀ ṙ, ω̄, ȧ]).
"""

from __future__ import annotations

import numpy as np

from .layout import N_WORK
from .rotation import A as rotation_matrix
from .rotation import angles_from_p
from .system import System

__all__ = ["history", "body_motion", "body_poses", "MOTION_CAPTURED"]

#: the kernel's work arrays a history keeps at each sample
_CAPTURED = ("w_base", "w_acc", "w_dx", "w_dxd", "w_f", "w_F", "w_M")
#: the work arrays :func:`body_motion` needs
MOTION_CAPTURED = ("w_base", "w_acc")


def body_poses(system: System, Y: np.ndarray, cap: dict) -> dict[str, np.ndarray]:
    """The bodies' poses at k samples: ``position`` (k, nb, 3) [m] and
    ``euler_parameters`` (k, nb, 4) of :func:`body_motion`, from the states
    Y (k, ny) and the base's motion ``cap["w_base"]`` (k, 3, 3)."""
    k, nb = Y.shape[0], system.nb
    parts = system.layout.split(Y)
    r = np.zeros((k, nb, 3))
    r[:, 0] = cap["w_base"][:, 0]
    r[:, 1:] = parts["r"]
    p = np.zeros((k, nb, 4))
    p[:, 0, 0] = 1.0
    p[:, 1:] = parts["p"] / np.linalg.norm(parts["p"], axis=-1, keepdims=True)
    return dict(position=r, euler_parameters=p)


def body_motion(system: System, Y: np.ndarray, cap: dict) -> dict[str, np.ndarray]:
    """The bodies' motion at k samples: states Y (k, ny) and the kernel's
    work arrays ``cap`` captured there (:data:`MOTION_CAPTURED` at least,
    by :meth:`System.rhs_batch`). Returns ``position``, ``velocity``,
    ``acceleration``, ``angular_velocity``, ``angular_acceleration`` (k, nb,
    3) and ``euler_parameters`` (k, nb, 4), as :func:`history`."""
    k, nb = Y.shape[0], system.nb
    parts = system.layout.split(Y)
    poses = body_poses(system, Y, cap)
    r, p = poses["position"], poses["euler_parameters"]
    rd = np.zeros((k, nb, 3))
    rd[:, 0] = cap["w_base"][:, 1]
    rd[:, 1:] = parts["rd"]
    w = np.zeros((k, nb, 3))
    w[:, 1:] = parts["w"]
    acc = cap["w_acc"]
    rdd = acc[:, :, :3].copy()
    if system.base_motion == "fixed":
        rdd[:, 0] = 0.0
    wd = acc[:, :, 3:].copy()
    wd[:, 0] = 0.0
    return dict(position=r, euler_parameters=p, velocity=rd, angular_velocity=w,
                acceleration=rdd, angular_acceleration=wd)


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
    t = np.ascontiguousarray(t, dtype=float).reshape(-1)
    Y = np.ascontiguousarray(y, dtype=float).reshape(t.size, system.ny)
    k = t.size
    nb, M, lay = system.nb, system.M, system.layout
    dY, cap = system.rhs_batch(t, Y, _CAPTURED)
    parts = lay.split(Y)

    out = body_motion(system, Y, cap)
    r, p, rd, w = (out[key] for key in ("position", "euler_parameters", "velocity",
                                        "angular_velocity"))
    out.update(deflection=cap["w_dx"], rate=cap["w_dxd"], force=cap["w_f"],
               force_i=cap["w_F"], force_j=-cap["w_F"])

    kinetic = 0.5 * system.mass * np.einsum("kbi,kbi->kb", rd, rd)
    kinetic[:, 1:] += 0.5 * np.einsum("kbi,bij,kbj->kb", w[:, 1:], system.J, w[:, 1:])
    gravity = -system.mass * (r @ system.g)
    strain = np.zeros((k, nb))
    a_all = np.asarray(parts["a"], dtype=float)
    ad_all = np.asarray(parts["ad"], dtype=float)
    q0, v0 = lay.q_modal.start, lay.v_modal.start
    for slot, fc in enumerate(system.flex_compiled):
        e, b, n = fc.eom, fc.body, fc.eom.n
        a = a_all[:, fc.qa.start - q0:fc.qa.stop - q0]
        ad = ad_all[:, fc.va.start - v0:fc.va.stop - v0]
        A = rotation_matrix(p[:, b])                                   # (k, 3, 3)
        vbar = np.concatenate([np.einsum("kji,kj->ki", A, rd[:, b]), w[:, b], ad], axis=1)
        L = np.tril(cap["w_M"][:, slot, :6 + n, :6 + n])               # M̄(a) = L Lᵀ
        u = np.einsum("kji,kj->ki", L, vbar)                           # Lᵀ v̄
        kinetic[:, b] = 0.5 * np.einsum("ki,ki->k", u, u)
        S = e.I2 + a @ e.I3.T                                          # (k, 3)
        gravity[:, b] -= np.einsum("kij,kj->ki", A, S) @ system.g
        strain[:, b] = 0.5 * np.einsum("ki,ij,kj->k", a, e.K, a)
    out.update(kinetic=kinetic, gravity_potential=gravity, strain=strain,
               mount_potential=system.laws.spring_potential(
                   cap["w_dx"].reshape(k, 3 * M)).reshape(k, M, 3).sum(axis=2),
               modal=a_all.copy(), modal_rate=ad_all.copy(),
               modal_acceleration=dY[:, lay.v_modal].copy(),
               work=np.array(parts["work"], dtype=float).reshape(k, N_WORK),
               power=dY[:, lay.work].copy())
    out["orientation"] = angles_from_p(p) if k else np.zeros((0, nb, 3))
    out["balance"] = (out["kinetic"].sum(axis=1) + out["gravity_potential"].sum(axis=1)
                      + out["strain"].sum(axis=1) - out["work"].sum(axis=1))
    return out

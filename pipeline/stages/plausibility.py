"""Is a static equilibrium believable? The mounts' static loads and
deflections, and the checks made on them after statics.

:func:`mount_statics` gives each mount's static deflection [m] and force
[N] per direction (u1, u2, u3 of the mount: axial and shear as the mount's
axes define them) at an equilibrium; :func:`mount_table` prints them,
:func:`mount_csv` writes them (what ``flexbed static`` and the run
summaries show, and what a verdict reuses).

Plausibility (:func:`implausibility`): an equilibrium is refused as an
input error when

- a mount's static deflection |Δx| (over its three directions) exceeds
  ``static_deflection_limit`` (default 0.25) times the size of a body it
  carries, or
- a body turns by more than ``static_rotation_limit_deg`` (default 10°)
  from its orientation in the scene.

A body's size is what the scene's sanity checks use
(:func:`flexbed.files.sanity.body_sizes`): the bed's half-diagonal, or the
half-diagonal √(1.5 tr J / m) of the uniform box with the body's mass and
inertia; a mass typed 1000× too large (in g for kg) shrinks it √1000 times
while the deflections grow 1000 times. Real isolators deflect millimetres to a few
centimetres under their equipment, far below a quarter of its length, and
a layout balanced on its mounts tilts by a degree or two at most. Either
limit may be raised (``inf`` turns it off) in ``[solver]``.

Stability (:func:`check_equilibrium`): an unstable equilibrium (a negative
eigenvalue of the stiffness at rest, :mod:`flexbed.dynamics.stability`)
stops the run as a numerical failure unless the user allows it
(``[solver] allow_unstable = true``, or ``--allow-unstable``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from flexbed.dynamics.statics import Equilibrium
from flexbed.dynamics.system import System
from flexbed.errors import InputError, NumericalError
from flexbed.files.sanity import body_sizes as scene_sizes

__all__ = ["MountStatics", "mount_statics", "mount_table", "mount_csv", "body_sizes",
           "implausibility", "check_equilibrium", "DEFLECTION_LIMIT", "ROTATION_LIMIT_DEG"]

#: default largest static mount deflection, as a fraction of the body's size
DEFLECTION_LIMIT = 0.25
#: default largest rotation of a body at its static equilibrium [deg]
ROTATION_LIMIT_DEG = 10.0


@dataclass(frozen=True)
class MountStatics:
    """The mounts at a static equilibrium (M mounts).

    names, body_i, body_j : tuple of str; deflection : (M, 3) [m] and
    force : (M, 3) [N] along the mount's directions u1, u2, u3: the
    deflection Δx = uᵀ(l − l₀) and the law's force f(Δx) (extension and
    tension positive, compression negative).
    """

    names: tuple
    body_i: tuple
    body_j: tuple
    deflection: np.ndarray
    force: np.ndarray


def mount_statics(system: System, y_eq: np.ndarray, eq: Equilibrium | None = None
                  ) -> MountStatics:
    """The mounts' static deflections and forces at the state ``y_eq`` (ny,):
    those ``eq`` kept (:attr:`Equilibrium.mounts`, when ``eq.y`` is
    ``y_eq``), else observed there."""
    if eq is not None and eq.mounts is not None and eq.y is y_eq:
        dx, f = eq.mounts
    else:
        obs = system.observe(0.0, np.asarray(y_eq, dtype=float))
        dx, f = obs.dx, obs.f
    bodies = [b.name for b in system.scene.bodies]
    mounts = system.scene.mounts
    return MountStatics(tuple(m.name for m in mounts),
                        tuple(bodies[i] for i in system.body_i),
                        tuple(bodies[j] for j in system.body_j),
                        np.array(dx, dtype=float), np.array(f, dtype=float))


def mount_table(ms: MountStatics) -> str:
    """The mounts' static loads [N] and deflections [mm] per direction, as
    a Markdown table (round-off below 1e-9 of a mount's largest shown as 0)."""
    lines = ["| mount | between | static force f1, f2, f3 [N] | static deflection "
             "Δx1, Δx2, Δx3 [mm] |", "|---|---|---|---|"]
    for k, name in enumerate(ms.names):
        f, d = _clean(ms.force[k]), _clean(ms.deflection[k]) * 1e3
        lines.append(f"| {name} | {ms.body_i[k]} – {ms.body_j[k]} | "
                     f"{f[0]:.6g}, {f[1]:.6g}, {f[2]:.6g} | {d[0]:.4f}, {d[1]:.4f}, {d[2]:.4f} |")
    return "\n".join(lines)


def _clean(v: np.ndarray) -> np.ndarray:
    """v (3,) with round-off (below 1e-9 of its largest entry) shown as 0."""
    v = np.asarray(v, dtype=float)
    return np.where(np.abs(v) <= 1e-9 * np.abs(v).max(), 0.0, v) + 0.0


def mount_csv(ms: MountStatics) -> str:
    """The same as CSV (SI units)."""
    lines = ["mount,body_i,body_j,f1_N,f2_N,f3_N,dx1_m,dx2_m,dx3_m"]
    for k, name in enumerate(ms.names):
        lines.append(",".join([name, ms.body_i[k], ms.body_j[k]]
                              + [f"{v:.10g}" for v in (*ms.force[k], *ms.deflection[k])]))
    return "\n".join(lines) + "\n"


def body_sizes(sf, system: System) -> np.ndarray:
    """Each body's size [m] (nb,), as the scene's sanity checks measure it
    (:func:`flexbed.files.sanity.body_sizes`: the bed's half-diagonal, the
    half-diagonal of the uniform box of another body's mass and inertia);
    the base's: inf."""
    bodies = system.scene.bodies
    bed_body = None
    if sf.has_bed and len(bodies) > 1:
        bed_body = sf.bed.body or bodies[1].name
    sizes = scene_sizes(system.scene, bed_body, sf.bed)
    return np.array([math.inf] + [sizes[b.name] for b in bodies[1:]])


def _rotation_deg(p0: np.ndarray, p1: np.ndarray) -> float | np.ndarray:
    """The angle [deg] between two orientations (Euler parameters (4,)), or
    between each pair of rows of two (n, 4) arrays ((n,) angles)."""
    p0, p1 = np.asarray(p0, dtype=float), np.asarray(p1, dtype=float)
    c = np.abs(np.sum(p0 * p1, axis=-1)) / (np.sqrt(np.sum(p0 * p0, axis=-1))
                                            * np.sqrt(np.sum(p1 * p1, axis=-1)))
    turn = np.degrees(2.0 * np.arccos(np.minimum(1.0, c)))
    return float(turn) if turn.ndim == 0 else turn


def implausibility(sf, system: System, y_eq: np.ndarray, *,
                   deflection_limit: float = DEFLECTION_LIMIT,
                   rotation_limit_deg: float = ROTATION_LIMIT_DEG,
                   eq: Equilibrium | None = None) -> str:
    """Why the equilibrium ``y_eq`` cannot be what the user meant (one
    sentence naming the body, the mount and the deflection), or "";
    ``eq``: the solve that gave ``y_eq`` (its mounts' values are read,
    :func:`mount_statics`)."""
    ms = mount_statics(system, y_eq, eq)
    size = body_sizes(sf, system)
    names = [b.name for b in system.scene.bodies]
    defl = np.linalg.norm(ms.deflection, axis=1)
    bj, bi = system.body_j, system.body_i
    over_j = (bj > 0) & (defl > deflection_limit * size[bj])
    over_i = (bi > 0) & (defl > deflection_limit * size[bi])
    order = np.argsort(-defl)
    worst = order[(over_j | over_i)[order]]      # the most deflected mount over its limit
    if worst.size:
        k = int(worst[0])
        b = int(bj[k]) if over_j[k] else int(bi[k])
        d = ms.deflection[k] * 1e3
        return (f"mount '{ms.names[k]}' deflects {defl[k] * 1e3:.4g} mm at the static "
                f"equilibrium (Δx1, Δx2, Δx3 = {d[0]:.4g}, {d[1]:.4g}, {d[2]:.4g} mm) "
                f"under body '{names[b]}', more than {deflection_limit:g} of its size "
                f"{size[b]:.3g} m: check its mass "
                f"(kg, not g) and the mounts' stiffness [N/m], or raise [solver] "
                f"static_deflection_limit")
    _, p_eq = system.poses(y_eq)
    turns = _rotation_deg(system.initial_p[1:], p_eq[1:])      # bodies 1, 2, …
    turned = np.flatnonzero(turns > rotation_limit_deg)
    if turned.size:
        b = int(turned[0]) + 1
        on = np.flatnonzero((bi == b) | (bj == b))
        k = int(on[np.argmax(defl[on])]) if on.size else None
        worst = (f"; its most deflected mount '{ms.names[k]}' by {defl[k] * 1e3:.4g} mm"
                 if k is not None else "")
        return (f"body '{names[b]}' turns {turns[b - 1]:.3g}° from its orientation in the "
                f"scene at the static equilibrium, more than {rotation_limit_deg:g}°{worst}: "
                f"check the masses (kg, not g), the mounts' stiffness and positions, or "
                f"raise [solver] static_rotation_limit_deg")
    return ""


def check_equilibrium(sf, system: System, eq: Equilibrium, *,
                      allow_unstable: bool | None = None) -> None:
    """Refuse an implausible equilibrium (InputError, exit 2) or an
    unstable one (NumericalError, exit 1, unless ``allow_unstable``, default
    the scene's ``[solver] allow_unstable``). ``eq`` has been through
    :func:`flexbed.stages.simulation.checked`."""
    s = sf.solver
    why = implausibility(sf, system, eq.y, deflection_limit=s.static_deflection_limit,
                         rotation_limit_deg=s.static_rotation_limit_deg, eq=eq)
    if why:
        raise InputError(f"{sf.source.name}: implausible static equilibrium: {why}")
    allowed = s.allow_unstable if allow_unstable is None else allow_unstable
    if eq.instability is not None and not allowed:
        raise NumericalError(f"{sf.source.name}: {eq.instability.line()}; a run from it would "
                             f"diverge: stopped (set [solver] allow_unstable = true to run it "
                             f"anyway)")

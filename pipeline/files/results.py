"""Results and equilibrium files of the dynamics stages (HDF5 via flexbed.files.store).

``flexbed.results`` 1.2 — one simulation run:

- ``time`` (k,) [s]; root attributes ``complete`` (bool) and ``message``
  (why it is incomplete, or "completed"), ``start`` ("equilibrium" or
  "initial"), ``scene_digest``;
- ``bodies/``: ``names`` (nb,), ``position`` (k, nb, 3) [m] of the centres
  of mass, ``euler_parameters`` (k, nb, 4) [1], ``orientation_deg``
  (k, nb, 3) roll/pitch/yaw, ``velocity`` (k, nb, 3) [m/s],
  ``angular_velocity`` (k, nb, 3) [rad/s] body frame, ``acceleration``,
  ``angular_acceleration``;
- ``mounts/``: ``names``, ``body_i``, ``body_j``, ``deflection``, ``rate``,
  ``force`` (k, M, 3) along the mount axes [m, m/s, N], ``force_i``,
  ``force_j`` (k, M, 3) inertial [N] on P_i and P_j;
- ``contacts/`` (1.2; scenes with bump stops only): ``time`` (n,) [s] the
  instants the integrator located where a stop's contact began or ended,
  ``mount`` (n,) 0-based, ``direction`` (n,) 1–3, ``side`` (n,) −1
  compression, +1 extension, ``begins`` (n,) bool;
- ``energy/``: ``kinetic`` (k, nb), ``gravity_potential`` (k, nb),
  ``mount_potential`` (k, M) [J] (spring parts), ``strain`` (k, nb) [J]
  (flexible bodies, ½aᵀKa), ``work_mount``, ``work_external``,
  ``work_drive``, ``work_structural`` (k,) [J], ``balance`` (k,) [J] =
  kinetic + gravity potential + strain − the four works (constant for an
  exact solution);
- ``modal/``: ``coordinates``, ``rates``, ``accelerations`` (k, n_modal)
  of the flexible bodies [kg^1/2 m, /s, /s²] (empty with a rigid bed);
- ``solver/`` attributes: method, settings and statistics (``method`` is
  the one that ran, ``method_requested`` and ``method_reason`` what was
  asked and why that one ran; ``wall_time`` [s] the solve's own time,
  ``load_time`` [s] loading the compiled code before it);
- ``bed`` attributes: ``model``, ``plate_input_hash`` (the modes file's
  ``input_hash``), ``modes_file`` (its absolute path when written),
  ``modes_file_relative`` (from the results file's folder; 1.1),
  ``n_modes``, ``invariants``, ``rayleigh``, ``damping_ratio``,
  ``static_sag``; post finds the modes file beside the results file by its
  name, then by these paths, and checks it by the hash;
- ``scene/toml`` (the scene file's text) with attributes ``digest``,
  ``statics_digest``, ``source``, ``name``;
- ``initial/position``, ``initial/euler_parameters``: the state at t = 0;
  ``equilibrium/…`` as in the equilibrium file when the run started there.

``flexbed.equilibrium`` 1.0 — the static equilibrium: ``bodies/names``,
``bodies/position`` (nb, 3) [m], ``bodies/euler_parameters`` (nb, 4),
``bodies/orientation_deg`` (nb, 3), ``state/y`` (ny,) the state at rest
(layout: flexbed.dynamics.layout), ``scene/toml``; root attributes ``statics_digest``,
``scene_digest``, ``success``, ``message``, ``iterations``, ``residual``,
``step``, ``tol``, ``stability`` ("stable"; "unstable" when the stiffness
at rest has a negative eigenvalue; "not checked" for an equilibrium read
back from a file) and ``instability`` (the line naming the body and the
direction, or "").
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from flexbed.dynamics.maxwell_terms import relax_states
from flexbed.errors import InputError
from flexbed.files.store import Contents, Dataset, read_file, write_file

if TYPE_CHECKING:   # reading a results file needs neither the dynamics nor the scene reader
    from flexbed.dynamics.integrate import Run
    from flexbed.dynamics.statics import Equilibrium
    from flexbed.dynamics.system import System
    from flexbed.files.scene import SceneFile

__all__ = ["write_results", "read_results", "results_contents", "write_results_contents",
           "write_equilibrium", "read_equilibrium",
           "RESULTS_SCHEMA", "EQUILIBRIUM_SCHEMA"]

RESULTS_SCHEMA = "flexbed.results"
EQUILIBRIUM_SCHEMA = "flexbed.equilibrium"
VERSION = "1.0"
#: 1.1: ``bed`` attribute ``modes_file_relative``; 1.2: the ``contacts/`` group
RESULTS_VERSION = "1.2"


def _scene_part(sf: SceneFile) -> tuple[dict, dict]:
    ds = {"scene/toml": Dataset(sf.text, "", "the scene file this came from")}
    attrs = {"scene": {"digest": sf.digest, "statics_digest": sf.statics_digest,
                       "source": str(sf.source), "name": sf.scene.name}}
    return ds, attrs


def _equilibrium_part(system: System, eq: Equilibrium, prefix: str) -> tuple[dict, dict]:
    pos, p = system.poses(eq.y)
    from flexbed.dynamics.rotation import angles_from_p
    ds = {
        f"{prefix}position": Dataset(pos, "m", "centre-of-mass positions at equilibrium"),
        f"{prefix}euler_parameters": Dataset(p, "1", "Euler parameters (scalar first)"),
        f"{prefix}orientation_deg": Dataset(np.degrees(angles_from_p(p)), "deg",
                                            "roll, pitch, yaw (X-Y-Z about body axes)"),
    }
    attrs = {"success": bool(eq.success), "message": eq.message, "iterations": int(eq.iterations),
             "residual": float(eq.residual), "step": float(eq.step), "tol": float(eq.tol),
             "rhs_evaluations": int(eq.rhs_evaluations), "wall_time": float(eq.wall_time),
             "stability": eq.stability,
             "instability": eq.instability.line() if eq.instability is not None else ""}
    return ds, attrs


def _relative(target, start_file) -> str:
    """``target``'s path relative to the folder of ``start_file`` ("" when
    there is none, e.g. another drive)."""
    try:
        return os.path.relpath(Path(target).resolve(), Path(start_file).resolve().parent)
    except ValueError:
        return ""


def write_equilibrium(path, sf: SceneFile, system: System, eq: Equilibrium) -> Path:
    """Write the equilibrium file atomically; returns its path."""
    ds, sattrs = _scene_part(sf)
    names = np.array([b.name for b in system.scene.bodies])
    ds["bodies/names"] = Dataset(names, "", "body names, body 1 = base")
    eds, eattrs = _equilibrium_part(system, eq, "bodies/")
    ds.update(eds)
    ds["state/y"] = Dataset(eq.y, "SI", "state at rest, layout of flexbed.dynamics.layout")
    root = dict(eattrs, statics_digest=sf.statics_digest, scene_digest=sf.digest)
    return write_file(path, schema=EQUILIBRIUM_SCHEMA, version=VERSION, datasets=ds,
                      attrs={"": root, **sattrs})


def read_equilibrium(path, sf: SceneFile, system: System) -> np.ndarray:
    """The state at rest stored in an equilibrium file, checked against the scene.

    Raises InputError if it belongs to another scene (statics digest), does
    not fit the state layout, or records a failed solve.
    """
    c = read_file(path, schema=EQUILIBRIUM_SCHEMA, major=1, required=("state/y",))
    root = c.attrs.get("", {})
    if root.get("statics_digest") != sf.statics_digest:
        raise InputError(f"{path}: equilibrium of another scene (statics digest "
                         f"{str(root.get('statics_digest'))[:12]}…, this scene "
                         f"{sf.statics_digest[:12]}…): run 'flexbed static' again")
    if not root.get("success", False):
        raise InputError(f"{path}: records a failed static solve: {root.get('message')}")
    y = np.asarray(c.get("state/y"), dtype=float)
    lay = system.layout
    if lay.n_internal and y.shape == (system.ny - lay.n_internal,):
        # the statics' state of the scene without Maxwell states: theirs at rest
        y = relax_states(system, np.concatenate([y[:lay.internal.start],
                                                 np.zeros(lay.n_internal), y[lay.internal.start:]]))
    if y.shape != (system.ny,):
        raise InputError(f"{path}: dataset 'state/y' has shape {y.shape}, "
                         f"this scene needs ({system.ny},)")
    return y


def write_results(path, sf: SceneFile, system: System, run: Run, *, start: str,
                  equilibrium: Equilibrium | None = None, modes_path=None,
                  model: dict | None = None) -> Path:
    """Write a run (complete or not) atomically; returns the path.

    ``modes_path``: the modes file a flexible bed was built from (recorded
    with the plate's input hash, which the modes file carries too).
    ``model``: the model's attributes (:meth:`flexbed.stages.motion.Motion.attrs`);
    default: the nonlinear model."""
    ds, attrs = results_contents(sf, system, run, start=start, equilibrium=equilibrium,
                                 modes_path=modes_path, model=model)
    return write_results_contents(path, ds, attrs)


def write_results_contents(path, datasets: dict, attrs: dict) -> Path:
    """Write what :func:`results_contents` gave as a results file, atomically
    (with the modes file's path relative to it, ``bed/modes_file_relative``)."""
    bed = dict(attrs.get("bed", {}))
    bed["modes_file_relative"] = (_relative(bed["modes_file"], path) if bed.get("modes_file")
                                  else "")
    attrs = {**attrs, "bed": bed}
    return write_file(path, schema=RESULTS_SCHEMA, version=RESULTS_VERSION, datasets=datasets,
                      attrs=attrs)


def results_contents(sf: SceneFile, system: System, run: Run, *, start: str,
                     equilibrium: Equilibrium | None = None, modes_path=None,
                     model: dict | None = None) -> tuple[dict, dict]:
    """The datasets and group attributes of a run's results file (the file's
    layout above), in memory: (``{path: Dataset}``, ``{group: attrs}``)."""
    from flexbed.dynamics.history import history
    h = history(system, run.t, run.y)
    ds, sattrs = _scene_part(sf)
    sc = system.scene
    ds["time"] = Dataset(run.t, "s", "output times")
    ds["bodies/names"] = Dataset(np.array([b.name for b in sc.bodies]), "", "body 1 = base")
    body = {
        "position": ("m", "centre-of-mass position, inertial frame"),
        "euler_parameters": ("1", "Euler parameters, scalar first"),
        "velocity": ("m/s", "centre-of-mass velocity, inertial frame"),
        "angular_velocity": ("rad/s", "angular velocity, body frame"),
        "acceleration": ("m/s^2", "centre-of-mass acceleration, inertial frame"),
        "angular_acceleration": ("rad/s^2", "angular acceleration, body frame"),
    }
    for key, (unit, what) in body.items():
        ds[f"bodies/{key}"] = Dataset(h[key], unit, what)
    ds["bodies/orientation_deg"] = Dataset(np.degrees(h["orientation"]), "deg",
                                           "roll, pitch, yaw (X-Y-Z about body axes)")
    ds["mounts/names"] = Dataset(np.array([m.name for m in sc.mounts] or [""])[:len(sc.mounts)],
                                 "", "mount names")
    ds["mounts/body_i"] = Dataset(np.array([m.body_i for m in sc.mounts] or [""])[:len(sc.mounts)],
                                  "", "reference body i")
    ds["mounts/body_j"] = Dataset(np.array([m.body_j for m in sc.mounts] or [""])[:len(sc.mounts)],
                                  "", "body j")
    mount = {
        "deflection": ("m", "Δx_k = u_kᵀ(l − l0) per mount and axis (eq. 2)"),
        "rate": ("m/s", "Δẋ_k = u_kᵀ l̇ (eq. 3)"),
        "force": ("N", "f_k along the mount axes (eq. 1)"),
        "force_i": ("N", "force on P_i, inertial frame (eq. 4)"),
        "force_j": ("N", "force on P_j, inertial frame (eq. 4)"),
    }
    for key, (unit, what) in mount.items():
        ds[f"mounts/{key}"] = Dataset(h[key], unit, what)
    if system.laws.stopped.size:
        ds.update(_contacts_part(run.events))
    ds["energy/kinetic"] = Dataset(h["kinetic"], "J", "kinetic energy per body")
    ds["energy/gravity_potential"] = Dataset(h["gravity_potential"], "J", "−m gᵀr per body")
    ds["energy/mount_potential"] = Dataset(h["mount_potential"], "J",
                                           "∫ f_spring dΔx per mount (spring parts)")
    for i, key in enumerate(("work_mount", "work_external", "work_drive", "work_structural")):
        ds[f"energy/{key}"] = Dataset(h["work"][:, i], "J", {
            0: "work of all mount forces on the bodies (springs and dampers)",
            1: "work of the external loads (the base's, its support, loads on bodies)",
            2: "work of the force that drives the base",
            3: "work of the flexible bodies' structural (modal) damping"}[i])
    ds["energy/strain"] = Dataset(h["strain"], "J", "elastic energy of flexible bodies, ½aᵀKa")
    ds["energy/balance"] = Dataset(h["balance"], "J", "kinetic + gravity potential + strain "
                                   "− works: constant if exact")
    ds["modal/coordinates"] = Dataset(h["modal"], "kg^1/2 m",
                                      "modal coordinates a of the flexible bodies")
    ds["modal/rates"] = Dataset(h["modal_rate"], "kg^1/2 m/s", "modal rates da/dt")
    ds["modal/accelerations"] = Dataset(h["modal_acceleration"], "kg^1/2 m/s^2",
                                        "modal accelerations d2a/dt2")
    y0 = run.y[0] if len(run.t) else system.initial_state()
    pos0, p0 = system.poses(y0)
    ds["initial/position"] = Dataset(pos0, "m", "positions at t = 0")
    ds["initial/euler_parameters"] = Dataset(p0, "1", "Euler parameters at t = 0")
    st = run.stats
    se = run.settings
    solver_attrs = {
        "method": st.method, "t_end": se.t_end, "dt": se.dt, "rtol": se.rtol, "atol": se.atol,
        "output_dt": se.output_dt, "steps": st.steps, "rejected_steps": st.rejected,
        "rejected_source": st.rejected_source, "rhs_evaluations": st.rhs_evaluations,
        "jacobian_evaluations": st.jacobian_evaluations,
        "lu_decompositions": st.lu_decompositions, "segments": st.segments,
        "wall_time": st.wall_time, "load_time": st.load_time,
        "method_requested": st.requested or st.method, "method_reason": st.reason,
        "t_reached": run.t_reached,
    }
    solver_attrs.update(model or {"model": "nonlinear", "model_requested": "nonlinear",
                                  "model_reason": "requested"})
    attrs = {"": {"complete": bool(run.complete), "message": run.message, "start": start,
                  "scene_digest": sf.digest},
             "solver": solver_attrs, **sattrs}
    bed = sf.bed
    flex = dict(system.scene.flexible)
    attrs["bed"] = {
        "model": "flexible" if flex else "rigid",
        "plate_input_hash": bed.plate.digest(),
        "modes_file": str(Path(modes_path).resolve()) if (flex and modes_path) else "",
        "n_modes": int(sum(fb.n_modes for fb in flex.values())),
        "invariants": ("full" if all(fb.full for fb in flex.values()) else "first_order")
        if flex else "",
        "rayleigh": np.array(bed.rayleigh, dtype=float),
        "damping_ratio": np.array(bed.damping_ratio or (), dtype=float),
        "static_sag": bool(bed.static_sag),
    }
    for fb in flex.values():
        ds["modal/damping"] = Dataset(fb.modal_damping, "s^-1", "modal damping matrix C_aa")
        ds["modal/stiffness"] = Dataset(fb.modal_stiffness, "s^-2",
                                        "modal stiffness matrix K_aa")
        if fb.basis is not None:
            ds["modal/basis"] = Dataset(fb.basis, "1", "the modal coordinates in terms of the "
                                        "modes file's modes: a_file = basis @ a (the kept "
                                        "modes, then the static correction's residual "
                                        "vectors)")
    if equilibrium is not None:
        eds, eattrs = _equilibrium_part(system, equilibrium, "equilibrium/")
        ds.update(eds)
        attrs["equilibrium"] = eattrs
    return ds, attrs


def _contacts_part(events) -> dict:
    """The ``contacts/`` datasets of a run's bump-stop events (1.2)."""
    ev = list(events)
    return {
        "contacts/time": Dataset(np.array([e.t for e in ev], dtype=float), "s",
                                 "instants a bump stop's contact began or ended"),
        "contacts/mount": Dataset(np.array([e.mount for e in ev], dtype=np.int64), "1",
                                  "the mount, 0-based (as mounts/names)"),
        "contacts/direction": Dataset(np.array([e.direction + 1 for e in ev], dtype=np.int64),
                                      "1", "the mount direction, 1 to 3"),
        "contacts/side": Dataset(np.array([e.side for e in ev], dtype=np.int64), "1",
                                 "-1 compression stop, +1 extension stop"),
        "contacts/begins": Dataset(np.array([e.begins for e in ev], dtype=bool), "",
                                   "true: contact began; false: it ended"),
    }


def read_results(path) -> Contents:
    """Read a results file (schema flexbed.results 1.x)."""
    return read_file(path, schema=RESULTS_SCHEMA, major=1,
                     required=("time", "bodies/position", "bodies/euler_parameters"))

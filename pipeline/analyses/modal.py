"""The mounted system's modes for a scene: set-up, tables, CSV text.

:func:`mounted` builds the linear mounted system about the static
equilibrium (solved here, or read from an equilibrium file) with the base
held; :func:`modal_tables` formats :class:`flexbed.dynamics.frequency.modal.Modes`
for the terminal and as CSV.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from flexbed.dynamics.frequency.modal import Modes
from flexbed.dynamics.frequency.mounted import MountedSystem, mounted_system
from flexbed.analyses.elastomer import modes_of, with_elastomers
from flexbed.dynamics.system import System
from flexbed.errors import NumericalError
from flexbed.files.modes import ModesData
from flexbed.files.results import read_equilibrium
from flexbed.files.scene import SceneFile
from flexbed.stages.simulation import equilibrium

__all__ = ["Mounted", "mounted", "modes_csv", "energy_csv", "strain_csv",
           "effective_mass_csv", "modes_text", "energy_text", "effective_mass_text"]


@dataclass(frozen=True)
class Mounted:
    """A scene's linear mounted system and its modes.

    system : System; y_eq : (ny,) the equilibrium; ms : MountedSystem;
    modes : Modes; solve_time : float — CPU seconds of the linearisation
    and the eigen-solution (the equilibrium and loading the compiled
    right-hand side not included); source : str —
    where the equilibrium came from.
    """

    system: System
    y_eq: np.ndarray
    ms: MountedSystem
    modes: Modes
    solve_time: float
    source: str
    bed_modes: ModesData | None


def mounted(sf: SceneFile, system: System, *, y_eq: np.ndarray | None = None,
            equilibrium_file: str | Path | None = None,
            bed_modes: ModesData | None = None) -> Mounted:
    """Linearise the scene about its equilibrium and solve its modes.

    ``y_eq`` given, or read from ``equilibrium_file`` (checked against the
    scene), or else solved by Newton–Raphson. NumericalError when the
    equilibrium is unstable (a negative eigenvalue of the stiffness)."""
    if y_eq is not None:
        source = "given"
    elif equilibrium_file is not None:
        y_eq = read_equilibrium(equilibrium_file, sf, system)
        source = str(equilibrium_file)
    else:
        y_eq = equilibrium(sf, system).y
        source = "solved"
    system.rhs(0.0, y_eq)                        # load the compiled code outside the timing
    system.rhs_batch(np.zeros(1), np.asarray(y_eq, dtype=float)[None, :], capture=("w_f",))
    t0 = time.process_time()
    ms = with_elastomers(mounted_system(system, y_eq), system, sf.elastomers)
    md = modes_of(ms, sf.source.name)
    cpu = time.process_time() - t0
    bad = np.flatnonzero(~np.isfinite(md.undamped_frequency))
    if bad.size:
        raise NumericalError(f"{sf.source.name}: the equilibrium is unstable: the linearised "
                             f"stiffness has {bad.size} negative eigenvalue(s); no modes")
    return Mounted(system, np.asarray(y_eq, dtype=float), ms, md, cpu, source, bed_modes)


# ------------------------------------------------------------------ tables
def _row(values, fmt: str) -> str:
    """The values as ``format(v, fmt)``, comma-separated: one ``%`` over
    the row (the same conversion, so the same text; 1.6 times faster on the
    million cells of a large raft's strain table)."""
    values = np.asarray(values, dtype=float).ravel()
    return ",".join(["%" + fmt] * values.size) % tuple(values.tolist())


def modes_csv(md: Modes) -> str:
    """mode, natural and damped frequency [Hz], damping ratio [1]."""
    lines = ["mode,frequency_Hz,damped_frequency_Hz,damping_ratio"]
    for k in range(md.frequency.size):
        lines.append(f"{k + 1}," + _row([md.frequency[k], md.damped_frequency[k],
                                         md.damping_ratio[k]], ".12g"))
    return "\n".join(lines) + "\n"


def energy_csv(ms: MountedSystem, md: Modes) -> str:
    """Kinetic energy share [%] per mode (rows) and coordinate (columns)."""
    head = "mode,frequency_Hz," + ",".join(f"{lab}_pct" for lab in ms.labels)
    lines = [head]
    for k in range(md.frequency.size):
        lines.append(f"{k + 1},{md.frequency[k]:.10g}," + _row(100.0 * md.energy[k], ".8f"))
    return "\n".join(lines) + "\n"


def strain_csv(names: list[str], md: Modes) -> str:
    """Strain energy share [%] per mode of each mount axis and of the bed's
    own deformation."""
    cols = [f"{m}_{d}_pct" for m in names for d in ("1", "2", "3")] + ["elastic_pct"]
    lines = ["mode,frequency_Hz," + ",".join(cols)]
    for k in range(md.frequency.size):
        lines.append(f"{k + 1},{md.frequency[k]:.10g}," + _row(
            np.concatenate([100.0 * md.strain_mounts[k].ravel(), [100.0 * md.strain_elastic[k]]]),
            ".8f"))
    return "\n".join(lines) + "\n"


def effective_mass_csv(md: Modes) -> str:
    """Effective mass [kg] along X, Y, Z per undamped mode and cumulative [%]."""
    lines = ["mode,frequency_Hz,mass_X_kg,mass_Y_kg,mass_Z_kg,cumulative_X_pct,"
             "cumulative_Y_pct,cumulative_Z_pct"]
    cum = 100.0 * md.cumulative_mass_fraction
    for k in range(md.undamped_frequency.size):
        lines.append(f"{k + 1},{md.undamped_frequency[k]:.10g}," +
                     _row(md.effective_mass[k], ".10g") + "," + _row(cum[k], ".6f"))
    return "\n".join(lines) + "\n"


def modes_text(ms: MountedSystem, md: Modes) -> str:
    """The modes with their dominant coordinates (kinetic energy ≥ 10 %)."""
    lines = [f"{'mode':>4}  {'f [Hz]':>10}  {'zeta':>8}  dominant kinetic energy"]
    for k in range(md.frequency.size):
        order = np.argsort(-md.energy[k])
        dom = ", ".join(f"{ms.labels[j]} {100 * md.energy[k, j]:.1f}%" for j in order[:3]
                        if md.energy[k, j] >= 0.1)
        lines.append(f"{k + 1:>4}  {md.frequency[k]:>10.4f}  {md.damping_ratio[k]:>8.5f}  {dom}")
    return "\n".join(lines)


def energy_text(ms: MountedSystem, md: Modes, body_names: list[str]) -> str:
    """The decoupling table: per mode, the kinetic energy share [%] of each
    body's x, y, z, roll, pitch, yaw (rows of bodies) as a Markdown table."""
    bodies = [b for b in body_names if any(lab.startswith(b + " ") for lab in ms.labels)]
    dof = ("x", "y", "z", "roll", "pitch", "yaw")
    cols = [(b, d) for b in bodies for d in dof]
    idx = {lab: j for j, lab in enumerate(ms.labels)}
    elastic = [j for j, lab in enumerate(ms.labels) if " mode " in lab]
    head = "| mode | f [Hz] | " + " | ".join(f"{b} {d}" for b, d in cols)
    head += " | bed modes |" if elastic else " |"
    lines = [head, "|" + "---|" * (2 + len(cols) + bool(elastic))]
    for k in range(md.frequency.size):
        vals = [100.0 * md.energy[k, idx[f"{b} {d}"]] for b, d in cols]
        if elastic:
            vals.append(100.0 * md.energy[k, elastic].sum())
        lines.append(f"| {k + 1} | {md.frequency[k]:.3f} | " +
                     " | ".join(f"{round(v, 1) + 0.0:.1f}" for v in vals) + " |")
    return "\n".join(lines)


def effective_mass_text(md: Modes) -> str:
    """Effective masses and their cumulative shares, as a Markdown table."""
    cum = 100.0 * md.cumulative_mass_fraction
    lines = ["| mode | f [Hz] | m_X [kg] | m_Y [kg] | m_Z [kg] | Σ X [%] | Σ Y [%] | Σ Z [%] |",
             "|---|---|---|---|---|---|---|---|"]
    for k in range(md.undamped_frequency.size):
        e = np.round(md.effective_mass[k], 2) + 0.0          # no "-0.00"
        lines.append(f"| {k + 1} | {md.undamped_frequency[k]:.3f} | {e[0]:.2f} | {e[1]:.2f} | "
                     f"{e[2]:.2f} | {cum[k, 0]:.2f} | {cum[k, 1]:.2f} | {cum[k, 2]:.2f} |")
    lines.append(f"\nmoving mass (everything but the base): {md.moving_mass:.3f} kg")
    return "\n".join(lines)

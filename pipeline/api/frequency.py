"""The mounted system in the frequency domain as library calls: its modes
(:func:`modal`, :class:`Modal`) and its transmissibility (:func:`frf`,
:class:`Transmissibility`), and the files the commands write of them.

>>> import flexbed
>>> scene = flexbed.load_scene()
>>> m = flexbed.modal(scene)                                   # doctest: +SKIP
>>> m.frequency, m.damping_ratio, m.energy, m.effective_mass   # doctest: +SKIP
>>> m.save("lee1999-modal")                                    # doctest: +SKIP
>>> t = flexbed.frf(scene, input="base z", band=(1, 40))       # doctest: +SKIP
>>> t.magnitude[:, t.column("A top az")]                       # doctest: +SKIP
>>> t.save("lee1999-frf")                                      # doctest: +SKIP
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

import numpy as np

from flexbed.analyses import frf as afrf
from flexbed.analyses import frf_loads
from flexbed.analyses.frf import MAX_GRID
from flexbed.analyses import modal as amodal
from flexbed.analyses.points import Point
from flexbed.api import bed_modes
from flexbed.api.arguments import Arguments
from flexbed.api.equilibrium import Statics
from flexbed.files.destination import check_destination, write_text
from flexbed.errors import InputError
from flexbed.files.frequency import frf_contents, modal_contents, write_frf_contents, \
    write_modal_contents
from flexbed.files.modes import ModesData
from flexbed.files.scene import SceneFile
from flexbed.threads import limited

__all__ = ["modal", "frf", "Modal", "Transmissibility", "modal_files", "frf_files"]


class Modal:
    """The mounted system's modes (:func:`modal`).

    Arrays (m modes, n coordinates, M mounts): ``frequency``,
    ``damped_frequency`` (m,) [Hz], ``damping_ratio`` (m,) [1], ``shapes``
    (m, n) complex, ``labels`` (n,) what each coordinate is, ``energy``
    (m, n) kinetic energy shares [1], ``strain_mounts`` (m, M, 3) and
    ``strain_elastic`` (m,) strain energy shares [1], ``undamped_frequency``
    (n,) [Hz], ``effective_mass`` (n, 3) [kg], ``cumulative_mass`` (n, 3)
    [1], ``moving_mass`` [kg], ``overdamped_rates`` (r,) [1/s] (real roots:
    overdamped motions, no modes), ``M``, ``K``, ``C`` (n, n); ``solve_time``
    [s CPU]; ``mounted``: the :class:`flexbed.analyses.modal.Mounted`.
    """

    def __init__(self, scene: SceneFile, mt: amodal.Mounted):
        self.scene = scene
        self.mounted = mt
        md, ms = mt.modes, mt.ms
        self.frequency, self.damped_frequency = md.frequency, md.damped_frequency
        self.damping_ratio, self.shapes, self.labels = md.damping_ratio, md.shapes, ms.labels
        self.energy, self.strain_mounts = md.energy, md.strain_mounts
        self.strain_elastic = md.strain_elastic
        self.undamped_frequency, self.effective_mass = md.undamped_frequency, md.effective_mass
        self.cumulative_mass = md.cumulative_mass_fraction
        self.moving_mass = md.moving_mass
        self.overdamped_rates = md.overdamped_rates
        self.M, self.K, self.C = ms.M, ms.K, ms.C
        self.solve_time = mt.solve_time

    def energy_table(self) -> str:
        """The decoupling table (Markdown)."""
        return amodal.energy_text(self.mounted.ms, self.mounted.modes,
                                  [b.name for b in self.mounted.system.scene.bodies])

    def save(self, prefix: str | Path) -> list[Path]:
        """Write ``PREFIX.h5`` and the CSV tables (as ``flexbed modal -o PREFIX``,
        without the plot and the mode shapes); returns the paths."""
        return save_files(prefix, modal_files(self.scene, self.mounted))


class Transmissibility:
    """A frequency response (:func:`frf`): ``frequency`` (k,) [Hz], ``names``,
    ``units`` (o,), ``H`` (k, o) complex, ``magnitude``, ``phase_deg``,
    ``isolation`` (k, o) [1], ``resonances`` (m,) [Hz], ``peaks`` (P, 3),
    ``solve_time`` [s CPU]; ``column(name)`` the index of an output."""

    def __init__(self, scene: SceneFile, r: afrf.FRF):
        self.scene = scene
        self.result = r
        for key in ("frequency", "names", "units", "H", "resonances", "damping_ratio", "peaks",
                    "solve_time", "evaluations", "input"):
            setattr(self, key, getattr(r, key))
        self.magnitude, self.phase_deg, self.isolation = r.magnitude, r.phase_deg, r.isolation

    def column(self, name: str) -> int:
        return self.result.column(name)

    def save(self, prefix: str | Path) -> list[Path]:
        """Write ``PREFIX.h5`` and ``PREFIX.csv`` (as ``flexbed frf -o PREFIX``,
        without the plots); returns the paths."""
        return save_files(prefix, frf_files(self.scene, self.result))


def modal_files(scene: SceneFile, mt: amodal.Mounted, *, shapes: bool = False) -> dict:
    """The files ``flexbed modal -o PREFIX --no-plots`` writes, in memory:
    suffix (``".h5"``, ``"-modes.csv"``, ``"-energy.csv"``,
    ``"-strain.csv"``, ``"-effective-mass.csv"``, with ``shapes``
    ``"-shapes.xdmf"``, which writes ``-shapes.h5`` beside it) →
    ``(writer, args)``; ``writer(path, *args)`` writes that file (plain
    functions and data: they pickle, so a study's worker hands them to the
    client, which writes them)."""
    md = mt.modes
    files = {".h5": (write_modal_contents, modal_contents(scene, mt)),
             "-modes.csv": (write_text, (amodal.modes_csv(md),)),
             "-energy.csv": (write_text, (amodal.energy_csv(mt.ms, md),)),
             "-strain.csv": (write_text, (amodal.strain_csv([m.name for m in
                                                             mt.system.scene.mounts], md),)),
             "-effective-mass.csv": (write_text, (amodal.effective_mass_csv(md),))}
    if shapes:
        from flexbed.analyses.mode_shapes import mode_shape_meshes
        from flexbed.files.mode_shapes import write_mode_shapes
        files["-shapes.xdmf"] = (write_mode_shapes, (mode_shape_meshes(scene, mt), md.frequency,
                                                     md.damping_ratio))
    return files


def frf_files(scene: SceneFile, r: afrf.FRF) -> dict:
    """The files ``flexbed frf -o PREFIX --no-plots`` writes, in memory:
    ``".h5"`` and ``".csv"`` → ``(writer, args)`` (as :func:`modal_files`)."""
    return {".h5": (write_frf_contents, frf_contents(scene, r)),
            ".csv": (write_text, (afrf.frf_csv(r),))}


def save_files(prefix, files: dict) -> list[Path]:
    """Write ``files`` (suffix → ``(writer, args)``, as :func:`modal_files`
    gives them) to ``prefix`` + suffix, every destination checked first;
    return the paths written."""
    paths = [check_destination(Path(str(prefix) + suffix)) for suffix in files]
    for path, (writer, args) in zip(paths, files.values()):
        writer(path, *args)
    return paths


def mounted_for(scene: SceneFile, modes: ModesData | None, equilibrium,
                check: Arguments) -> amodal.Mounted:
    """The linearised mounted system of ``scene`` about ``equilibrium`` (a
    Statics, an equilibrium file, a Modal whose linearisation is reused, or
    None: solved here), with the bed's ``modes`` (computed when a flexible
    bed has none); bad arguments are reported through ``check``."""
    if not (equilibrium is None or isinstance(equilibrium, (Modal, Statics, str, Path))):
        check.bad("equilibrium", equilibrium, "a Statics from flexbed.statics, an "
                                              "equilibrium file, a Modal, or None")
    if isinstance(equilibrium, Statics) and \
            equilibrium.scene.statics_digest != scene.statics_digest:
        check.fail("", f"equilibrium: it is the equilibrium of another scene "
                       f"({equilibrium.scene.source.name}: its bodies, mounts or bed differ)")
    if isinstance(equilibrium, (str, Path)):
        equilibrium = check.path(equilibrium, "equilibrium")
    if isinstance(equilibrium, Modal):           # its linearisation and modes, as they are
        if equilibrium.scene.digest != scene.digest:
            check.fail("", "equilibrium: the Modal given is of another scene")
        return equilibrium.mounted
    if scene.bed.flexible and modes is None:
        modes = bed_modes.modes(scene)
    if equilibrium is not None and not isinstance(equilibrium, (str, Path)):
        return amodal.mounted(scene, equilibrium.system, y_eq=equilibrium.equilibrium.y,
                              bed_modes=modes)
    system = bed_modes.compiled(scene, modes)
    return amodal.mounted(scene, system, equilibrium_file=equilibrium, bed_modes=modes)


@limited()
def modal(scene: SceneFile, *, modes: ModesData | None = None, equilibrium=None) -> Modal:
    """Modes of the mounted system about its static equilibrium, base held.

    Parameters
    ----------
    scene : SceneFile
    modes : ModesData, optional
        A flexible bed's modes (default: computed in memory).
    equilibrium : Statics or path, optional
        From :func:`flexbed.statics`, or an equilibrium file (default:
        solved here).
    """
    check = Arguments("modal")
    scene, modes = check.scene(scene), check.modes(modes)
    return Modal(scene, mounted_for(scene, modes, equilibrium, check))


@limited()
def frf(scene: SceneFile, *, input: str = "base z",
        force_at: tuple[str, Sequence[float]] | None = None,
        points: Sequence[tuple] | None = None, band: tuple[float, float] | None = None,
        n: int = 400, frequencies: Sequence[float] | None = None,
        modes: ModesData | None = None, equilibrium=None, quantity: str = "acceleration",
        deflections: bool = False) -> Transmissibility:
    """Transmissibility of the mounted system.

    Parameters
    ----------
    scene : SceneFile
    input : str
        "base x|y|z": unit base acceleration [m/s²]; "force x|y|z": unit
        force [N] at ``force_at`` = (body, position [m] in its frame);
        "load NAME": the scene's [[load]] NAME per unit [N or N m], or its
        [[unbalance]] NAME per newton of its rotating force m·e·Ω²
        (:mod:`flexbed.analyses.frf_loads`).
    points : sequence of (name, body, position) or (name, body, position,
        relative_to), optional
        Default: the scene's [[point]] tables, else every body's centre of mass.
    band : (f_min, f_max) [Hz], optional
    n : int
        Log-spaced frequencies of the base grid (each resonance adds its own).
    frequencies : sequence [Hz], optional
        Exactly these frequencies, no refinement.
    modes, equilibrium : as in :func:`modal`; ``equilibrium`` may also be
        this scene's :class:`Modal` (its linearisation and modes reused:
        the same numbers as solving them again, without the cost).
    quantity : str
        The points' "acceleration" (default), "velocity" or "displacement"
        (relative displacement for points given with ``relative_to``).
    deflections : bool
        Also the mounts' deflections (columns ``<mount> d1..d3``).
    """
    check = Arguments("frf")
    if quantity not in afrf.QUANTITIES:
        check.bad("quantity", quantity, "'acceleration', 'velocity' or 'displacement'")
    if not isinstance(deflections, bool):
        check.bad("deflections", deflections, "True or False")
    scene, modes = check.scene(scene), check.modes(modes)
    input = check.string("", "input", input)
    load = frf_loads.load_name(input)
    if load is not None:                    # a scene's load: refused here if it has none
        if force_at is not None:
            check.bad("force_at", force_at, "None with input = 'load NAME' (a load acts where "
                                            "the scene puts it)")
        frf_loads.scene_load(scene, load, f"flexbed.frf: input = {input!r}")
    pts = check.points(points, "points")
    at = None
    kind = "load"
    if load is None:
        try:
            kind, _ = afrf.parse_input(input)
        except InputError:
            check.bad("input", input, "'base x|y|z', 'force x|y|z' or 'load NAME'")
    if kind == "base" and force_at is not None:
        check.bad("force_at", force_at, f"None with input = {input!r} (it moves the base)")
    if kind == "force" and force_at is None:
        check.bad("force_at", force_at, f"(body, [x, y, z]) with input = {input!r}: the point "
                                        f"the force acts at")
    if force_at is not None:
        if isinstance(force_at, (str, bytes)) or not isinstance(force_at, (tuple, list)) \
                or len(force_at) != 2:
            check.bad("force_at", force_at, "(body, [x, y, z]), metres in the body's frame")
        at = Point("force", check.name(force_at[0], "force_at body"),
                   check.position(force_at[1], "force_at position"))
    band = check.band(band)
    n = check.integer(n, "n", minimum=2, maximum=MAX_GRID)
    freqs = None
    if frequencies is not None:
        if isinstance(frequencies, (str, bytes)) or not hasattr(frequencies, "__len__") \
                or not 0 < len(frequencies) <= MAX_GRID:
            check.bad("frequencies", frequencies, f"a list of 1 to {MAX_GRID:,} frequencies "
                                                  f"[Hz]")
        freqs = np.array([check.real(f, f"frequencies[{i}]", positive=True, optional=False)
                          for i, f in enumerate(frequencies)])
    names = [b.name for b in scene.scene.bodies]
    for key, body in ([("force_at body", at.body)] if at else []) + \
            [(f"points[{i}] body", p.body) for i, (p, _) in enumerate(pts or [])] + \
            [(f"points[{i}] relative_to", r) for i, (_, r) in enumerate(pts or []) if r]:
        if body not in names:
            check.bad(key, body, f"a body of {scene.source.name} ({', '.join(names)})")
    mt = mounted_for(scene, modes, equilibrium, check)
    return Transmissibility(scene, afrf.frequency_response(
        scene, mt, input=input, force_at=at, points=pts, band=band, n=n, frequencies=freqs,
        quantity=quantity, deflections=deflections))

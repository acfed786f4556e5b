"""A run's results as an object: the datasets of its results file in memory,
the motion of any point afterwards, and the shock response spectra.

>>> import flexbed
>>> run = flexbed.simulate(flexbed.load_scene(), t_end=1.0)            # doctest: +SKIP
>>> run.t, run.position[:, 2], run.mount_force                         # doctest: +SKIP
>>> top = run.point("equipment A", [0, 0, 0.15], relative_to="bed")  # doctest: +SKIP
>>> again = flexbed.open_results("lee1999.h5")                       # doctest: +SKIP
>>> spectra = flexbed.srs(again, point="A=equipment A:0,0,0")         # doctest: +SKIP
"""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from flexbed.analyses.points import Point, PointMotion, Run
from flexbed.errors import FlexbedWarning, InputError
from flexbed.files.modes import ModesData
from flexbed.files.results import read_results, write_results_contents
from flexbed.files.store import Contents

__all__ = ["Results", "open_results", "srs"]


class Results:
    """A run: the datasets of its results file, in memory.

    Arrays (k samples, nb bodies, M mounts): ``t`` (k,) [s]; ``position``,
    ``velocity``, ``acceleration`` (k, nb, 3) of the centres of mass
    [m, m/s, m/s²], inertial; ``euler_parameters`` (k, nb, 4);
    ``orientation_deg`` (k, nb, 3); ``angular_velocity``,
    ``angular_acceleration`` (k, nb, 3) body frame [rad/s, rad/s²];
    ``mount_deflection``, ``mount_rate``, ``mount_force`` (k, M, 3) along
    the mount axes [m, m/s, N]; ``modal_coordinates`` (k, n). Every dataset
    of the file by its path: ``results["energy/balance"]``.
    ``complete`` / ``message`` say whether the run reached its end.
    """

    def __init__(self, contents: Contents, *, modes: ModesData | None = None,
                 modes_file: str | Path | None = None, datasets: tuple | None = None):
        self.contents = contents
        self._modes = modes
        self._modes_file = modes_file
        self._datasets = datasets
        self._post: Run | None = None

    # the file's datasets
    def __getitem__(self, name: str) -> Any:
        return self.contents.get(name)

    def _array(self, name: str) -> np.ndarray:
        return np.asarray(self.contents.get(name))

    t = property(lambda self: self._array("time"))
    position = property(lambda self: self._array("bodies/position"))
    velocity = property(lambda self: self._array("bodies/velocity"))
    acceleration = property(lambda self: self._array("bodies/acceleration"))
    euler_parameters = property(lambda self: self._array("bodies/euler_parameters"))
    orientation_deg = property(lambda self: self._array("bodies/orientation_deg"))
    angular_velocity = property(lambda self: self._array("bodies/angular_velocity"))
    angular_acceleration = property(lambda self: self._array("bodies/angular_acceleration"))
    mount_deflection = property(lambda self: self._array("mounts/deflection"))
    mount_rate = property(lambda self: self._array("mounts/rate"))
    mount_force = property(lambda self: self._array("mounts/force"))
    modal_coordinates = property(lambda self: self._array("modal/coordinates"))

    @property
    def body_names(self) -> tuple[str, ...]:
        return tuple(str(n) for n in self.contents.get("bodies/names"))

    @property
    def mount_names(self) -> tuple[str, ...]:
        return tuple(str(n) for n in np.atleast_1d(self.contents.datasets.get("mounts/names",
                                                                               [])))

    @property
    def complete(self) -> bool:
        return bool(self.contents.attrs.get("", {}).get("complete", True))

    @property
    def message(self) -> str:
        return str(self.contents.attrs.get("", {}).get("message", ""))

    @property
    def solver(self) -> dict:
        """Method, settings and statistics (the results file's ``solver`` group)."""
        return dict(self.contents.attrs.get("solver", {}))

    def body(self, name: str) -> int:
        """Index of a body by name (InputError naming the bodies if unknown)."""
        names = self.body_names
        if name not in names:
            raise InputError(f"flexbed.Results.body: name = {name!r} is not a body of this run "
                             f"(bodies: {', '.join(names)})")
        return names.index(name)

    # points of interest
    def _run(self) -> Run:
        if self._post is None:
            self._post = Run(self.contents, modes=self._modes, modes_file=self._modes_file)
        return self._post

    def point(self, body: str, position: Sequence[float], *, relative_to: str | None = None,
              name: str = "point") -> PointMotion:
        """Motion of a point fixed in a body (on a flexible bed: moving with
        the modes; ``position[2]`` is then the offset from the mid-surface).

        Parameters
        ----------
        body : str
        position : 3 floats
            In the body's frame [m].
        relative_to : str, optional
            Give the motion relative to this body, in its frame.

        Returns
        -------
        PointMotion
            ``position``, ``velocity``, ``acceleration`` (k, 3) [m, m/s, m/s²],
            inertial or in ``relative_to``'s frame.
        """
        from flexbed.api.arguments import Arguments

        check = Arguments("Results.point")
        body = check.name(body, "body")
        xyz = check.position(position, "position")
        relative_to = None if relative_to is None else check.name(relative_to, "relative_to")
        name = check.name(name, "name")
        for key, b in (("body", body), ("relative_to", relative_to)):
            if b is not None and b not in self.body_names:
                check.bad(key, b, f"a body of this run ({', '.join(self.body_names)})")
        run = self._run()
        pt = Point(name=name, body=body, position=xyz)
        return run.relative(pt, relative_to) if relative_to else run.absolute(pt)

    def stresses(self):
        """The flexible bed's stresses over the run by modal superposition
        (:mod:`flexbed.analyses.bed_stress`): the peak von Mises stress in the
        plate and the peak absolute stress at each stiffener's extreme fibres,
        with place and time, and the map of each element's peak.

        Returns
        -------
        flexbed.analyses.bed_stress.BedStresses
        """
        from flexbed.analyses.bed_stress import in_run_coordinates, superpose

        run = self._run()
        data = run.modes_data
        if data is None:
            raise InputError("Results.stresses: the run's bed is rigid: it has no stresses")
        if data.stress is None:
            raise InputError(f"Results.stresses: {data.path}: the modes hold no stresses "
                             f"(a modes file older than schema 1.4); re-run 'flexbed modes'")
        return superpose(in_run_coordinates(data.stress, data.n_modes, run.basis), run.a, run.t)

    def points(self) -> dict[str, PointMotion]:
        """The scene's ``[[point]]`` tables: name → absolute motion, and
        ``name@body`` → the motion relative to its ``relative_to`` body."""
        run = self._run()
        out = {}
        for pt in run.scene_points:
            out[pt.name] = run.absolute(pt)
            if pt.relative_to:
                out[f"{pt.name}@{pt.relative_to}"] = run.relative(pt, pt.relative_to)
        return out

    def save(self, path: str | Path) -> Path:
        """Write the results file (as ``flexbed simulate -o``)."""
        from flexbed.api.arguments import Arguments
        path = Arguments("Results.save").path(path, "path", optional=False)
        if self._datasets is None:
            raise InputError("flexbed.Results.save: these results were read from a file: copy "
                             "the file instead")
        return write_results_contents(path, *self._datasets)


def open_results(path: str | Path, *, modes: ModesData | str | Path | None = None) -> Results:
    """A results file read back. ``modes``: a flexible bed's modes (data, or
    a modes file); default the modes file the run used, looked for beside
    the results file, then where the run recorded it (checked by the
    plate's hash)."""
    from flexbed.api.arguments import Arguments

    check = Arguments("open_results")
    path = check.path(path, "path", optional=False)
    if isinstance(modes, (str, Path)):
        return Results(read_results(path), modes_file=check.path(modes, "modes"))
    return Results(read_results(path), modes=check.modes(modes))


def srs(results: Results | str | Path, *,
        point: tuple | Point | Sequence[tuple | Point] | None = None, q: float = 10.0,
        fmin: float = 1.0, fmax: float | None = None,
        per_octave: int = 12):
    """Shock response spectra of points' absolute accelerations (as ``flexbed srs``).

    Parameters
    ----------
    results : Results or path of a results file
    point : (name, body, [x, y, z]) [m, body frame], a :class:`Point`, or a
        list of them (the form :func:`flexbed.frf` takes); default the
        scene's ``[[point]]`` tables
    q : quality factor Q = 1/(2ζ) [1]
    fmin, fmax : band [Hz] (``fmax``: default a tenth of the sampling
        rate, at most a quarter)
    per_octave : frequencies per octave

    Returns
    -------
    flexbed.analyses.shock.Spectra
        ``frequency`` (n,) [Hz]; ``points``: for each point ``positive``,
        ``negative``, ``maximax`` (n, 3) [m/s²] and ``pseudo_velocity``
        (n, 3) [m/s], columns X, Y, Z; ``input``: the same for a driven
        base's acceleration, else None.
    """
    from flexbed.analyses.frf import BAND_LIMITS
    from flexbed.analyses.shock import MAX_PER_OCTAVE, Q_MIN, spectra
    from flexbed.api.arguments import POINT_FORM, Arguments

    check = Arguments("srs")
    if not isinstance(results, (Results, str, Path)):
        check.bad("results", results, "a Results from flexbed.simulate, or a results file")
    q = check.real(q, "q", positive=True, optional=False)
    if not q > Q_MIN:
        check.bad("q", q, f"above {Q_MIN:g} (damping ratio below 1)")
    fmin = check.real(fmin, "fmin", positive=True, optional=False)
    if fmin < BAND_LIMITS[0]:
        check.bad("fmin", fmin, f"at least {BAND_LIMITS[0]:g} Hz")
    fmax = check.real(fmax, "fmax", positive=True)
    if fmax is not None and not fmax >= fmin:
        check.bad("fmax", fmax, f"at or above fmin = {fmin:g} Hz")
    per_octave = check.integer(per_octave, "per_octave", minimum=1, maximum=MAX_PER_OCTAVE)
    r = open_results(results) if isinstance(results, (str, Path)) else results
    run = r._run()
    given = check.points(point, "point") or []
    for i, (_, rel) in enumerate(given):
        if rel is not None:
            check.bad("point relative_to" if len(given) == 1 else f"point[{i}] relative_to",
                      rel, "None: a shock spectrum is of the absolute acceleration")
    points = [p for p, _ in given]
    for i, p in enumerate(points):
        if p.body not in r.body_names:
            check.bad("point body" if len(points) == 1 else f"point[{i}] body", p.body,
                      f"a body of this run ({', '.join(r.body_names)})")
    if not points:
        points = list(run.scene_points)
    if not points:
        check.fail("", f"give point = {POINT_FORM} (the scene has no [[point]] tables)")
    out = spectra(run, points, q=q, fmin=fmin, fmax=fmax, per_octave=per_octave)
    for text in out.warnings:             # as the command prints them: one line each
        warnings.warn(text, FlexbedWarning, stacklevel=2)
    return out

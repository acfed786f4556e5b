"""Post-processing of a finished run (paper, section 4): the motion of any
point of interest, absolute or relative to any body, and the mount forces,
computed from the results file alone (plus the modes file for points on a
flexible bed), without running again.

Kinematics, for a point at ū(t) in the frame of body b (rigid: ū = s̄; the
flexible bed: ū = s̄ + Φ(s̄) a(t), Φ including the normal's rotation ×
offset for points off the mid-surface):

    R = r + A ū
    Ṙ = ṙ + A (ω × ū + Φ ȧ)
    R̈ = r̈ + A (α × ū + ω × (ω × ū) + 2 ω × Φ ȧ + Φ ä)

with ω, α the body-frame angular velocity and acceleration. Relative to a
body B, in B's frame (ρ = A_Bᵀ (R − r_B)):

    ρ̇ = A_Bᵀ (Ṙ − ṙ_B) − ω_B × ρ
    ρ̈ = A_Bᵀ (R̈ − r̈_B) − α_B × ρ − 2 ω_B × ρ̇ − ω_B × (ω_B × ρ)
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from flexbed.dynamics.frames import apply, apply_t
from flexbed.dynamics.rotation import A as rotation_matrix
from flexbed.fem.quad_shapes import mode_shapes
from flexbed.fem.grid_shapes import OutsidePlateError

from flexbed.errors import InputError
from flexbed.files.modes import ModesData, read_modes_file
from flexbed.files.results import read_results
from flexbed.files.scene_text import scene_data
from flexbed.files.store import Contents


@dataclass(frozen=True)
class Point:
    """A point of interest: ``position`` [m] in the frame of ``body``."""

    name: str
    body: str
    position: np.ndarray
    relative_to: str | None = None


@dataclass(frozen=True)
class PointMotion:
    """Motion of one point over the run: (k, 3) arrays, inertial frame
    (absolute) or the reference body's frame (relative) [m, m/s, m/s²]."""

    point: Point
    frame: str                 # "inertial" or the reference body's name
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray


def parse_point(text: str) -> Point:
    """``NAME=BODY:x,y,z`` → :class:`Point` (InputError on a malformed one)."""
    try:
        name, rest = text.split("=", 1)
        body, coords = rest.rsplit(":", 1)
        xyz = np.array([float(v) for v in coords.split(",")])
    except ValueError:
        raise InputError(f"--point {text!r}: expected NAME=BODY:x,y,z (metres, body frame)") \
            from None
    if not name or not body or xyz.shape != (3,) or not np.all(np.isfinite(xyz)):
        raise InputError(f"--point {text!r}: expected NAME=BODY:x,y,z (metres, body frame)")
    return Point(name=name, body=body, position=xyz)


def modes_file_candidates(results: Path, bed: dict) -> list[Path]:
    """Where a run's modes file may be, in the order tried: beside the
    results file under its recorded name, at the recorded path relative to
    the results file, at the recorded absolute path (duplicates dropped)."""
    recorded = str(bed.get("modes_file", ""))
    relative = str(bed.get("modes_file_relative", ""))
    found = []
    if recorded:
        found.append(results.parent / Path(recorded).name)
    if relative:
        found.append(results.parent / relative)
    if recorded:
        found.append(Path(recorded))
    unique = []
    for p in found:
        if not any(p.resolve() == q.resolve() for q in unique):
            unique.append(p)
    return unique


def find_modes_file(results: Path, bed: dict, modes_file=None):
    """The modes file a flexible-bed run was made with, checked by the
    plate's input hash the results file records.

    Parameters
    ----------
    results : Path
        The results file.
    bed : dict
        Its ``bed`` attributes (``modes_file``, ``modes_file_relative``,
        ``plate_input_hash``).
    modes_file : path-like, optional
        Given by the user (``--modes-file``): the only one tried.

    Returns
    -------
    data : ModesData
    path : Path

    Raises
    ------
    InputError
        None found, or none made for this run's plate; the message names
        the places tried.
    """
    want = str(bed.get("plate_input_hash", ""))
    candidates = [Path(modes_file)] if modes_file is not None else \
        modes_file_candidates(results, bed)
    tried = []
    for path in candidates:
        if not path.is_file():
            tried.append(f"{path} (missing)")
            continue
        if modes_file is not None:
            data = read_modes_file(path)
            if data.input_hash != want:
                raise InputError(f"{results}: modes file {path} was made for another bed than "
                                 f"this run (plate input hash {data.input_hash[:12]}…, the "
                                 f"run's {want[:12]}…)")
            return data, path
        try:
            data = read_modes_file(path)
        except InputError as exc:
            tried.append(f"{path} (unreadable: {exc})")
            continue
        if data.input_hash == want:
            return data, path
        tried.append(f"{path} (made for another bed)")
    where = "; ".join(tried) or "no modes file recorded"
    raise InputError(f"{results}: the flexible bed's modes file is not found: {where}; give "
                     f"--modes-file FILE (or re-run 'flexbed modes' and the simulation)")


def numeric(c: Contents, name: str, shape: tuple) -> np.ndarray:
    """Dataset ``name`` of ``c`` as a float array of ``shape`` (None: any
    length), or InputError naming the file and the dataset."""
    a = np.asarray(c.get(name))
    if a.dtype.kind not in "biuf":
        what = "text" if a.dtype.kind in "OSU" else f"values of type {a.dtype}"
        raise InputError(f"{c.path}: dataset '{name}' holds {what}, not numbers")
    if a.ndim != len(shape) or any(s is not None and s != n for s, n in zip(shape, a.shape)):
        want = "(" + ", ".join("k" if s is None else str(s) for s in shape) + ")"
        raise InputError(f"{c.path}: dataset '{name}' has shape {a.shape}, expected {want}")
    return a.astype(float)


def _rigid_bed_centre(table: dict, path: Path, source: str = "") -> np.ndarray:
    """Centre of mass (3,) [m] of a rigid bed from the scene's [bed] table
    (zero for the plain rectangle; a relative mesh_file is looked for beside
    the scene file the run came from, ``source``, then beside the run)."""
    from flexbed.files.bed_section import read_bed
    folder = path.parent
    mesh = table.get("mesh_file")
    if source and isinstance(mesh, str) and (Path(source).parent / mesh).is_file():
        folder = Path(source).parent
    try:
        return read_bed(table, f"{path}: scene [bed]", folder).mass_properties.centre
    except InputError as exc:
        raise InputError(f"{exc}; cannot place the points on the bed") from None


class Frames:
    """The rotation matrices (k, 3, 3) of the bodies' frames over a run,
    ``frames[:, b]``, each body's computed when first indexed (the numbers
    of ``rotation.A(p)[:, b]``: the same operations on each quaternion): a
    post-processing reads one or two bodies' of many. p : (k, nb, 4)."""

    def __init__(self, p: np.ndarray):
        self.p, self._done = p, {}

    def __getitem__(self, index: tuple) -> np.ndarray:
        whole, b = index
        if whole != slice(None) or not isinstance(b, (int, np.integer)):
            raise IndexError(f"frames[{index!r}]: only frames[:, body] is kept")
        b = int(b)
        if b not in self._done:
            self._done[b] = rotation_matrix(self.p[:, b])
        return self._done[b]


class Run:
    """A run opened for post-processing: a results file, or its contents in
    memory (:class:`flexbed.files.store.Contents`), and the modes of a
    flexible bed (``modes``: given, else the modes file the run records)."""

    def __init__(self, source: str | Path | Contents, modes: ModesData | None = None,
                 modes_file: str | Path | None = None):
        c = source if isinstance(source, Contents) else read_results(source)
        self.path = c.path if c.path is not None else Path("results")
        self._modes = modes
        if not c.attrs.get("", {}).get("complete", True):
            self.incomplete = str(c.attrs[""].get("message", ""))
        else:
            self.incomplete = ""
        self.t = numeric(c, "time", (None,))
        if self.t.size == 0:
            raise InputError(f"{self.path}: dataset 'time' holds no samples")
        if not (np.all(np.isfinite(self.t)) and np.all(np.diff(self.t) >= 0)):
            raise InputError(f"{self.path}: dataset 'time' is not finite and non-decreasing")
        k = self.t.size
        self.names = [str(n) for n in np.atleast_1d(c.get("bodies/names"))]
        nb = len(self.names)
        self.r = numeric(c, "bodies/position", (k, nb, 3))
        self.p = numeric(c, "bodies/euler_parameters", (k, nb, 4))
        self.rd = numeric(c, "bodies/velocity", (k, nb, 3))
        self.rdd = numeric(c, "bodies/acceleration", (k, nb, 3))
        self.w = numeric(c, "bodies/angular_velocity", (k, nb, 3))
        self.wd = numeric(c, "bodies/angular_acceleration", (k, nb, 3))
        self.A = Frames(self.p)                                  # [:, b] (k, 3, 3), on first use
        self.mount_names = [str(n) for n in np.atleast_1d(c.datasets.get("mounts/names", []))]
        self.mount_body_i, self.mount_body_j = (
            [str(n) for n in np.atleast_1d(c.datasets.get(f"mounts/{key}", []))]
            for key in ("body_i", "body_j"))
        nm = len(self.mount_names)
        self.mounts = {key: numeric(c, f"mounts/{key}", (k, nm, 3))
                       for key in ("deflection", "rate", "force", "force_i", "force_j")
                       if f"mounts/{key}" in c.datasets}
        text = str(c.datasets.get("scene/toml", ""))
        try:
            scene = scene_data(text)
        except tomllib.TOMLDecodeError:
            raise InputError(f"{self.path}: dataset 'scene/toml' is not valid TOML") from None
        self.scene_points = tuple(self._scene_points(scene))
        #: the scene as parsed TOML, and the scene file it was read from
        self.scene_data = scene
        self.scene_source = str(c.attrs.get("scene", {}).get("source", ""))
        #: the base's motion: "fixed", "driven" or "free"
        self.base_motion = str(scene.get("base", {}).get("motion", "fixed"))
        bed = c.attrs.get("bed", {})
        self.bed_model = str(bed.get("model", "rigid"))
        self.bed_name = None
        self.shapes = None
        self.translation = None
        self.modes_path = None
        self.modes_data, self.basis = None, None      # a flexible bed's (bed stresses)
        # points on the bed are given in its drawing frame; the bed body's
        # frame has its origin at the bed's centre of mass, bed_centre
        self.bed_body = None
        self.bed_centre = np.zeros(3)
        if isinstance(scene.get("bed"), dict) and len(self.names) > 1:
            self.bed_body = scene["bed"].get("body") or self.names[1]
        if self.bed_model == "flexible":
            self._open_modes(c, bed, modes_file)
        elif self.bed_body is not None:
            self.bed_centre = _rigid_bed_centre(
                scene["bed"], self.path, str(c.attrs.get("scene", {}).get("source", "")))

    def _scene_points(self, data: dict):
        for i, p in enumerate(data.get("point", [])):
            try:
                pos = np.array(p["position"], dtype=float)
                yield Point(name=str(p["name"]), body=str(p["body"]), position=pos,
                            relative_to=p.get("relative_to"))
            except (KeyError, TypeError, ValueError):
                raise InputError(f"{self.path}: scene point {i + 1} is malformed") from None

    def _open_modes(self, c, bed: dict, modes_file) -> None:
        if self._modes is not None:
            data, path = self._modes, self._modes.path
            if data.input_hash != str(bed.get("plate_input_hash", "")):
                raise InputError(f"{self.path}: the modes given were made for another bed than "
                                 f"this run (plate input hash {data.input_hash[:12]}…)")
        else:
            data, path = find_modes_file(self.path, bed, modes_file)
        self.modes_path = path
        n = int(bed.get("n_modes", 0))
        basis = c.datasets.get("modal/basis")
        basis = np.eye(n) if basis is None else np.asarray(basis, dtype=float)
        if basis.shape[0] > data.n_modes or basis.shape[1] != n:
            raise InputError(f"{self.path}: the run's {n} modal coordinates draw on "
                             f"{basis.shape[0]} modes, {path} holds {data.n_modes}; re-run "
                             f"'flexbed modes'")
        self.modes_data, self.basis = data, basis
        a = np.asarray(c.get("modal/coordinates"), dtype=float)
        self.a = a[:, :n]
        self.ad = np.asarray(c.get("modal/rates"), dtype=float)[:, :n]
        add = c.datasets.get("modal/accelerations")
        if add is None:
            raise InputError(f"{self.path}: dataset 'modal/accelerations' is missing")
        self.add = np.asarray(add, dtype=float)[:, :n]
        toml = scene_data(str(c.datasets.get("scene/toml", "")))
        self.bed_name = toml.get("bed", {}).get("body") or self.names[1]
        self.bed_centre = np.asarray(data.origin, dtype=float)
        self.translation, rotation, twist = run_shapes(data, basis)
        self.shapes = mode_shapes(data.plate.theory, data.nodes, data.cells, self.translation,
                                  rotation, twist)

    def body_index(self, name: str, what: str = "body") -> int:
        if name not in self.names:
            raise InputError(f"{self.path}: {what} {name!r} is not a body of this run "
                             f"(bodies: {', '.join(self.names)})")
        return self.names.index(name)

    def absolute(self, point: Point) -> PointMotion:
        """Inertial position, velocity and acceleration of a point."""
        b, u, phi = self._offset(point)
        k = self.t.size
        ud = np.zeros((k, 3))
        udd = np.zeros((k, 3))
        if phi is not None:
            ud = self.ad @ phi.T
            udd = self.add @ phi.T
        A = self.A[:, b]
        w, wd = self.w[:, b], self.wd[:, b]
        R = self.r[:, b] + apply(A, u)            # the order of flexbed.dynamics.frames
        V = self.rd[:, b] + np.einsum("kij,kj->ki", A, np.cross(w, u) + ud)
        acc_body = np.cross(wd, u) + np.cross(w, np.cross(w, u)) + 2.0 * np.cross(w, ud) + udd
        Acc = self.rdd[:, b] + np.einsum("kij,kj->ki", A, acc_body)
        return PointMotion(point, "inertial", R, V, Acc)

    def position(self, point: Point, relative_to: str | None = None) -> np.ndarray:
        """(k, 3) [m]: ``absolute(point).position``, or with ``relative_to``
        ``relative(point, relative_to).position``, the same numbers,
        without the velocities and accelerations."""
        b, u, _ = self._offset(point)
        R = self.r[:, b] + apply(self.A[:, b], u)
        if relative_to is None:
            return R
        B = self.body_index(relative_to, "--relative-to body")
        return apply_t(self.A[:, B], R - self.r[:, B])

    def _offset(self, point: Point) -> tuple:
        """(body index, u (k, 3) [m] the point in its body's frame at each
        sample, the bed's mode shapes there (3, n) or None)."""
        b = self.body_index(point.body, f"point '{point.name}': body")
        s = np.asarray(point.position, dtype=float)
        if self.names[b] == self.bed_body:
            s = s - self.bed_centre                    # drawing frame -> bed frame
        u = np.broadcast_to(s, (self.t.size, 3)).copy()
        phi = None
        if self.shapes is not None and self.names[b] == self.bed_name:
            try:
                trans, _ = self.shapes.at(s[None, :])
            except OutsidePlateError as exc:
                raise InputError(f"point '{point.name}': {exc}") from None
            phi = trans[:, 0, :].T                                       # (3, n)
            u += self.a @ phi.T
        return b, u, phi

    def relative(self, point: Point, body: str) -> PointMotion:
        """Motion of a point relative to ``body``, in that body's frame."""
        m = self.absolute(point)
        B = self.body_index(body, "--relative-to body")
        AB = self.A[:, B]
        wB, wdB = self.w[:, B], self.wd[:, B]
        rho = apply_t(AB, m.position - self.r[:, B])
        rhod = np.einsum("kji,kj->ki", AB, m.velocity - self.rd[:, B]) - np.cross(wB, rho)
        rhodd = (np.einsum("kji,kj->ki", AB, m.acceleration - self.rdd[:, B])
                 - np.cross(wdB, rho) - 2.0 * np.cross(wB, rhod) - np.cross(wB, np.cross(wB, rho)))
        return PointMotion(point, body, rho, rhod, rhodd)


def motion_table(motions: list[PointMotion]) -> str:
    """Peaks of each point's motion: displacement from t = 0, speed, acceleration."""
    head = ("| point | body | frame | peak displacement x, y, z [mm] | peak |v| [m/s] "
            "| peak |a| [m/s²] |").replace("|v|", "speed").replace("|a|", "acceleration")
    lines = [head, "|---|---|---|---|---|---|"]
    for m in motions:
        d = m.position - m.position[0]
        peak = np.abs(d).max(axis=0) * 1e3
        lines.append(f"| {m.point.name} | {m.point.body} | {m.frame} | "
                     f"{peak[0]:.4f}, {peak[1]:.4f}, {peak[2]:.4f} | "
                     f"{np.linalg.norm(m.velocity, axis=1).max():.5g} | "
                     f"{np.linalg.norm(m.acceleration, axis=1).max():.5g} |")
    return "\n".join(lines)


def motion_csv(t: np.ndarray, m: PointMotion) -> str:
    """Time series of one point as CSV (SI units)."""
    cols = ["t_s"] + [f"{q}_{c}_{u}" for q, u in (("position", "m"), ("velocity", "m/s"),
                                                  ("acceleration", "m/s2"))
                      for c in "xyz"]
    data = np.column_stack([t, m.position, m.velocity, m.acceleration])
    lines = [",".join(cols)] + [",".join(f"{v:.12g}" for v in row) for row in data]
    return "\n".join(lines) + "\n"


def mount_table(run: Run) -> str:
    """Peak deflection and force per mount and direction."""
    if "deflection" not in run.mounts:
        return "(no mounts)"
    dx = np.abs(run.mounts["deflection"]).max(axis=0) * 1e3
    f = np.abs(run.mounts["force"]).max(axis=0)
    lines = ["| mount | peak Δx1, Δx2, Δx3 [mm] | peak f1, f2, f3 [N] |", "|---|---|---|"]
    for i, name in enumerate(run.mount_names):
        lines.append(f"| {name} | {dx[i, 0]:.4f}, {dx[i, 1]:.4f}, {dx[i, 2]:.4f} | "
                     f"{f[i, 0]:.6g}, {f[i, 1]:.6g}, {f[i, 2]:.6g} |")
    return "\n".join(lines)


def mount_peaks_csv(run: Run) -> str:
    """Peak |deflection| and |force| per mount and direction as CSV (m, N)."""
    dx = np.abs(run.mounts["deflection"]).max(axis=0)
    f = np.abs(run.mounts["force"]).max(axis=0)
    lines = ["mount,peak_dx1_m,peak_dx2_m,peak_dx3_m,peak_f1_N,peak_f2_N,peak_f3_N"]
    for i, name in enumerate(run.mount_names):
        lines.append(",".join([name] + [f"{v:.10g}" for v in (*dx[i], *f[i])]))
    return "\n".join(lines) + "\n"


def mount_csv(run: Run) -> str:
    """Mount deflections and forces over time as CSV (SI units)."""
    cols = ["t_s"]
    blocks = [run.t[:, None]]
    for i, name in enumerate(run.mount_names):
        for key, unit in (("deflection", "m"), ("force", "N")):
            cols += [f"{name}_{key}{k + 1}_{unit}" for k in range(3)]
            blocks.append(run.mounts[key][:, i, :])
    data = np.hstack(blocks)
    return "\n".join([",".join(cols)] + [",".join(f"{v:.12g}" for v in row)
                                         for row in data]) + "\n"


def run_shapes(data, basis: np.ndarray) -> tuple:
    """The modes file's nodal shapes (translation (N, nodes, 3), rotation,
    twist) in a run's modal coordinates, a_file = basis @ a (basis (N', n),
    N' ≤ the file's modes): (n, nodes, 3) each."""
    N = basis.shape[0]
    return tuple(np.einsum("kn,k...->n...", basis, arr[:N])
                 for arr in (data.translation, data.rotation, data.twist))


def bed_motion(run: Run, nodes: np.ndarray, translation: np.ndarray):
    """Positions of the bed's nodes over the run.

    Parameters
    ----------
    nodes : ndarray (N, 3)
        Nodes in the bed frame [m].
    translation : ndarray (n, N, 3)
        Translations at the nodes per modal coordinate of the run
        (``Run.translation``; n ≥ the run's coordinates; unused for a rigid
        bed).

    Returns
    -------
    position : ndarray (k, N, 3)
        Inertial positions [m].
    deflection : ndarray (k, N)
        Elastic deflection along the bed's normal [m].
    """
    b = run.names.index(run.bed_name) if run.bed_name else 1
    u = np.broadcast_to(nodes, (run.t.size,) + nodes.shape).copy()
    deflection = np.zeros((run.t.size, nodes.shape[0]))
    if run.shapes is not None:
        n = run.a.shape[1]
        d = np.einsum("kn,nNj->kNj", run.a, translation[:n])
        u += d
        deflection = d[..., 2]
    position = run.r[:, b, None, :] + np.einsum("kij,kNj->kNi", run.A[:, b], u)
    return position, deflection

"""Stiffeners: straight beams along lines of the plate's mesh, joined to
it with their eccentricity. Each beam element is an edge of a cell between
two consecutive mesh nodes on the line (:func:`line_nodes` refuses a line
that crosses cells).

A stiffener's section is a flat bar, a T, an I or a general one (A, Iy, Iz,
J); its centroid sits at ``offset`` from the mid-surface (negative:
below). Its centroid moves with the shell node it is joined to by the
shell's kinematics at that height, U = (u + e θy, v − e θx, w), and turns
with the node (θx, θy, and the in-plane rotation ½(∂v/∂x − ∂u/∂y) of the
elements around it). Along the beam (axis s, in-plane normal n):

* axial EA and torsion GJ, linear;
* bending in the vertical plane EIy, by ``model``:

  - ``"hinged"`` (the default for flat, T and I sections): the section
    has a rotation ψ of its own, one extra DOF at each node of its line
    (after the shell's 5 N, :class:`flexbed.fem.shell.ShellModel`), and is
    hinged to the plate's face: the web's fibre at height a above the
    face z_f = e − c (c the centroid's height above the face, signed with
    e) moves along s by u_s − z_f φ − a ψ, continuous with the plate's
    face, while its section turns on its own. Per unit length
    ½ EA (u_c')² + ½ EIy (ψ')² + ½ G A_s (w' − ψ)², u_c = u_s − z_f φ − c ψ:
    the web shears by its own strain w' − ψ, not by the plate's w' − φ. w
    and ψ linear with the shear tied at the mid-point (as ``"timoshenko"``).
    Its mass: the centroid's axial displacement u_c and the section's
    rotary inertia about n with ψ; in a rigid motion ψ = φ;
  - ``"timoshenko"``: the section turns with the plate's
    normal, φ = −θ·n (the plate's Mindlin rotation; the web a fibre of it
    continued below the plate), w and φ linear, bending ½ EIy ∫ (φ')² ds
    and the web's own transverse shear ½ G A_s ∫ (w' − φ)² ds, A_s the
    section's ``shear_area`` (5/6 of the web's rectangle for flat, T and
    I), tied at the element's mid-point as the MITC4 plate ties its own
    (:func:`flexbed.fem.beam_elements.timoshenko`). The section's shear
    is thus the plate's plus the web's, held to one strain: the stiffened
    bed's bending modes come out up to 0.55 % stiff against a 3D solid
    (docs/stiffeners.md);
  - ``"euler-bernoulli"`` (the model before issue 26): cubic Hermite in w
    with slope φ, which ties the plate's shear strain along the line to
    zero: the reference stiffened bed's bending modes come out 0.1–2.6 %
    stiff against a 3D solid, more on finer meshes (docs/stiffeners.md);

* bending in the plane EIz, cubic Hermite in the mid-surface line's u·n
  with slope θz (the centroid's offset part, e (θ × z)·n, is linear along
  each element and bends nothing);
* mass ρA on the centroid's translation and the section's rotary inertia
  ρ(Iy + Iz), ρIy, ρIz about s, n, z, both interpolated linearly and
  integrated with two Gauss points — which makes them exactly the mass of
  a row of rigid slices, so every modal invariant of the stiffener follows
  from :func:`flexbed.fem.fixed_masses.moments` at those points.

Pure NumPy/SciPy.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from .beam_elements import hermite, timoshenko
from .cells import edges
from .geometry import GeometryError

SECTIONS = ("flat", "T", "I", "general")
#: the beam models of the vertical bending (:func:`stiffener_matrices`)
MODELS = ("hinged", "timoshenko", "euler-bernoulli")
#: shear coefficient of a web's rectangle (its shear area κ h t)
WEB_SHEAR = 5 / 6


def _positive(entry: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not (
            math.isfinite(value) and value > 0):
        raise GeometryError(entry, f"{entry} = {value!r} must be a number > 0")
    return float(value)


@dataclass(frozen=True, slots=True)
class Section:
    """Section properties [m², m⁴], the centroid's height above the
    section's base c [m] (for flat/T/I; 0 for general) and the shear area
    of its vertical shear κ A_web [m²] (flat, T, I: 5/6 of the web's
    rectangle; general: as given, 0 when not)."""

    area: float
    Iy: float
    Iz: float
    J: float
    centroid: float
    shear_area: float = 0.0


def section_of(kind: str, *, height=None, width=None, web=None, flange_width=None,
               flange=None, area=None, Iy=None, Iz=None, J=None, shear_area=None) -> Section:
    """Properties of a flat bar (height × width), a T (web height × web
    thickness, flange width × flange thickness at the free end), a doubly
    symmetric I (overall height, web, flange width, flange thickness) or a
    general section (A, Iy, Iz, J). Iy is about the horizontal axis through
    the centroid (vertical bending), Iz about the vertical axis; J by the
    thin-walled open-section formula Σ b t³ / 3 for flat, T and I."""
    if shear_area is not None and kind != "general":
        raise GeometryError("shear_area", f"shear_area = {shear_area!r} applies to section = "
                                          f"'general' only (a {kind} section's is its web's)")
    if kind == "flat":
        h, b = _positive("height", height), _positive("width", width)
        return Section(h * b, b * h ** 3 / 12, h * b ** 3 / 12, _thin(h, b), h / 2,
                       WEB_SHEAR * h * b)
    if kind == "T":
        h, tw = _positive("height", height), _positive("web", web)
        bf, tf = _positive("flange_width", flange_width), _positive("flange", flange)
        Aw, Af = h * tw, bf * tf
        c = (Aw * h / 2 + Af * (h + tf / 2)) / (Aw + Af)
        Iy = (tw * h ** 3 / 12 + Aw * (h / 2 - c) ** 2
              + bf * tf ** 3 / 12 + Af * (h + tf / 2 - c) ** 2)
        Iz = h * tw ** 3 / 12 + tf * bf ** 3 / 12
        return Section(Aw + Af, Iy, Iz, _thin(h, tw) + _thin(bf, tf), c, WEB_SHEAR * Aw)
    if kind == "I":
        h, tw = _positive("height", height), _positive("web", web)
        bf, tf = _positive("flange_width", flange_width), _positive("flange", flange)
        hw = h - 2 * tf
        if hw <= 0:
            raise GeometryError("height", f"height = {h!r} must exceed twice flange = {tf!r}")
        A = hw * tw + 2 * bf * tf
        Iy = tw * hw ** 3 / 12 + 2 * (bf * tf ** 3 / 12 + bf * tf * (h / 2 - tf / 2) ** 2)
        Iz = hw * tw ** 3 / 12 + 2 * tf * bf ** 3 / 12
        return Section(A, Iy, Iz, _thin(hw, tw) + 2 * _thin(bf, tf), h / 2,
                       WEB_SHEAR * hw * tw)
    if kind == "general":
        return Section(_positive("area", area), _positive("Iy", Iy), _positive("Iz", Iz),
                       _positive("J", J), 0.0,
                       0.0 if shear_area is None else _positive("shear_area", shear_area))
    raise GeometryError("section", f"section = {kind!r} must be one of "
                                   + ", ".join(f'"{s}"' for s in SECTIONS))


def _thin(b: float, t: float) -> float:
    """Saint-Venant torsion constant of a thin rectangle, b t³/3 (b ≥ t)."""
    b, t = max(b, t), min(b, t)
    return b * t ** 3 / 3 * (1 - 0.63 * t / b)


@dataclass(frozen=True, slots=True)
class Stiffener:
    """A stiffener on the line start → end (drawing frame) [m].

    ``offset`` is the centroid's height above the mid-surface [m]
    (negative below the plate); ``model`` the vertical bending's beam,
    ``"hinged"`` (its own section rotation, hinged at the plate's face),
    ``"timoshenko"`` (the section turns with the plate's normal) or
    ``"euler-bernoulli"`` (module docstring). None (the default) chooses
    ``"hinged"`` for a flat, T or I section, ``"timoshenko"`` for a general
    one with ``shear_area``, else ``"euler-bernoulli"``.
    """

    name: str
    start: tuple[float, float]
    end: tuple[float, float]
    section: Section
    offset: float
    model: str | None = None

    def __post_init__(self) -> None:
        for key in ("start", "end"):
            p = np.array(getattr(self, key), dtype=float)
            if p.shape != (2,) or not np.all(np.isfinite(p)):
                raise GeometryError(key, f"{key} = {getattr(self, key)!r} must be [x, y] [m]")
            object.__setattr__(self, key, (float(p[0]), float(p[1])))
        if np.hypot(self.end[0] - self.start[0], self.end[1] - self.start[1]) <= 0:
            raise GeometryError("end", f"end = {self.end!r} equals start")
        if not math.isfinite(self.offset):
            raise GeometryError("offset", f"offset = {self.offset!r} must be finite [m]")
        object.__setattr__(self, "offset", float(self.offset))
        if self.model is None:
            sec = self.section
            object.__setattr__(self, "model", "hinged" if sec.centroid > 0 else
                               "timoshenko" if sec.shear_area > 0 else "euler-bernoulli")
        if self.model not in MODELS:
            raise GeometryError("model", f"model = {self.model!r} must be one of "
                                         + ", ".join(f'"{m}"' for m in MODELS))
        if self.model == "hinged" and not self.section.centroid > 0:
            raise GeometryError("model", "model = 'hinged' needs the section's depth (a flat, "
                                         "T or I section; for section = 'general' use "
                                         "'timoshenko' or 'euler-bernoulli')")
        if self.model != "euler-bernoulli" and not self.section.shear_area > 0:
            raise GeometryError("shear_area", f"model = {self.model!r} needs the section's "
                                              "shear_area > 0 [m²] (give shear_area for "
                                              "section = 'general', or model = "
                                              "'euler-bernoulli')")

    @property
    def length(self) -> float:
        return float(np.hypot(self.end[0] - self.start[0], self.end[1] - self.start[1]))

    def rotary(self, density: float) -> np.ndarray:
        """Rotary inertia per unit length about the centroid, bed axes (3, 3) [kg m]."""
        s, n = self.axes()
        sec = self.section
        local = np.diag([density * (sec.Iy + sec.Iz), density * sec.Iy, density * sec.Iz])
        Q = np.column_stack([s, n, [0.0, 0.0, 1.0]])
        return Q @ local @ Q.T

    def axes(self) -> tuple[np.ndarray, np.ndarray]:
        """Unit axis s and in-plane normal n = z × s, (3,) each."""
        d = np.array([self.end[0] - self.start[0], self.end[1] - self.start[1], 0.0])
        s = d / np.linalg.norm(d)
        return s, np.array([-s[1], s[0], 0.0])


def line_mass_properties(st: Stiffener, density: float, centre: np.ndarray
                         ) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass [kg], first moment (3,) [kg m] and inertia about the origin
    (3, 3) [kg m²] of a stiffener, drawing frame shifted by ``centre``."""
    m = density * st.section.area * st.length
    a = np.array([st.start[0], st.start[1], st.offset]) - centre
    b = np.array([st.end[0], st.end[1], st.offset]) - centre
    mid = 0.5 * (a + b)
    d = b - a
    second = m * (np.outer(mid, mid) + np.outer(d, d) / 12.0)       # ∫ρA r rᵀ ds
    J = np.trace(second) * np.eye(3) - second + st.rotary(density) * st.length
    return m, m * mid, J


def _xy(p: np.ndarray) -> str:
    return f"[{p[0]:.6g}, {p[1]:.6g}]"


def line_nodes(st: Stiffener, nodes: np.ndarray, cells: np.ndarray, centre: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """The mesh nodes a stiffener joins, in order from its start to its end.

    The beam's elements are the pieces between consecutive nodes on its
    line, so the nodes must reach from end to end and each piece must be an
    edge of a cell (four per quadrilateral, three per triangle): a piece
    across a cell would tie two of its corners through the plate.

    Parameters
    ----------
    st : Stiffener
    nodes : ndarray (N, 2)
        Shell nodes in the bed frame [m].
    cells : ndarray (ne, 4)
        Quadrilaterals, and triangles as (a, b, c, c).
    centre : ndarray (2,)
        The bed frame's origin in the drawing frame [m].

    Returns
    -------
    order : ndarray (k,) of int
        The nodes on the line, start to end (k >= 2).
    along : ndarray (N,)
        Every node's distance along the line from its start [m].

    Raises
    ------
    GeometryError
        The nodes on the line do not reach its ends, or two consecutive
        ones are not joined by a cell edge (one line naming them).
    """
    a = np.array(st.start) - centre
    s3, n3 = st.axes()
    s, L = s3[:2], st.length
    rel = nodes - a
    along = rel @ s
    across = rel @ n3[:2]
    scale = max(L, float(np.max(np.ptp(nodes, axis=0))))
    on = np.flatnonzero((np.abs(across) <= 1e-9 * scale) & (along >= -1e-9 * scale)
                        & (along <= L + 1e-9 * scale))
    order = on[np.argsort(along[on])]
    covered = along[order[-1]] - along[order[0]] if order.size > 1 else 0.0
    where = f"stiffener {st.name!r} from {list(st.start)} to {list(st.end)} m"
    if order.size < 2 or abs(along[order[0]]) > 1e-9 * scale or abs(covered - L) > 1e-9 * scale:
        raise GeometryError("stiffener", f"{where} does not run along lines of the "
                                         f"mesh (set element_size so the mesher puts lines "
                                         f"through its ends, or move it onto grid lines)")
    pieces = np.sort(np.column_stack([order[:-1], order[1:]]), axis=1)
    known = edges(cells)
    n = nodes.shape[0]
    joined = np.isin(pieces[:, 0] * n + pieces[:, 1], known[:, 0] * n + known[:, 1])
    if not joined.all():
        k = int(np.flatnonzero(~joined)[0])
        p, q = nodes[order[k]] + centre, nodes[order[k + 1]] + centre
        raise GeometryError("stiffener", f"{where} crosses cells: its mesh nodes at {_xy(p)} "
                                         f"and {_xy(q)} m, next to each other on its line, "
                                         f"are not joined by a cell edge (give the mesh "
                                         f"cell edges along the stiffener's line)")
    return order, along


def stiffener_matrices(st: Stiffener, nodes: np.ndarray, cells: np.ndarray, drilling,
                       centre: np.ndarray, young: float, poisson: float, density: float,
                       first: int = 0):
    """Stiffness and mass of one stiffener on the shell's DOFs.

    Parameters
    ----------
    st : Stiffener
    nodes : ndarray (N, 2)
        Shell nodes in the bed frame [m].
    cells : ndarray (ne, 4)
        The shell's cells (triangles as (a, b, c, c)).
    drilling : sparse (N, 5N)
        The shell's nodal in-plane rotation operator.
    centre : ndarray (2,)
        The bed frame's origin in the drawing frame [m].
    young, poisson, density : float
    first : int
        A hinged stiffener's first own DOF (its section rotation at the
        line's nodes are DOFs first, first + 1, … in order along it).

    Returns
    -------
    K, M : list of (dofs (k,), block (k, k))
    slices : list of (FixedMass, where (3,), dofs, T (3, k), R (3, k))
        The rigid slices at the Gauss points (mass and invariants).
    own : (nodes (m,), rigid (m, 5N) sparse) or None
        A hinged stiffener's: the node of each own DOF and its value in a
        rigid motion of the shell's DOFs (ψ = −θ·n); None for the others.

    Raises
    ------
    GeometryError
        The line does not run along edges of the mesh (:func:`line_nodes`).
    """
    from .fixed_masses import FixedMass
    order, along = line_nodes(st, nodes, cells, centre)
    s3, n3 = st.axes()
    sec, e = st.section, st.offset
    G = young / (2 * (1 + poisson))
    D = drilling.tocsr()
    K, M, slices = [], [], []
    rot = st.rotary(density)
    g = 1 / math.sqrt(3)
    above = math.copysign(sec.centroid, e)      # the centroid above the face [m]
    hinged = st.model == "hinged"
    if st.model in ("timoshenko", "hinged"):
        def vertical(EI, L):
            return timoshenko(EI, G * sec.shear_area, L)
    else:
        vertical = hermite
    for k, (ia, ib) in enumerate(zip(order[:-1], order[1:])):
        Le = along[ib] - along[ia]
        cols = set(range(5 * ia, 5 * ia + 5)) | set(range(5 * ib, 5 * ib + 5))
        if hinged:
            cols |= {first + k, first + k + 1}
        for i in (ia, ib):
            cols |= set(D.indices[D.indptr[i]:D.indptr[i + 1]].tolist())
        dofs = np.array(sorted(cols))
        pos = {d: j for j, d in enumerate(dofs)}

        def ops(i, own, dofs=dofs, pos=pos):
            T = np.zeros((3, dofs.size))
            R = np.zeros((3, dofs.size))
            u, v, w, tx, ty = (pos[5 * i + c] for c in range(5))
            T[0, u], T[0, ty] = 1.0, e
            T[1, v], T[1, tx] = 1.0, -e
            T[2, w] = 1.0
            R[0, tx] = R[1, ty] = 1.0
            row = slice(D.indptr[i], D.indptr[i + 1])
            for c, val in zip(D.indices[row], D.data[row]):
                R[2, pos[c]] += val
            if not hinged:
                return T, R
            psi = np.zeros(dofs.size)
            psi[pos[own]] = 1.0
            phi = -(n3 @ R)
            return T + above * np.outer(s3, phi - psi), R - np.outer(n3, psi - phi)

        (Ta, Ra), (Tb, Rb) = ops(ia, first + k), ops(ib, first + k + 1)
        us = np.array([s3 @ Ta, s3 @ Tb])
        ts = np.array([s3 @ Ra, s3 @ Rb])
        vert = np.array([Ta[2], -(n3 @ Ra), Tb[2], -(n3 @ Rb)])
        # in-plane bending of the line it is joined along: its centroid's
        # u_c·n = u·n + e (θ × z)·n adds a part linear along the element (θ
        # is), which bends nothing, yet the drilling slope θz does not carry
        # its slope: a plate's twist would bend the beam sideways, more the
        # finer the mesh. So the Hermite beam takes the mid-surface line.
        tilt = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
        plane = np.array([n3 @ (Ta - e * tilt @ Ra), Ra[2], n3 @ (Tb - e * tilt @ Rb), Rb[2]])
        bar = np.array([[1.0, -1.0], [-1.0, 1.0]]) / Le
        Ke = (young * sec.area * us.T @ bar @ us + G * sec.J * ts.T @ bar @ ts
              + vert.T @ vertical(young * sec.Iy, Le) @ vert
              + plane.T @ hermite(young * sec.Iz, Le) @ plane)
        K.append((dofs, Ke))
        Me = np.zeros((dofs.size, dofs.size))
        for xi in (-g, g):
            Na, Nb = 0.5 * (1 - xi), 0.5 * (1 + xi)
            T, R = Na * Ta + Nb * Tb, Na * Ra + Nb * Rb
            p = Na * nodes[ia] + Nb * nodes[ib]
            item = FixedMass(f"{st.name}:{k}:{xi:+.3f}", (p[0], p[1], e),
                             density * sec.area * Le / 2, rot * Le / 2)
            Me += item.mass * T.T @ T + R.T @ np.array(item.inertia) @ R
            slices.append((item, np.array([p[0], p[1], e]), dofs, T, R))
        M.append((dofs, Me))
    if not hinged:
        return K, M, slices, None
    k = order.size
    n5 = drilling.shape[1]
    rigid = sp.csr_matrix((np.tile(-n3[:2], k), (np.repeat(np.arange(k), 2),
                                                  (5 * order[:, None] + [3, 4]).ravel())),
                          shape=(k, n5))
    return K, M, slices, (order, rigid)

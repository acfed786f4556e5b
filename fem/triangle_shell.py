"""The triangles' share of the shell's matrices: element and edge blocks
ready to assemble (:func:`flexbed.fem.shell.assemble_mesh`).

The three-node flat shell is MITC3 transverse shear on each triangle
(:mod:`flexbed.fem.mitc3`) with its membrane strain and bending curvature
smoothed over edge domains (:mod:`flexbed.fem.edge_smoothing`): "ES-MITC3".
Mass is the triangle's consistent mass with rotary inertia.

A mesh holds triangles as four-corner cells whose last two corners are the
same node (a, b, c, c), so every array of cells stays (ne, 4)
(:mod:`flexbed.fem.cells`).
"""

from __future__ import annotations

import numpy as np

from .edge_smoothing import smoothed_operators
from .mitc3 import drilling_operator, gradients, mass_blocks, shear_stiffness, strain_operators

def _material(poisson: float) -> np.ndarray:
    nu = poisson
    return np.array([[1.0, nu, 0.0], [nu, 1.0, 0.0], [0.0, 0.0, 0.5 * (1.0 - nu)]])


def triangle_blocks(nodes: np.ndarray, tris: np.ndarray, thickness: np.ndarray, young: float,
                    poisson: float, density: float, smoothed: bool = True) -> dict:
    """Blocks of the triangles' stiffness parts and masses.

    Parameters
    ----------
    nodes : ndarray (N, 2) [m]
    tris : ndarray (nt, 3)
        Counter-clockwise triangles.
    thickness : ndarray (nt,) [m]
    young, poisson, density : float
        E [Pa], ν [-], ρ [kg/m³].
    smoothed : bool
        Edge-smoothed membrane and bending (the element); False gives the
        plain constant-strain / constant-curvature triangle (kept to show
        how stiff it is).

    Returns
    -------
    dict
        ``membrane``, ``shear``, ``bend_xx``, ``bend_yy``, ``bend_rest``:
        (blocks (k, n, n), node stencils (k, n / 5)) each, n = 15 or 20
        [N/m per unit DOF²]; ``mass0``, ``mass2``: (nt, 3, 3) scalar
        blocks on ``tris`` [kg], [kg m²]; ``drilling``: (nt, 6) operator
        on the corners' (u, v) [1/m].
    """
    t = np.asarray(thickness, float)
    xy = nodes[tris]
    area, dNx = gradients(xy)
    Bm, Bb = strain_operators(dNx)
    nu = poisson
    Dm = young * t / (1.0 - nu * nu)
    Db = young * t ** 3 / (12.0 * (1.0 - nu * nu))
    if smoothed:
        where, (Bm, Bb), (fm, fb) = smoothed_operators(tris, area, [Bm, Bb], [Dm, Db])
    else:
        where, fm, fb = tris, area * Dm, area * Db
    C = _material(poisson)
    Bt = np.transpose(Bb, (0, 2, 1))
    full = fb[:, None, None] * (Bt @ (C @ Bb))
    kxx = fb[:, None, None] * (Bt[:, :, 0:1] @ Bb[:, 0:1, :])
    kyy = fb[:, None, None] * (Bt[:, :, 1:2] @ Bb[:, 1:2, :])
    membrane = fm[:, None, None] * (np.transpose(Bm, (0, 2, 1)) @ (C @ Bm))
    m0, m2 = mass_blocks(area, t, density)
    return {"membrane": (membrane, where), "bend_xx": (kxx, where), "bend_yy": (kyy, where),
            "bend_rest": (full - kxx - kyy, where),
            "shear": (shear_stiffness(xy, area, t, young, poisson), tris),
            "mass0": m0, "mass2": m2, "drilling": drilling_operator(dNx)}

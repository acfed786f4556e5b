"""A Kirchhoff bed's theory error: its frequencies against the
shear-deformable (Reissner–Mindlin) shell's, both converged.

The thin-plate theory leaves out transverse shear and the free edges'
boundary layer of twisting moment: on the reference bed (t / b = 1 / 8)
its torsion modes are 4.2 % high against the shell and a 3D solid, its
bending modes within 0.05 %; a thicker plate moves every mode.
:func:`theory_error` measures it for the modes of a Kirchhoff bed with one
shell comparison: the shell on the auto meshes at H and H / 2
(:func:`flexbed.fem.auto_mesh.mesh_spec`, H = the shorter side / 4) is
extrapolated (Richardson, h²); the Kirchhoff frequencies are extrapolated
with their own estimate (:mod:`flexbed.fem.accuracy`); modes are matched
by the MAC of the deflection on a lattice of points. Its own error is
that of the shell's extrapolation (about 0.1 % on the reference bed's first
ten modes).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from .accuracy import EXTRA_MODES, MIN_MAC, RATES, element_size, match, richardson
from .auto_mesh import mesh_spec, start_size


def theory_error(bed, kirchhoff_error: np.ndarray | None = None) -> np.ndarray:
    """f_Kirchhoff / f_shell − 1 (n,) of a Kirchhoff bed's modes, both
    converged (NaN where no shell mode matches with a MAC of :data:`MIN_MAC`).

    Parameters
    ----------
    bed : BedModes
        A Kirchhoff bed's modes.
    kirchhoff_error : ndarray (n,), optional
        Their estimated discretisation error (removed first; NaN: kept).
    """
    from .bed import compute_bed_modes
    n = bed.modes.omega.size
    shell = replace(bed.spec, theory="mindlin", mesh_tolerance=0.005)
    H = start_size(shell)
    fine = compute_bed_modes(mesh_spec(shell, H / 2), n_modes=n + EXTRA_MODES)
    coarse = compute_bed_modes(mesh_spec(shell, H), n_modes=n + 2 * EXTRA_MODES)
    index, value = match(fine, coarse)
    ratio = element_size(coarse.nodes, coarse.cells) / element_size(fine.nodes, fine.cells)
    f_fine = fine.modes.frequency
    f_shell = f_fine / (1.0 + richardson(f_fine, coarse.modes.frequency[index], ratio,
                                         RATES["mindlin"]))
    f_shell = np.where(value >= MIN_MAC, f_shell, f_fine)
    f_k = bed.modes.frequency
    if kirchhoff_error is not None:
        f_k = np.where(np.isfinite(kirchhoff_error), f_k / (1.0 + kirchhoff_error), f_k)
    index, value = match(bed, fine)
    return np.where(value >= MIN_MAC, f_k / f_shell[index] - 1.0, np.nan)

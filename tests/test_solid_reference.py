"""A stiffened bed and a bed with a cut-out against a 3D solid (issue 14).

The reference frequencies are the converged scikit-fem hexahedral solid of
docs/solid-reference.md (ElementHex2, Richardson-extrapolated in the plane
and through the thickness; `python docs/solid_reference.py` reproduces
them). The tests build coarse solids themselves: their error against the
reference falls as the mesh is refined (so the reference is not just typed
in), and their mode shapes pick the shell's modes by MAC (not by index:
in the stiffened bed the second bending and the first torsion mode lie
within 1 % of each other and swap order between meshes).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pytest
import scipy.sparse as sp
from skfem import Basis, BilinearForm, ElementHex2, ElementVector, MeshHex, asm
from skfem.helpers import dot
from skfem.models.elasticity import lame_parameters, linear_elasticity

from flexbed.fem.bed import compute_bed_modes
from flexbed.fem.solid import assemble, solid_modes
from flexbed.fem.solid_check import (match, sample_points, shell_shapes, shell_spec, solid_bed,
                                     solid_shapes)

E, NU, RHO = 2.1e11, 0.3, 7800.0
#: first six elastic modes of the converged solids (docs/solid-reference.md)
REFERENCE = {
    "stiffened": (28.683, 78.590, 78.969, 152.650, 160.713, 169.389),
    "cutout": (22.457, 62.421, 76.038, 123.358, 153.305, 161.227),
}
LABELS = {
    "stiffened": ("bending", "bending", "torsion", "bending", "torsion", "in-plane"),
    "cutout": ("bending", "bending", "torsion", "bending", "torsion", "in-plane"),
}


@lru_cache(maxsize=None)
def _solid(case: str, level: int, nz: int):
    return solid_modes(solid_bed(case), level, nz, n_modes=8)


def test_solid_assembly_is_scikit_fem_linear_elasticity():
    """The solid's stiffness and mass equal scikit-fem's vector forms on a
    mesh of unequal boxes; rigid motions strain nothing; the mass is ρV."""
    mesh = MeshHex.init_tensor(np.array([0.0, 0.3, 0.45]), np.array([0.0, 0.2, 0.7]),
                               np.array([-0.05, 0.0, 0.02]))
    K, M, _ = assemble(mesh, E, NU, RHO)
    vb = Basis(mesh, ElementVector(ElementHex2()), intorder=4)
    Kf = asm(linear_elasticity(*lame_parameters(E, NU)), vb)

    @BilinearForm
    def mass(u, v, w):
        return RHO * dot(u, v)

    Mf = asm(mass, vb)
    assert sp.linalg.norm(K - Kf) < 1e-12 * sp.linalg.norm(Kf)
    assert sp.linalg.norm(M - Mf) < 1e-12 * sp.linalg.norm(Mf)
    x = vb.doflocs[:, ::3].T
    rigid = np.zeros((K.shape[0], 6))
    for c in range(3):
        rigid[c::3, c] = 1.0
    for c, (a, b) in enumerate(((1, 2), (2, 0), (0, 1))):     # rotation about axis c
        rigid[a::3, 3 + c] = -x[:, b]
        rigid[b::3, 3 + c] = x[:, a]
    assert np.abs(K @ rigid).max() < 1e-6 * abs(K).max()
    assert rigid[:, 0] @ M @ rigid[:, 0] == pytest.approx(RHO * 0.45 * 0.7 * 0.07, rel=1e-13)


@pytest.mark.slow
@pytest.mark.parametrize("case, coarse, finer", [("cutout", (0, 1), (1, 1)),
                                                 ("stiffened", (0, 1), (0, 2))])
def test_coarse_solid_converges_to_the_reference(case, coarse, finer):
    """Two coarse solids built here, modes matched by shape: each of the
    first six modes' error against the documented reference falls from the
    coarser to the finer mesh (cut-out: the cells halved in the plane;
    stiffened: a second element through the thickness, which is what the
    torsion modes need), and the finer is within its documented distance."""
    ref = np.array(REFERENCE[case])
    pts = sample_points(case)
    a, b = _solid(case, *coarse), _solid(case, *finer)
    j, q = match(solid_shapes(a, pts)[:6], solid_shapes(b, pts))
    assert np.all(q > 0.99) and np.array_equal(j, np.arange(6))
    err_a = np.abs(a.frequency[:6] / ref - 1)
    err_b = np.abs(b.frequency[:6] / ref - 1)
    assert np.all(err_b < err_a)
    assert np.all(err_b < 0.01)


@pytest.mark.slow
@pytest.mark.parametrize("case", ["stiffened", "cutout"])
def test_mindlin_bed_against_the_3d_solid(case):
    """flexbed's Mindlin bed (element_size 0.05 m; the stiffened one with
    two flat-bar stiffeners, eccentric beams) against the converged solid:
    the first six elastic modes (three vertical bending, two torsion, the
    in-plane bending), each matched to the solid's by MAC ≥ 0.99 of the
    mid-surface translations.

    Tolerances (docs/solid-reference.md; the reference's own bound is
    ≤ 0.12 %): cut-out ≤ 0.3 % for bending and in-plane, ≤ 0.8 % for the
    torsion modes, the shell's own error at 5 cm elements near the hole's
    re-entrant corners (+0.74 %; +0.25 % at 2.5 cm). Stiffened, with the
    default hinged stiffener (the web's own section rotation, docs/
    stiffeners.md): every mode ≤ 0.3 % (+0.03, +0.10, +0.07, +0.22, +0.06,
    +0.09 %). The Timoshenko and Euler–Bernoulli stiffeners, whose web is
    tied to the plate's normal, came out 0.5–1 % high on the second and
    third bending modes; tests/test_stiffener_model.py holds the models
    apart.
    """
    ref = np.array(REFERENCE[case])
    pts = sample_points(case)
    coarse = _solid(case, 0, 1)
    bed = compute_bed_modes(shell_spec(case, 0.05), n_modes=10)
    j, q = match(solid_shapes(coarse, pts)[:6], shell_shapes(bed, pts))
    assert np.all(q > 0.99) and len(set(j.tolist())) == 6
    err = bed.modes.frequency[j] / ref - 1
    tol = np.full(6, 0.003)
    if case == "cutout":
        tol[[2, 4]] = 0.008
    assert np.all(np.abs(err) < tol), err
    # the stiffeners matter: the first bending mode rises by a fifth
    if case == "stiffened":
        assert ref[0] > 1.2 * 23.144


def test_solid_bed_refuses_a_hole_off_the_plate_or_across_a_web():
    from flexbed.fem.solid import SolidBed, Web
    with pytest.raises(ValueError, match="must not cross the web at x = 0.2 m"):
        SolidBed(hole=(0.1, 0.3, 0.0, 1.0), webs=(Web(0.2, 0.02, 0.1),))
    with pytest.raises(ValueError, match="must lie on the plate"):
        SolidBed(hole=(0.3, 0.5, 0.0, 1.0))

"""The shell's stresses against the 3D solid (issue 26 part 3): a bed
0.8 × 1.2 × 0.1 m (the reference plate's width and thickness) clamped
along one short edge, loaded by 100 kN on a 0.2 × 0.2 m mount pad; the
top face's in-plane stresses at element centres (MITC4 on 0.1 m
elements; triquadratic hexahedra, two through the thickness, on the same
grid)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse.linalg as sla

from flexbed.fem.shell import assemble_shell
from flexbed.fem.solid import SolidBed, assemble, solid_mesh
from flexbed.fem.solid_stress import pad_load, top_face_stresses
from flexbed.fem.spec import PlateSpec
from flexbed.fem.stresses import shell_stress_operators

LX, LY, T = 0.8, 1.2, 0.1
PAD = (0.1, 0.3, 0.2, 0.4)                 # x0, x1, y0, y1 [m]
FORCE = 1e5                                # N
H = 0.1                                    # element side [m]


def _solve(K, f, fixed):
    u = np.zeros(f.size)
    free = ~fixed
    u[free] = sla.spsolve(K[free][:, free].tocsc(), f[free])
    return u


def _solid():
    bed = SolidBed(length_x=LX, length_y=LY, thickness=T, h0=2 * H)
    mesh = solid_mesh(bed, level=1, nz=2)
    K, _, basis = assemble(mesh, bed.young, bed.poisson, bed.density)
    f = pad_load(mesh, K.shape[0], PAD, FORCE, T / 2)
    assert f.sum() == pytest.approx(-FORCE, rel=1e-12)
    fixed = np.repeat(np.abs(basis.doflocs[1] + LY / 2) < 1e-9, 3)
    where, sigma = top_face_stresses(mesh, _solve(K, f, fixed), bed.young, bed.poisson)
    top = np.abs(where[:, 2] - T / 2) < 1e-9
    return where[top, :2], sigma[top][:, [0, 1, 0], [0, 1, 1]]        # (σxx, σyy, τxy)


def _shell(points):
    m = assemble_shell(PlateSpec(length_x=LX, length_y=LY, thickness=T, nx=round(LX / H),
                                 ny=round(LY / H), theory="mindlin"))
    d = m.node_dofs
    fixed = np.zeros(m.K.shape[0], bool)
    fixed[d[:, np.isclose(m.nodes[:, 1], -LY / 2)].ravel()] = True
    centre = m.nodes[m.cells].mean(axis=1)
    pad = ((centre[:, 0] > PAD[0]) & (centre[:, 0] < PAD[1]) & (centre[:, 1] > PAD[2])
           & (centre[:, 1] < PAD[3]))
    f = np.zeros(m.K.shape[0])
    p = FORCE / ((PAD[1] - PAD[0]) * (PAD[3] - PAD[2]))
    np.add.at(f, d[2, m.cells[pad]].ravel(), -p * H * H / 4)          # bilinear: a quarter each
    ops = shell_stress_operators(m)
    sm, sb = ops.of(_solve(m.K, f, fixed)[:, None])
    key = {tuple(k): i for i, k in enumerate(np.round(ops.centres * 1e6).astype(np.int64))}
    rows = [key[tuple(k)] for k in np.round(points * 1e6).astype(np.int64)]
    return (sm + sb)[0, rows]


def test_shell_stresses_at_a_mount_pad_against_the_solid():
    """Away from the clamped edge (its 3D corner effects, y > −0.4 m): every
    component within 3.5 % of the largest stress, the peaks of σyy and σxx
    within 1 % and 3 % (measured 2.7 %, 0.6 %, 2.2 %; on 0.05 m elements
    1.9 %, 0.8 %, 0.2 %)."""
    points, solid = _solid()
    shell = _shell(points)
    away = points[:, 1] > -LY / 2 + 2 * T
    scale = np.abs(solid[away]).max()
    assert np.max(np.abs(shell - solid)[away]) <= 0.035 * scale
    for c, tol in ((1, 0.01), (0, 0.03)):
        peak_solid, peak_shell = np.abs(solid[away, c]).max(), np.abs(shell[away, c]).max()
        assert abs(peak_shell / peak_solid - 1) <= tol, (c, peak_shell, peak_solid)
    # the largest stress sits at the pad's edge nearest the clamp, in both
    i, j = np.argmax(np.abs(solid[away, 1])), np.argmax(np.abs(shell[away, 1]))
    np.testing.assert_allclose(points[away][i], points[away][j])

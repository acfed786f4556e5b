"""The worked example of docs/bed-stresses.md: stresses in the reference
bed as a Mindlin shell (0.05 m elements).

1. A static load at a mount: the stress at the mount by modal
   superposition with n modes, with and without the static correction at
   the mount points, against the direct static solve.
2. The reference scene's transient (the lee1999 base pulse) with the bed
   flexible: the peak von Mises stress with 5, 10 and 20 modes, with and
   without the static correction, against 40 modes; its place and time;
   the peak map as docs/bed-stresses-peak.png.

Run: ``python docs/bed_stresses.py`` (about 30 s of CPU).
"""

import tomllib
from pathlib import Path

import numpy as np
import scipy.linalg as la
import scipy.sparse as sp
import scipy.sparse.linalg as sla

import flexbed
from flexbed.fem.modal_stress import modal_stress
from flexbed.fem.modes import free_free_modes
from flexbed.fem.shell import assemble_shell
from flexbed.fem.spec import PlateSpec
from flexbed.fem.stresses import von_mises
from flexbed.files.scene import parse_scene
from flexbed.stages.residual_modes import residual_basis

HERE = Path(__file__).resolve().parent

# ---------------------------------------------------------------- 1. static
# the reference bed (0.8 x 4.8 x 0.1 m) on 0.1 m elements, on four stiff
# supports near its ends, 10 kN down at a mount point at (0.3, 0.5) m
model = assemble_shell(PlateSpec(theory="mindlin", nx=8, ny=48))
x, y = model.nodes.T
d = model.node_dofs


def node(px, py):
    return int(np.argmin((x - px) ** 2 + (y - py) ** 2))


supports = [node(sx, sy) for sx in (-0.3, 0.3) for sy in (-1.9, 1.9)]
load = node(0.3, 0.5)
springs = np.zeros(model.K.shape[0])
springs[d[:3, supports].ravel()] = 1e8                                  # N/m
K = (model.K + sp.diags(springs)).tocsr()
f = np.zeros(model.K.shape[0])
f[d[2, load]] = -1e4                                                    # N
exact_u = sla.spsolve(K.tocsc(), f)
N = 120
modes = free_free_modes(model, n_modes=N)
Phi = modes.vectors
stress = modal_stress(model, Phi)
exact = von_mises(modal_stress(model, exact_u[:, None]).faces(np.ones(1))).max(axis=-1)
near = np.hypot(*(stress.centres - model.nodes[load]).T) < 0.15          # at the mount
rows = np.concatenate([d[c][supports + [load]] for c in range(3)])
R = model.rigid_vectors()

print(f"static: 10 kN at the mount (0.3, 0.5) m, direct solve: peak von Mises "
      f"{exact.max() / 1e6:.3f} MPa at the mount")
print("modes kept | coordinates | error at the mount: plain | with the correction "
      f"(from {N} modes)")
for n in (5, 10, 20, 40, 80):
    errors = []
    for corrected in (False, True):
        if corrected:
            T, _ = residual_basis(np.eye(N), np.diag(modes.omega ** 2), Phi[rows].T, n)
        else:
            T = np.eye(N)[:, :n]
        V = np.column_stack([R, Phi @ T])
        q = la.solve(V.T @ (K @ V), V.T @ f, assume_a="pos")[6:]
        got = von_mises(stress.transformed(T).faces(q)).max(axis=-1)
        errors.append(np.max(np.abs(got - exact)[near]) / exact[near].max())
    print(f"{n:10d} | {n:4d} / {n + T.shape[1] - n:<4d} | {100 * errors[0]:6.2f} % "
          f"| {100 * errors[1]:6.2f} %")

# ------------------------------------------------------------- 2. transient
base = flexbed.load_scene()
text = base.text.replace('model = "rigid"', 'model = "flexible"\ntheory = "mindlin"', 1)
text = text.replace("nx = 10\nny = 10\n", "element_size = 0.05\n", 1)


def scene(n, corrected):
    extra = f"modes = {n}\n" + ("static_correction = true\ncorrection_modes = 40\n"
                                if corrected else "")
    return parse_scene(text.replace("modes = 2\n", extra, 1), base.source)


def peak(n, corrected):
    sf = scene(n, corrected)
    return flexbed.simulate(sf, t_end=1.0).stresses()


ref = peak(40, False)
print(f"\ntransient, 0-1 s, 40 modes: peak von Mises {ref.bed.value / 1e6:.3f} MPa at "
      f"(x, y) = ({ref.bed.x:.3f}, {ref.bed.y:.3f}) m (bed frame), {ref.bed.where} face, "
      f"t = {ref.bed.time:.3f} s; at t = 0 (the sag) {ref.initial_peak.value / 1e6:.3f} MPa")
print("modes kept | peak [MPa] plain (error) | with the correction from 40 modes (error)")
for n in (5, 10, 20):
    plain, corr = peak(n, False).bed.value, peak(n, True).bed.value
    print(f"{n:10d} | {plain / 1e6:.3f} ({100 * (plain / ref.bed.value - 1):+.2f} %) "
          f"| {corr / 1e6:.3f} ({100 * (corr / ref.bed.value - 1):+.2f} %)")

from flexbed.plots.stress import plot_peak_map  # noqa: E402  (matplotlib)

data = flexbed.modes(scene(40, False))
mounts = np.array([m[f"point_{k}"] for m in tomllib.loads(base.text)["mount"] for k in "ij"
                   if m[f"body_{k}"] == "bed"])                        # drawing frame
plot_peak_map(HERE / "bed-stresses-peak.png",
              "reference scene, Mindlin bed (0.05 m), 40 modes: peak von Mises over 0-1 s",
              data.nodes, data.cells, ref.peak_map, (ref.bed.x, ref.bed.y), data.origin,
              mounts=mounts)
print("wrote docs/bed-stresses-peak.png")

"""Figures of docs/validation.md that flexbed computes against exact or
independent references, printed as Markdown rows (about 20 s of CPU)::

    OPENBLAS_NUM_THREADS=1 python docs/validation.py

1. the static equilibrium of the reference scene against its closed form
   (linear mounts: each deflection is the weight carried over the stiffness)
   and the paper's Table 2;
2. the Mindlin bed as a user gets it with ``theory = "mindlin"`` and nothing
   else, against the project's converged 3D solid (docs/solid-reference.json,
   27-node hexahedra, level 1 with 4 elements through the thickness), modes
   matched in order of frequency;
3. the energy balance of the reference scene with an undamped flexible bed
   (kinetic + gravity + strain energy − the work of mounts and loads, the
   results file's ``energy/balance``): its drift against the largest kinetic
   energy over the run.
"""

from __future__ import annotations

import json
import re
from pathlib import Path

import numpy as np

import flexbed

HERE = Path(__file__).resolve().parent


def statics_rows() -> list[str]:
    scene = flexbed.load_scene()
    eq = flexbed.statics(scene)
    g = 9.81
    z2 = 5.1 - (2995.2 + 200.0) * g / (4 * 5e5)
    z3 = z2 + 0.25 - 100.0 * g / (4 * 1e5)
    err = max(abs(eq.position[1, 2] - z2), abs(eq.position[2, 2] - z3),
              abs(eq.position[3, 2] - z3))
    return [f"| static equilibrium of the reference scene | closed form m g / k; the paper's "
            f"Table 2 (5.084, 5.332 m) | z = {eq.position[1, 2]:.9f}, {eq.position[2, 2]:.9f} m; "
            f"largest difference from the closed form {err:.1e} m |"]


def mindlin_rows() -> list[str]:
    text = flexbed.load_scene().text
    text = text.replace('model = "rigid"', 'model = "flexible"\ntheory = "mindlin"')
    text = re.sub(r"(?m)^n[xy] = \d+\n", "", text)
    text = re.sub(r"(?m)^modes = \d+\n", "modes = 8\n", text)
    path = Path("validation-mindlin.toml")
    path.write_text(text)
    try:
        data = flexbed.modes(flexbed.load_scene(path))
    finally:
        path.unlink()
    solid = np.array(json.loads((HERE / "solid-reference.json").read_text())
                     ["plain"]["solid"]["1,4"]["f"])
    f = np.asarray(data.frequency)[:len(solid)]
    rel = (f - solid[:len(f)]) / solid[:len(f)]
    return [f"| the reference bed, `theory = \"mindlin\"` and nothing else (`element_size = "
            f"\"auto\"`) | the project's 3D solid, 44,523 DOF | first {len(f)} modes within "
            f"{100 * np.abs(rel).max():.2f} % ({', '.join(f'{100 * r:+.2f}' for r in rel)} %) |"]


def energy_rows() -> list[str]:
    scene = flexbed.vary(flexbed.load_scene(), {"bed.model": "flexible",
                                                "bed.rayleigh": [0.0, 0.0]})
    run = flexbed.simulate(scene, integrator="dop853", rtol=1e-10, atol=1e-12, t_end=3.0)
    b = np.asarray(run["energy/balance"])
    kinetic = np.asarray(run["energy/kinetic"]).sum(axis=tuple(range(1, np.ndim(
        run["energy/kinetic"]))))
    drift = np.abs(b - b[0]).max() / kinetic.max()
    return [f"| energy balance, reference scene, undamped flexible bed, 0–3 s (dop853, rtol "
            f"1e-10) | conservation: kinetic + gravity + strain − work = constant | drift "
            f"{drift:.1e} of the largest kinetic energy |"]


if __name__ == "__main__":
    print("| check | reference | figure |")
    print("|---|---|---|")
    for rows in (statics_rows, mindlin_rows, energy_rows):
        for row in rows():
            print(row)

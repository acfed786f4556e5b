"""flexbed from Python: two mount designs on the reference scene, rigid and
flexible bed, compared by the peak motion of equipment A's top relative to
the bed and by the peak mount force. Run: ``python docs/api_example.py``
(about 10 s; the tests run it too)."""

import numpy as np

import flexbed

scene = flexbed.load_scene()                      # the built-in reference scene
eq = flexbed.statics(scene)
print("static z of the bed and the equipment [m]:", np.round(eq.position[1:, 2], 6))

# A softer design: every vertical stiffness (the mounts' third axis) halved.
soft = flexbed.vary(scene, {f"mount.{m.name}.k": [m.laws[0].k, m.laws[1].k, 0.5 * m.laws[2].k]
                            for m in scene.scene.mounts})

for label, design in (("reference", scene), ("soft mounts", soft)):
    for bed in ("rigid", "flexible"):
        variant = flexbed.vary(design, {"bed.model": bed})
        run = flexbed.simulate(variant, t_end=1.5)    # from the static equilibrium
        top = run.point("equipment A", [0.0, 0.0, 0.15], relative_to="bed")
        dz = top.position[:, 2] - top.position[0, 2]
        force = np.abs(run.mount_force[:, :, 2]).max()
        print(f"{label:12s} {bed:8s} bed: peak |dz| of A's top relative to the bed "
              f"{1e3 * np.abs(dz).max():7.4f} mm, peak vertical mount force {force:9.1f} N "
              f"({run.solver['method']}, {run.solver['steps']} steps)")

"""The worked example of docs/response-spectrum.md: the reference scene
(Lee, Kim & Jeong 1999) against a tripartite design spectrum in z
(docs/response-spectrum-deck.toml), by both routes, with the bed rigid and
flexible:

1. the response-spectrum analysis (NRL, SRSS, CQC, ABS);
2. a base motion synthesised to the spectrum (±1.5 dB, 3–300 Hz), its SRS
   plotted against the target (docs/response-spectrum-motion.png);
3. transient runs on that motion;
4. the two routes side by side, per quantity.

Run: ``python docs/response_spectrum.py [FOLDER]`` (about 8 s of CPU once
compiled; the plot goes to FOLDER, default docs/)."""

import sys
import tempfile
from pathlib import Path

import flexbed
from flexbed.analyses.response_spectrum import default_points, rsa_text
from flexbed.analyses.spectrum_routes import route_rows, routes_text

HERE = Path(__file__).parent
SPECTRUM = HERE / "response-spectrum-deck.toml"
RULE = "nrl"

# The reference scene's mounts carry little damping (M1-M8 none); the spectrum is
# for 5 %, and the response-spectrum method gives every mode the spectrum's
# damping. For a like-for-like comparison the mounts get dampers that give the
# mounted modes about 5 %: c = 2000 N s/m on M1-M4, 160 N s/m on M5-M12.
reference = flexbed.load_scene()
dampers = {f"mount.M{i}.c": [2000.0] * 3 for i in range(1, 5)}
dampers |= {f"mount.M{i}.c": [160.0] * 3 for i in range(5, 13)}
rigid = flexbed.vary(reference, dampers)
flexible = flexbed.vary(rigid, {"bed.model": "flexible"})

# 1. Response-spectrum analysis, rigid and flexible bed (as `flexbed rsa --spectrum FILE`).
modal = {"rigid": flexbed.modal(rigid), "flexible": flexbed.modal(flexible)}
scenes = {"rigid": rigid, "flexible": flexible}
rsa = {case: flexbed.response_spectrum(scenes[case], SPECTRUM, equilibrium=modal[case])
       for case in scenes}
for case, r in rsa.items():
    z = r.axes[2]
    zeta = modal[case].damping_ratio
    print(f"{case} bed: {r.frequency.size} modes, {100 * z.mass_included:.1f} % of the moving "
          f"mass, RSA {1e3 * r.solve_time:.1f} ms CPU; the scene's modal damping "
          f"{zeta.min():.3f}-{zeta.max():.3f}")
shown = ("M1 d3", "M5 d3", "M9 d3", "M1 f3", "A top az", "A top uz", "bed centre az",
         "base FZ")
for case, r in rsa.items():
    print(f"\n{case} bed, all four combinations:")
    print(rsa_text(r.result, lambda name: name in shown))

# 2. A base motion matched to the spectrum (as `flexbed synthesise FILE --axis z --band 3 300`).
motion = flexbed.synthesise(SPECTRUM, axis="z", band=(3.0, 300.0), seed=0)
s = motion.synthesis
print(f"\nsynthesised: worst {abs(s.error_db).max():.2f} dB over {s.frequency.size} frequencies, "
      f"{s.time.size} samples, end velocity {s.end_velocity:.1e} m/s, end displacement "
      f"{s.end_displacement:.1e} m")
tmp = Path(tempfile.mkdtemp())
motion.save(tmp / "deck-z", plot=False)
from flexbed.dynamics.pulses import STANDARD_GRAVITY                        # noqa: E402
from flexbed.plots.spectrum import plot_synthesis                          # noqa: E402
OUT = Path(sys.argv[1]) if len(sys.argv) > 1 else HERE
plot_synthesis(OUT / "response-spectrum-motion.png", "deck z (3-300 Hz)", s, STANDARD_GRAVITY)

# 3. Transient runs on the motion, base driven in z, and 0.3 s of free response after it.
t_end = float(s.time[-1]) + 0.3
rows = []
for case, scene in scenes.items():
    driven = flexbed.vary(scene, {"base": {"motion": "driven", "drive": [motion.drive("z")]},
                                  "solver.t_end": t_end})
    run = flexbed.simulate(driven)
    assert run.complete, run.message
    points = default_points(scene, modal[case].mounted)
    rows += route_rows(case, rsa[case].axes[2], RULE, run, points, "base")

# 4. Both routes side by side.
print()
print(routes_text(rows, RULE))

"""Worked example (docs/machinery-loads.md): a pump and a generator running
on the flexible reference bed; the force transmitted to the base with the
bed rigid and flexible, narrow-band and in third octaves (dB re 1 N), and
the insertion loss of the flexible bed against the rigid one.

Run:  python docs/machinery_loads.py [OUTPUT_FOLDER]
Writes docs/machinery-loads.png (and the scene and CSV tables into
OUTPUT_FOLDER, default a temporary folder).
"""

from __future__ import annotations

import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import flexbed
from flexbed.analyses.transmitted import db
from flexbed.files.builtin import builtin_scene_text
from flexbed.plots.transmitted import plot_transmitted

HERE = Path(__file__).resolve().parent

#: the machinery: unbalances by ISO 21940-11 balance grades, and the
#: generator's twice-line-frequency pull (an order 2 of its speed)
MACHINERY = """
[[unbalance]]            # pump, 30 kg impeller, grade G6.3 at 24.5 Hz: e = 41 µm
name = "pump"
body = "equipment A"
point = [0.0, 0.0, 0.05]
axis = "y"
mass_radius = 1.23e-3    # kg m: 30 N at 24.5 Hz
speed = 24.5

[[unbalance]]            # generator, 50 kg rotor, grade G2.5 at 29.6 Hz: e = 13 µm
name = "generator"
body = "equipment B"
point = [0.0, 0.0, 0.05]
axis = "y"
mass_radius = 6.7e-4     # kg m: 23 N at 29.6 Hz
speed = 29.6

[[load]]                 # the generator's magnetic pull at twice its speed, vertical
name = "generator 2x"
body = "equipment B"
frame = "body"
direction = "z"
shape = "harmonic"
speed = 29.6
order = 2
amplitude = 10.0
"""

T_END, START, FMAX = 8.0, 4.0, 200.0        # s, s (transient gone), Hz


def scene_text() -> str:
    """The reference scene with its base held (no shock), the bed flexible
    with 2 % modal damping, the bed's mounts damped (c = 2000 N s/m: about
    5 % in bounce, so the start-up transient dies out), run for 8 s, plus
    the machinery."""
    text = builtin_scene_text()
    head, rest = text.split("[base]", 1)
    rest = rest.split("sample = 1.0e-3", 1)[1]
    text = head + '[base]\nmotion = "fixed"\n' + rest
    for old, new in (('model = "rigid"', 'model = "flexible"'),
                     ("rayleigh = [0.0, 0.01]", "damping_ratio = [0.02]"),
                     ("c = [0.0, 0.0, 0.0]", "c = [2000.0, 2000.0, 2000.0]"),
                     ("t_end = 3.0", f"t_end = {T_END}")):
        assert old in text, old
        text = text.replace(old, new)
    return text + MACHINERY


def main(out: Path, png: Path = HERE / "machinery-loads.png") -> dict:
    """Run the example into the folder ``out``, the figure to ``png``;
    returns the two designs' :class:`flexbed.api.transmission.Transmitted`."""
    out.mkdir(parents=True, exist_ok=True)
    path = out / "machinery.toml"
    path.write_text(scene_text())
    cpu = time.process_time()
    comparison = flexbed.compare(flexbed.load_scene(path))
    runs = {"rigid bed": comparison.runs["rigid"],
            "flexible bed, 2 % damping": comparison.runs["damped"]}
    forces = {label: flexbed.transmitted(run, start=START, fmax=FMAX)
              for label, run in runs.items()}
    rigid, flexible = forces.values()
    il = flexible.insertion_loss(rigid)
    print(f"force into the base, z, from {START:g} s to {T_END:g} s "
          f"(Hann, Δf = {rigid.spectrum.resolution:.4g} Hz)")
    print("  band [Hz]   rigid [dB re 1 N]   flexible [dB re 1 N]   insertion loss [dB]")
    for b, nominal in enumerate(rigid.bands.nominal):
        if nominal >= 16.0:
            print(f"  {nominal:8g}   {rigid.band_levels[b, 2]:17.2f}   "
                  f"{flexible.band_levels[b, 2]:20.2f}   {il[b, 2]:19.2f}")
    for label, tr in forces.items():
        sp = tr.spectrum
        lines = [int(np.argmin(np.abs(sp.frequency - f))) for f in (24.5, 29.6, 59.2)]
        print(f"  {label}: lines nearest 24.5, 29.6, 59.2 Hz: "
              + ", ".join(f"{sp.rms[j, 2]:.3g} N ({float(db(sp.rms[j, 2])):.1f} dB)"
                          for j in lines))
        np.savetxt(out / f"{label.split()[0]}-bands.csv",
                   np.column_stack([tr.bands.nominal, tr.band_levels]), delimiter=",",
                   header="nominal_Hz,Fx_dB_re_1N,Fy_dB_re_1N,Fz_dB_re_1N", comments="")
    png = plot_transmitted(png,
                           "pump (24.5 Hz) and generator (29.6 Hz) on the reference bed: "
                           "force into the base, z",
                           {label: (tr.spectrum, tr.bands) for label, tr in forces.items()},
                           axis=2, fmax=FMAX)
    print(f"wrote {png}; CPU {time.process_time() - cpu:.1f} s")
    return forces


if __name__ == "__main__":
    folder = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(tempfile.mkdtemp())
    main(folder)

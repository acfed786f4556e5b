"""The worked example of docs/random-vibration.md: the reference scene with
its bed flexible (6 modes) under a MIL-STD-810-style random base
acceleration given as a g²/Hz table on all three axes: RMS and 3σ mount
deflections and equipment accelerations, Miles' equation beside them, and
the PSD plots. Run: ``python docs/random_vibration.py [FOLDER]`` (about 9 s
of CPU, most of it loading and compiling; the files go into FOLDER, default
the current folder; ``FOLDER = docs`` redraws the page's plots)."""

import sys
from dataclasses import replace
from pathlib import Path

import flexbed

out = Path(sys.argv[1] if len(sys.argv) > 1 else ".")
out.mkdir(parents=True, exist_ok=True)
G = 9.80665

# 1. The flexible reference bed, 6 modes kept.
scene = flexbed.load_scene()
scene = replace(scene, bed=replace(scene.bed, model="flexible", modes=6))

# 2. The profile, as a specification writes it: breakpoints [Hz, g²/Hz], log-log between.
#    Vertical: a plateau of 0.01 g²/Hz from 10 to 40 Hz, +6.9 dB/octave below, -5.3 above;
#    the horizontal axes at half the vertical level.
vertical = [[5, 0.002], [10, 0.01], [40, 0.01], [100, 0.002], [500, 0.0002]]
horizontal = [[f, w / 2] for f, w in vertical]
profile = {"z": vertical, "x": horizontal, "y": horizontal}

# 3. The random response (as `flexbed random SCENE --psd profile.toml`).
r = flexbed.random_vibration(scene, psd=profile)
print(f"input: {', '.join(f'{a} {g:.3f} g RMS' for a, g in zip('XYZ', r.input_rms))}; "
      f"{r.frequency.size} frequencies, {r.resonances.size} modes in 5-500 Hz; "
      f"solve {r.solve_time:.3f} s CPU")

print("\nequipment accelerations       RMS [g]   3 sigma [g]   Miles [g]  (mode)")
for name in ("A top", "B top"):
    for axis in "xyz":
        j = r.column(f"{name} a{axis}")
        miles = (f"{r.miles.rms[j] / G:9.3f}  ({r.miles.frequency[j]:.2f} Hz)"
                 if r.miles.rms[j] == r.miles.rms[j] else "        -")
        print(f"  {name} a{axis:<20} {r.rms[j] / G:8.3f} {r.three_sigma[j] / G:12.3f}   "
              f"{miles}")

print("\nmount deflections (largest axis)  RMS [mm]  3 sigma [mm]  integration error")
for m in scene.scene.mounts:
    cols = [r.column(f"{m.name} d{k}") for k in (1, 2, 3)]
    j = max(cols, key=lambda c: r.rms[c])
    print(f"  {r.names[j]:<30} {1e3 * r.rms[j]:8.3f} {1e3 * r.three_sigma[j]:12.3f}   "
          f"{r.rms_error[j] / r.rms[j]:.1e}")

# 4. Files and plots: HDF5, CSV tables, and the PSDs with the input (log-log).
r.save(out / "random-lee1999")
from flexbed.plots.random import plot_psd  # noqa: E402  (only the example draws)

acc = [r.column(f"A top a{a}") for a in "xyz"] + [r.column(f"B top a{a}") for a in "xyz"]
plot_psd(out / "random-lee1999-acceleration.png",
         "flexible reference bed (6 modes): equipment acceleration PSDs",
         r.frequency, r.psd[:, acc] / G**2, [r.names[j] for j in acc], "g", r.rms[acc] / G,
         r.input_psd, ["X", "Y", "Z"], r.resonances)
defl = sorted((r.column(f"{m.name} d{k}") for m in scene.scene.mounts for k in (1, 2, 3)),
              key=lambda j: -r.rms[j])[:6]
plot_psd(out / "random-lee1999-deflection.png",
         "flexible reference bed (6 modes): the six largest mount deflection PSDs",
         r.frequency, r.psd[:, defl] * 1e6, [r.names[j] for j in defl], "mm",
         r.rms[defl] * 1e3, resonances=r.resonances)
print(f"wrote random-lee1999.h5, -rms.csv, -psd.csv, -acceleration.png and -deflection.png "
      f"into {out}")

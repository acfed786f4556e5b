"""The example of docs/elastomer-mounts.md: the reference scene (rigid
bed) with elastomer mounts, a frequency table under the bed and a constant
loss factor under the equipment; its modes and vertical transmissibility
against the undamped steel-spring original, and the generalised Maxwell fit
a time run would need, against the table. Run: ``python
docs/elastomer_mounts.py`` from the repository's root (a few seconds)."""

import tempfile
import warnings
from pathlib import Path

import matplotlib
import numpy as np

import flexbed
from flexbed.dynamics.frequency.maxwell import fit_maxwell
from flexbed.files.scene import builtin_scene_text

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

here = Path(__file__).parent
TABLE = ("elastomer = {frequency = [1.0, 10.0, 100.0], "
         "stiffness = [[5.0e5, 5.0e5, 5.0e5], [6.0e5, 6.0e5, 6.0e5], [7.5e5, 7.5e5, 7.5e5]], "
         "loss_factor = [[0.08, 0.08, 0.08], [0.12, 0.12, 0.12], [0.18, 0.18, 0.18]]}")
LOSS = "loss_factor = [0.1, 0.1, 0.1]"

# 1. The reference scene as TOML (`flexbed scene -o ref.toml`), elastomer keys added:
#    the bed's mounts (k = 5e5 N/m) get the table, the equipment's (1e5 N/m) η = 0.1.
text = builtin_scene_text()
spring = "c = [0.0, 0.0, 0.0]\n"
rubber = text.replace("k = [5.0e5, 5.0e5, 5.0e5]\n" + spring,
                      "k = [5.0e5, 5.0e5, 5.0e5]\n" + spring + TABLE + "\n")
rubber = rubber.replace("k = [1.0e5, 1.0e5, 1.0e5]\n" + spring,
                        "k = [1.0e5, 1.0e5, 1.0e5]\n" + spring + LOSS + "\n")
out = Path(tempfile.mkdtemp())
(out / "ref.toml").write_text(text)
(out / "elastomer.toml").write_text(rubber)
with warnings.catch_warnings(record=True) as said:
    warnings.simplefilter("always")
    ref, el = flexbed.load_scene(out / "ref.toml"), flexbed.load_scene(out / "elastomer.toml")
for w in said:
    print(w.message)

# 2. Modes: each with the elastomers at its own frequency, ζ ≈ η/2.
m0, m1 = flexbed.modal(ref), flexbed.modal(el)
print("\nmode   steel f [Hz]  zeta     elastomer f [Hz]  zeta")
for j in range(6):
    print(f"{j + 1:4d} {m0.frequency[j]:12.3f} {m0.damping_ratio[j]:8.4f} "
          f"{m1.frequency[j]:14.3f} {m1.damping_ratio[j]:10.4f}")

# 3. Vertical transmissibility to the equipment and the bed.
pts = [("A", "equipment A", [0, 0, 0]), ("bed centre", "bed", [0, 0, 0])]
f = np.logspace(0, np.log10(40.0), 600)
t0 = flexbed.frf(ref, points=pts, frequencies=f)
t1 = flexbed.frf(el, points=pts, frequencies=f)
for name in ("A az", "bed centre az"):
    print(f"{name}: peak |T| steel {np.abs(t0.H[:, t0.column(name)]).max():.4g}, "
          f"elastomer {np.abs(t1.H[:, t1.column(name)]).max():.4g}")

# 4. The Maxwell fit of the table, against it.
table = dict(el.elastomers)[0]
fit = fit_maxwell(table)
print(f"\nMaxwell fit of the bed mounts' table: {fit.tau.size} terms, error "
      f"{100 * fit.error[2]:.2f} % over {fit.band[0]:g}-{fit.band[1]:g} Hz")
g = np.logspace(0, 2, 300)
K, Kf = table.complex(g)[:, 2], fit.complex(g)[:, 2]

fig, ax = plt.subplots(1, 2, figsize=(11, 4.2))
for t, style, label in ((t0, "--", "linear springs, no mount damping"), (t1, "-", "elastomer")):
    for name, colour in (("A az", "C0"), ("bed centre az", "C1")):
        ax[0].loglog(f, np.abs(t.H[:, t.column(name)]), style, color=colour,
                     label=f"{name}, {label}")
ax[0].set(xlabel="frequency [Hz]", ylabel="|T| [1] (base Z acceleration)",
          title="vertical transmissibility, reference scene")
ax[0].grid(True, which="both", alpha=0.3)
ax[0].legend(fontsize=8, loc="lower left")
ax[1].semilogx(g, K.real / 1e3, "C0-", label="table k(f) [kN/m]")
ax[1].semilogx(g, Kf.real / 1e3, "C0--", label="Maxwell fit, storage [kN/m]")
ax[1].set(xlabel="frequency [Hz]", ylabel="dynamic stiffness [kN/m]",
          title=f"bed mounts: table and Maxwell fit ({100 * fit.error[2]:.1f} % max)")
a2 = ax[1].twinx()
a2.semilogx(g, K.imag / K.real, "C3-", label="table η(f) [1]")
a2.semilogx(g, Kf.imag / Kf.real, "C3--", label="Maxwell fit, loss factor [1]")
a2.set_ylabel("loss factor η [1]")
h1, l1 = ax[1].get_legend_handles_labels()
h2, l2 = a2.get_legend_handles_labels()
ax[1].legend(h1 + h2, l1 + l2, fontsize=8, loc="upper left")
ax[1].grid(True, which="both", alpha=0.3)
fig.tight_layout()
fig.savefig(here / "elastomer-mounts.png", dpi=110)
print(f"wrote {here / 'elastomer-mounts.png'}")

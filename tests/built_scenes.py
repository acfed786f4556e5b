"""Scenes built directly as :mod:`flexbed.dynamics.scene` objects (no
TOML) that several test modules run: one body on one mount, and a
reference-like bed with one piece of equipment.

A plain module, not fixtures: the scenes are functions of the laws, axes
and base a test chooses. It imports by its plain name because pytest puts
this folder on ``sys.path`` (see ``conftest.py``)."""

import math

import numpy as np

from flexbed.dynamics.laws import LinearLaw
from flexbed.dynamics.scene import Base, Body, Load, Mount, Scene
from flexbed.dynamics.time_functions import Sinusoid, Triangle, sampled

# ------------------------------------------------------------ one body on one mount

M_BODY = 50.0       # kg
K = 2.0e4           # N/m
Z0 = 1.0            # m


def one_mount(c=0.0, base=None):
    """A 50 kg body hanging on one mount attached at its centre of mass, no
    gravity; ``c`` [N s/m] the mount's damping in each direction."""
    bodies = (Body("ground", 1e3, (1.0, 1.0, 1.0), (0, 0, 0)),
              Body("box", M_BODY, (2.0, 3.0, 4.0), (0, 0, Z0)))
    mount = Mount("m", "ground", "box", (0, 0, Z0), (0, 0, 0), np.eye(3), (LinearLaw(K, c),) * 3)
    return Scene(bodies, base or Base("fixed"), (mount,), (0.0, 0.0, 0.0), "one")


def free_vibration(system, amp, zeta, t):
    """Exact vertical displacement [m] of :func:`one_mount`'s body released
    from ``amp`` [m] at rest, damping ratio ``zeta``, at times ``t`` [s]."""
    wn = math.sqrt(K / M_BODY)
    wd = wn * math.sqrt(1 - zeta ** 2)
    return amp * np.exp(-zeta * wn * t) * (np.cos(wd * t) + zeta * wn / wd * np.sin(wd * t))


# ------------------------------------------------ a bed and one piece of equipment

SIGNS = [(-1, -1), (-1, 1), (1, -1), (1, 1)]
K_BED, K_EQ, C_EQ = 5.0e5, 1.0e5, 300.0     # N/m, N/m, N s/m


def bed_and_equipment(eq_laws, axes=None, base=None, bed_axes=None):
    """Base, bed on 4 mounts, one piece of equipment on 4 mounts
    (reference-like); ``eq_laws`` the equipment mounts' three laws, ``axes``
    and ``bed_axes`` their and the bed mounts' axes (3, 3) (default upright),
    ``base`` default: free, under a sampled sine and a triangle load."""
    axes = np.eye(3) if axes is None else axes
    bed_axes = np.eye(3) if bed_axes is None else bed_axes
    bodies = (Body("base", 1e6, (2.2e8, 4.2e4, 2.4e8), (0, 0, 0)),
              Body("bed", 2995.2, (5753.28, 162.24, 5910.53), (0, 0, 5.1)),
              Body("eq", 100.0, (9.1, 2.8, 10.4), (0.05, 0.3, 5.35)))
    mounts = [Mount(f"b{n}", "base", "bed", (0.4 * sx, 2.4 * sy, 5.0), (0.4 * sx, 2.4 * sy, 0.0),
                    bed_axes, (LinearLaw(K_BED),) * 3) for n, (sx, sy) in enumerate(SIGNS)]
    mounts += [Mount(f"e{n}", "bed", "eq", (0.05 + 0.24 * sx, 0.3 + 0.48 * sy, 0.0),
                     (0.24 * sx, 0.48 * sy, -0.15), axes, eq_laws)
               for n, (sx, sy) in enumerate(SIGNS)]
    base = base or Base("free", loads=(Load(2, sampled(Sinusoid(1e6, 5.0, 0.0, 0.0, 0.4), 1e-3)),
                                       Load(0, Triangle(3e5, 0.05, 0.1, 0.1))),
                        support="static")
    return Scene(bodies, base, tuple(mounts), (0.0, 0.0, -9.81), "t")

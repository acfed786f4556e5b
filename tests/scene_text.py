"""The two-body scene most hand-written test scenes start from: a heavy
base and one body above it, as TOML text to which a test appends its
mounts, base motion (``sine_drive``) and solver settings; and that body on four linear
mounts, the fault catalogue's scene, which the fuzzer and the sanity
checks mutate too.

A plain module, not fixtures: test modules build their scene texts at
import time (module constants, parametrisations, Hypothesis strategies).
It imports by its plain name because pytest puts this folder on
``sys.path`` (see ``conftest.py``)."""


def base_and_body(name: str, *, gravity: float = -9.81, mass: float = 50.0,
                  inertia: str = "[2.0, 3.0, 4.0]", body_extra: str = "") -> str:
    """``[scene]``, a 1000 kg base at the origin and body "mass" [kg] at
    z = 0.5 m; ``body_extra``: more keys of the body's table."""
    return f"""
[scene]
name = "{name}"
gravity = [0.0, 0.0, {gravity}]

[[body]]
name = "base"
mass = 1000.0
inertia = [100.0, 100.0, 100.0]
position = [0.0, 0.0, 0.0]

[[body]]
name = "mass"
mass = {mass}
inertia = {inertia}
position = [0.0, 0.0, 0.5]
{body_extra}"""


def sine_drive(amplitude, frequency, direction: str = "z") -> str:
    """``[base]`` driven by one sinusoidal acceleration: ``amplitude``
    [m/s²] at ``frequency`` [Hz] along ``direction``."""
    return f"""
[base]
motion = "driven"

[[base.drive]]
direction = "{direction}"
shape = "sinusoid"
amplitude = {amplitude}
frequency = {frequency}
"""


#: the corners of the mounts' square under body "mass" [m]
CORNERS = ((-0.2, -0.2), (0.2, -0.2), (0.2, 0.2), (-0.2, 0.2))


def four_mounts(law: str, *, corners=CORNERS, prefix: str = "M") -> str:
    """Four ``[[mount]]`` tables from the base (at z = 0.5 m) to body
    "mass" (at its centre's height) at ``corners`` (x, y) [m]; ``law``: the
    law's keys as TOML lines (e.g. ``'law = "linear"\\nk = [...]'``)."""
    return "".join(f"""
[[mount]]
name = "{prefix}{i}"
body_i = "base"
body_j = "mass"
point_i = [{x}, {y}, 0.5]
point_j = [{x}, {y}, 0.0]
{law.strip()}
""" for i, (x, y) in enumerate(corners, 1))


_LINEAR_MOUNT = """
[[mount]]
name = "M{n}"
body_i = "base"
body_j = "mass"
point_i = [{x}, {y}, 0.3]
point_j = [{x}, {y}, -0.2]
law = "linear"
k = [{k}, {k}, {k}]
"""


def body_on_four_mounts(*, mass="50.0", gravity="-9.81", inertia="[2.0, 3.0, 4.0]", k="1.0e5",
                        extra="", point_j_z="-0.2") -> str:
    """A 50 kg body on four linear mounts above a fixed base (statics in
    3 Newton steps); the arguments are pasted into the TOML as written.
    M1's ``point_j`` is the first ``-0.2]`` of the text."""
    mounts = "".join(_LINEAR_MOUNT.format(n=i + 1, x=x, y=y, k=k)
                     .replace("-0.2]", f"{point_j_z}]")
                     for i, (x, y) in enumerate([(-0.2, -0.2), (0.2, -0.2), (-0.2, 0.2),
                                                 (0.2, 0.2)]))
    return base_and_body("cat", mass=mass, gravity=gravity, inertia=inertia) + mounts + extra

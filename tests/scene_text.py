"""The two-body scene most hand-written test scenes start from: a heavy
base and one body above it, as TOML text to which a test appends its
mounts, base motion and solver settings."""


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

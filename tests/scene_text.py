"""The two-body scene most hand-written test scenes start from: a heavy base
and one body above it, as TOML text to which a test appends its mounts, base
motion (``driven_base``, ``sine_drive``) and solver settings; and that body
on four linear mounts, the fault catalogue's scene, which the fuzzer and the
sanity checks mutate too; the one-stage isolator whose closed forms the
modal, FRF, random and elastomer tests check (``one_stage``); and the
reference scene with its base held (``FIXED_REFERENCE``).

A plain module, not fixtures: test modules build their scene texts at
import time (module constants, parametrisations, Hypothesis strategies).
It imports by its plain name because pytest puts this folder on
``sys.path`` (see ``conftest.py``)."""

from flexbed.files.builtin import builtin_scene_text


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


def driven_base(shape: str, direction: str = "z", **keys) -> str:
    """``[base]`` driven by one acceleration of ``shape`` along
    ``direction``, its numeric keys (``peak``, ``start``, …) given."""
    lines = "".join(f"{k} = {v}\n" for k, v in keys.items())
    return f"""
[base]
motion = "driven"

[[base.drive]]
direction = "{direction}"
shape = "{shape}"
{lines}"""


def sine_drive(amplitude, frequency, direction: str = "z") -> str:
    """``[base]`` driven by one sinusoidal acceleration: ``amplitude``
    [m/s²] at ``frequency`` [Hz] along ``direction``."""
    return driven_base("sinusoid", direction, amplitude=amplitude, frequency=frequency)


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


# ------------------------------------------------------------ the one-stage isolator

M1 = 50.0                           # the body's mass [kg]
A, B = 0.2, 0.3                     # half-spacings of the mounts along x, y [m]
KX, KY, KZ = 2.0e4, 3.0e4, 5.0e4    # per mount [N/m]
J1 = (2.0, 3.0, 4.0)                # the body's principal inertias [kg m²]
ISOLATOR_CORNERS = [(-A, -B), (A, -B), (A, B), (-A, B)]


def isolator_mounts(prefix, body_i, body_j, z_i, k, beta, axes="", z_j=0.0) -> str:
    """Four linear ``[[mount]]`` tables "{prefix}1".."{prefix}4" at
    ``ISOLATOR_CORNERS`` (x, y) [m], from ``body_i`` at height ``z_i`` to
    ``body_j`` at ``z_j`` [m]; ``k`` (3,) [N/m], dampers c = ``beta`` k
    [s]; ``axes``: the mounts' axes as a TOML line (default upright)."""
    return "".join(f"""
[[mount]]
name = "{prefix}{n}"
body_i = "{body_i}"
body_j = "{body_j}"
point_i = [{x}, {y}, {z_i}]
point_j = [{x}, {y}, {z_j}]
{axes}law = "linear"
k = [{k[0]}, {k[1]}, {k[2]}]
c = [{beta * k[0]}, {beta * k[1]}, {beta * k[2]}]
""" for n, (x, y) in enumerate(ISOLATOR_CORNERS, 1))


def one_stage(beta, axes="", z_j=0.0) -> str:
    """Body "mass" (M1, J1) on four mounts (KX, KY, KZ; c = ``beta`` k) at
    its centre of mass's height (``z_j`` [m] from it): six uncoupled modes
    with closed forms (see ``test_modal``)."""
    return (base_and_body("isolator", mass=M1, inertia=f"[{J1[0]}, {J1[1]}, {J1[2]}]")
            + isolator_mounts("M", "base", "mass", 0.5 + z_j, (KX, KY, KZ), beta, axes, z_j))


def elastomer_stage(extra: str) -> str:
    """The one-stage isolator (no viscous damping) with ``extra`` keys on every mount."""
    return one_stage(0.0).replace('law = "linear"\n', f'law = "linear"\n{extra}\n')


def load_text(tmp_path, text, name="scene.toml"):
    """The scene of TOML ``text``, written to ``tmp_path / name`` and loaded."""
    import flexbed
    path = tmp_path / name
    path.write_text(text)
    return flexbed.load_scene(path)


# ------------------------------------------------ the reference scene, its base held

#: the reference scene's text without its ``[base]`` table (its base fixed)
FIXED_REFERENCE = builtin_scene_text().split("[base]")[0] + builtin_scene_text().split(
    "sample = 1.0e-3", 1)[1]

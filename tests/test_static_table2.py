"""Static equilibrium: the paper's Table 2, scenes without an equilibrium, and the
`flexbed static` command."""

import numpy as np

from flexbed.dynamics.laws import LinearLaw, PolynomialLaw
from flexbed.dynamics.rotation import angles_from_p
from flexbed.dynamics.scene import Base, Body, Mount, Scene
from flexbed.dynamics.statics import solve_statics
from flexbed.dynamics.system import System
from flexbed.cli import main
from flexbed.files.scene import load_scene


def flexbed(argv):
    """`flexbed ARGV` in-process; returns the exit code."""
    return main(argv)


def test_table2_of_the_reference_scene():
    """g = 9.81: z2 = 5.084327544, z3 = z4 = 5.331875044 within 1e-9 m (linear
    mounts: static deflection = weight / stiffness); x, y as placed; all
    orientations zero."""
    s = System(load_scene().scene)
    eq = solve_statics(s)
    assert eq.success, eq.message
    assert eq.iterations <= 6 and eq.residual < 1e-6
    parts = s.layout.split(eq.y)
    r = parts["r"]
    assert abs(r[0, 2] - 5.084327544) < 1e-9
    assert abs(r[1, 2] - 5.331875044) < 1e-9
    assert abs(r[2, 2] - 5.331875044) < 1e-9
    # closed form, to round-off: deflections m g / k
    g = 9.81
    z2 = 5.1 - (2995.2 + 200.0) * g / (4 * 5e5)
    z3 = z2 + 0.25 - 100.0 * g / (4 * 1e5)
    assert abs(r[0, 2] - z2) < 1e-12 and abs(r[1, 2] - z3) < 1e-12 and abs(r[2, 2] - z3) < 1e-12
    assert np.allclose(r[:, :2], [[0, 0], [0, -0.96], [0, 0.96]], atol=1e-12, rtol=0)
    assert np.max(np.abs(angles_from_p(parts["p"]))) < 1e-12


def box_on_mounts(laws, gravity=(0, 0, -9.81)):
    bodies = (Body("ground", 1e3, (1, 1, 1), (0, 0, 0)),
              Body("box", 100.0, (9.1, 2.8, 10.4), (0, 0, 1.0)))
    mounts = tuple(Mount(f"m{n}", "ground", "box", (0.2 * sx, 0.3 * sy, 0.8),
                         (0.2 * sx, 0.3 * sy, -0.2), np.eye(3), laws)
                   for n, (sx, sy) in enumerate([(-1, -1), (-1, 1), (1, -1), (1, 1)]))
    return System(Scene(bodies, Base("fixed"), mounts, gravity, "box"))


def test_hardening_polynomial_mount_converges_to_the_root():
    """Polynomial law f = k1 Δx + k3 Δx³ carrying a quarter of the weight each:
    the equilibrium deflection is the real root of k3 δ³ + k1 δ = m g / 4."""
    k1, k3 = 2e4, 5e7
    law = PolynomialLaw((0.0, k1, 0.0, k3))
    s = box_on_mounts((LinearLaw(1e5), LinearLaw(1e5), law))
    eq = solve_statics(s)
    assert eq.success, eq.message
    roots = np.roots([k3, 0.0, k1, -100.0 * 9.81 / 4])
    delta = float(np.real(roots[np.abs(roots.imag) < 1e-9][0]))
    z = s.layout.split(eq.y)["r"][0, 2]
    assert abs((1.0 - z) - delta) < 1e-12


def test_a_body_free_in_a_direction_has_no_equilibrium():
    """No stiffness along y (a polynomial law with a zero linear term): the
    stiffness matrix is singular; the message names the body and 'y'."""
    free_y = PolynomialLaw((0.0,), (0.0, 50.0))
    s = box_on_mounts((LinearLaw(1e5), free_y, LinearLaw(1e5)))
    eq = solve_statics(s)
    assert not eq.success
    assert "'box'" in eq.message and " free in y" in eq.message
    assert np.all(np.isfinite(eq.y))


def test_a_softening_mount_that_cannot_carry_the_weight_fails_cleanly():
    """f = k1 Δx + k2 Δx² never pulls harder than k1²/(4 k2) = 125 N per mount
    but the box needs 245 N: there is no root, Newton–Raphson cannot converge;
    the message names the body and 'z', and nothing is NaN."""
    law = PolynomialLaw((0.0, 1e3, 2e3))
    s = box_on_mounts((LinearLaw(1e5), LinearLaw(1e5), law))
    eq = solve_statics(s)
    assert not eq.success
    assert "no static equilibrium" in eq.message and "'box'" in eq.message
    assert " z" in eq.message
    assert np.all(np.isfinite(eq.y)) and np.isfinite(eq.residual)


def test_static_command_prints_table2_and_writes_the_equilibrium(tmp_path, capsys):
    out = tmp_path / "eq.h5"
    assert flexbed(["static", "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert "5.084327544" in text and "5.331875044" in text
    assert "iterations" in text and "residual" in text
    assert out.is_file()
    from flexbed.files.results import read_equilibrium
    sf = load_scene()
    s = System(sf.scene)
    y = read_equilibrium(out, sf, s)
    assert abs(s.layout.split(y)["r"][0, 2] - 5.084327544) < 1e-9


def test_static_command_without_equilibrium_exits_1(tmp_path, capsys):
    text = load_scene().text
    bad = text.replace('k = [1.0e5, 1.0e5, 1.0e5]\nc = [0.0, 0.0, 0.0]',
                       'stiffness = [[0.0], [0.0, 1.0e5], [0.0, 1.0e5]]')
    bad = bad.replace('law = "linear"\nstiffness', 'law = "polynomial"\nstiffness')
    scene = tmp_path / "free.toml"
    scene.write_text(bad)
    out = tmp_path / "eq.h5"
    assert flexbed(["static", str(scene), "-o", str(out)]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("flexbed static: free.toml: no static equilibrium")
    assert "'equipment A'" in err[0] and " free in x" in err[0]
    assert not out.exists()

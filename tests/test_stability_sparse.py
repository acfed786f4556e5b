"""The stability check of an equilibrium on large scenes (issue 30): M⁻¹K
from the block linearisation, its extreme eigenvalues by ARPACK
(:mod:`flexbed.dynamics.stability`'s sparse path), answers as the dense
path (every eigenvalue of the column-by-column linearisation) does. The
sparse path is forced on small scenes by ``dense_limit = 0``."""

import tomllib
from pathlib import Path

import numpy as np
import pytest

from flexbed.bench.tiling import tiled_text
from flexbed.dynamics.jacobian import mount_graph
from flexbed.dynamics.stability import DENSE_LIMIT, instability
from flexbed.dynamics.statics import solve_statics
from flexbed.files.scene import parse_scene
from flexbed.files.toml_text import dumps
from flexbed.stages.system import compile_scene
from scene_text import base_and_body, four_mounts


def _equilibrium(text: str, name: str):
    sf = parse_scene(text, Path(name))
    system = compile_scene(sf)
    eq = solve_statics(system, tol=1e-10)
    assert eq.success, eq.message
    return system, eq.y


def _negated(body: str):
    """The 2 × 2 tiling, the four mounts under ``body`` of negated stiffness
    (the linear law as a polynomial one): (system, equilibrium)."""
    data = tomllib.loads(tiled_text(2, bed_model="rigid"))
    neg = [m for m in data["mount"] if m["body_j"] == body]
    assert len(neg) == 4
    for m in neg:
        m["law"] = "polynomial"
        m["stiffness"] = [[0.0, -k] for k in m.pop("k")]
        m.pop("c")
    return _equilibrium(dumps(data), "negative.toml")


def _both(system, y):
    """(dense answer, sparse answer) at the equilibrium y."""
    assert mount_graph(system).n <= DENSE_LIMIT          # the default is the dense path
    return instability(system, y), instability(system, y, dense_limit=0)


def test_tiled_scene_stable_by_both_paths():
    """The 2 × 2 tiling (8 pieces of equipment, 54 free coordinates)."""
    system, y = _equilibrium(tiled_text(2, bed_model="rigid"), "tiled.toml")
    dense, sparse = _both(system, y)
    assert dense is None and sparse is None


def test_one_body_of_negative_stiffness_exact():
    """10 kg without gravity on four mounts of vertical stiffness
    −1e4 N/m (stiff sideways, as tests/test_unstable_statics.py): M⁻¹K has
    the eigenvalue 4 k_z / m = −4000 1/s² in z; both paths find it, as
    central differences of step h = 1e-6 m see it: the hardening cubic
    k₃ z³ adds k₃ h² to the slope, so 4 (k_z + k₃ h²) / m = −3999.99996."""
    held = base_and_body("held", gravity=0.0, mass=10.0, inertia="[1.0, 1.0, 1.0]")
    text = held + four_mounts("""
law = "polynomial"
stiffness = [[0.0, 1.0e4], [0.0, 1.0e4], [0.0, -1.0e4, 0.0, 1.0e8]]
""")
    system, y = _equilibrium(text, "unstable.toml")
    dense, sparse = _both(system, y)
    for r in (dense, sparse):
        assert (r.body, r.direction) == ("mass", "z")
        assert r.eigenvalue == pytest.approx(4.0 * (-1.0e4 + 1.0e8 * 1e-12) / 10.0, rel=1e-10)
        assert r.rate == pytest.approx(np.sqrt(-r.eigenvalue), rel=1e-15)
    assert sparse.eigenvalue == pytest.approx(dense.eigenvalue, rel=1e-9)


def test_tiled_scene_with_one_piece_on_negative_mounts():
    """The 2 × 2 tiling with the four mounts of one piece of equipment of
    negated stiffness (its equilibrium lifted, unstable): both paths name
    that piece, the same direction, and the same eigenvalue to 1e-6."""
    system, y = _negated("equipment B 1.0")
    dense, sparse = _both(system, y)
    assert dense is not None and sparse is not None
    assert dense.body == sparse.body == "equipment B 1.0"
    assert sparse.direction == dense.direction
    assert sparse.eigenvalue == pytest.approx(dense.eigenvalue, rel=1e-6)
    assert sparse.rate == pytest.approx(dense.rate, rel=1e-6)


def test_sparse_path_not_converged_falls_back_to_the_dense(monkeypatch):
    """ARPACK not converging: the dense path answers (the same Instability)."""
    from scipy.sparse.linalg import ArpackNoConvergence

    import flexbed.dynamics.stability as stability

    system, y = _negated("equipment A 0.1")
    dense = instability(system, y)

    def stuck(*args, **kwargs):
        raise ArpackNoConvergence("no convergence", np.zeros(0), np.zeros((0, 0)))

    monkeypatch.setattr(stability, "eigs", stuck)
    assert instability(system, y, dense_limit=0) == dense
    assert dense.body == "equipment A 0.1"

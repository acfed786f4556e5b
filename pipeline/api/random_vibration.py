"""Random vibration as a library call: :func:`random_vibration` and its
:class:`RandomVibration`.

>>> import flexbed
>>> r = flexbed.random_vibration(flexbed.load_scene(), psd="profile.toml")   # doctest: +SKIP
>>> r.rms[r.column("A top az")] / 9.80665                                   # doctest: +SKIP
>>> r.save("lee1999-random")                                                # doctest: +SKIP
"""

from __future__ import annotations

from pathlib import Path
from typing import Sequence

from flexbed.analyses import random as arandom
from flexbed.analyses.frf import MAX_GRID
from flexbed.files.psd import BasePSD, load_psd, psd_from_tables
from flexbed.api.arguments import Arguments
from flexbed.api.frequency import mounted_for, save_files
from flexbed.errors import InputError
from flexbed.files.destination import write_text
from flexbed.files.modes import ModesData
from flexbed.files.random import random_contents, write_random_contents
from flexbed.files.scene import SceneFile
from flexbed.threads import limited

__all__ = ["random_vibration", "RandomVibration", "random_files"]


class RandomVibration:
    """A random response (:func:`random_vibration`): ``frequency`` (k,) [Hz],
    ``input_psd`` (k, 3) [g²/Hz], ``names``, ``units`` (o,) SI, ``psd``
    (k, o) [unit²/Hz], ``rms``, ``rms_error``, ``three_sigma``, ``peak``
    (o,) [unit], ``miles`` (Miles' estimates), ``input_rms`` (3,) [g],
    ``solve_time`` [s CPU]; ``column(name)`` the index of an output."""

    def __init__(self, scene: SceneFile, r: arandom.RandomResponse):
        self.scene = scene
        self.result = r
        for key in ("frequency", "input_psd", "names", "units", "psd", "rms", "rms_error",
                    "three_sigma", "peak", "peak_factor", "miles", "input_rms", "resonances",
                    "damping_ratio", "solve_time"):
            setattr(self, key, getattr(r, key))

    def column(self, name: str) -> int:
        return self.result.column(name)

    def save(self, prefix: str | Path) -> list[Path]:
        """Write ``PREFIX.h5``, ``PREFIX-rms.csv`` and ``PREFIX-psd.csv`` (as
        ``flexbed random -o PREFIX --no-plots``); returns the paths."""
        return save_files(prefix, random_files(self.scene, self.result))


def random_files(scene: SceneFile, r: arandom.RandomResponse) -> dict:
    """The files ``flexbed random -o PREFIX --no-plots`` writes, in memory."""
    return {".h5": (write_random_contents, random_contents(scene, r)),
            "-rms.csv": (write_text, (arandom.rms_csv(r),)),
            "-psd.csv": (write_text, (arandom.psd_csv(r),))}


@limited()
def random_vibration(scene: SceneFile, *, psd, points: Sequence[tuple] | None = None,
                     n: int = 2000, peak_factor: float = 3.0,
                     modes: ModesData | None = None, equilibrium=None) -> RandomVibration:
    """Stationary random response to base acceleration PSDs.

    Parameters
    ----------
    scene : SceneFile
    psd : path, or dict
        A PSD file (:mod:`flexbed.files.psd`: TOML or CSV, g²/Hz),
        or ``{"x"|"y"|"z": [[f Hz, level g²/Hz], ...], "coherence":
        {"xz": γ}}``.
    points : sequence of (name, body, position[, relative_to]), optional
        Default: the scene's [[point]] tables, else every body's centre of mass.
    n : int
        Log-spaced frequencies of the base grid (each damped mode adds its own).
    peak_factor : float
        The peak reported besides 3σ: ``peak_factor`` σ.
    modes, equilibrium : as in :func:`flexbed.modal`.
    """
    check = Arguments("random_vibration")
    scene, modes = check.scene(scene), check.modes(modes)
    spec = _psd(psd, check)
    pts = check.points(points, "points")
    n = check.integer(n, "n", minimum=2, maximum=MAX_GRID)
    peak_factor = check.real(peak_factor, "peak_factor", positive=True, optional=False)
    names = [b.name for b in scene.scene.bodies]
    for key, body in [(f"points[{i}] body", p.body) for i, (p, _) in enumerate(pts or [])] + \
            [(f"points[{i}] relative_to", r) for i, (_, r) in enumerate(pts or []) if r]:
        if body not in names:
            check.bad(key, body, f"a body of {scene.source.name} ({', '.join(names)})")
    mt = mounted_for(scene, modes, equilibrium, check)
    return RandomVibration(scene, arandom.random_response(scene, mt, spec, points=pts, n=n,
                                                          peak_factor=peak_factor))


def _psd(psd, check: Arguments) -> BasePSD:
    if isinstance(psd, BasePSD):
        return psd
    if isinstance(psd, (str, Path)):
        return load_psd(check.path(psd, "psd"))
    if isinstance(psd, dict):
        tables = {k: v for k, v in psd.items() if k != "coherence"}
        try:
            return psd_from_tables(tables, psd.get("coherence"), "psd")
        except InputError as exc:
            check.fail("", str(exc))
    check.bad("psd", psd, "a PSD file (TOML or CSV) or {'z': [[Hz, g²/Hz], ...], ...}")

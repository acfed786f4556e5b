"""Shock by spectrum as library calls: the response-spectrum analysis of a
scene against a design spectrum (:func:`response_spectrum`) and a base
motion synthesised to it (:func:`synthesise`).

>>> import flexbed
>>> scene = flexbed.load_scene()
>>> r = flexbed.response_spectrum(scene, "deck.toml")           # doctest: +SKIP
>>> print(r.table("nrl"))                                       # doctest: +SKIP
>>> m = flexbed.synthesise("deck.toml", axis="z", band=(3, 300))  # doctest: +SKIP
>>> m.save("deck-z")                  # deck-z.csv: curve data for a drive  # doctest: +SKIP
"""

from __future__ import annotations

from pathlib import Path

from flexbed.analyses import response_spectrum as arsa
from flexbed.api.arguments import Arguments
from flexbed.api.frequency import mounted_for
from flexbed.files.destination import check_destination, write_text
from flexbed.files.modes import ModesData
from flexbed.files.scene import SceneFile
from flexbed.files.spectrum import SpectrumFile, read_spectrum
from flexbed.files.table_reader import MAX_SEED
from flexbed.threads import limited

__all__ = ["response_spectrum", "synthesise", "SpectrumResponse", "Motion"]


class SpectrumResponse:
    """A response-spectrum analysis (:func:`response_spectrum`):
    ``result`` the :class:`flexbed.analyses.response_spectrum.ResponseSpectrum`
    (``axes`` {0|1|2: AxisResponse with ``names``, ``units``, ``modal`` (m, k),
    ``combined`` {rule: (k,)}, ``mass_included``}), ``damping``,
    ``frequency`` (m,) [Hz], ``solve_time`` [s CPU]."""

    def __init__(self, scene: SceneFile, r: arsa.ResponseSpectrum):
        self.scene, self.result = scene, r
        self.axes, self.damping, self.frequency = r.axes, r.damping, r.frequency
        self.solve_time = r.solve_time

    def peak(self, axis: str, output: str, rule: str = "nrl") -> float:
        """The combined peak of one output [SI] for the base axis "x|y|z"."""
        a = self.axes["xyz".index(axis)]
        return float(a.combined[rule][a.column(output)])

    def table(self, rule: str | None = None) -> str:
        """The combined peaks in mm, N and g (Markdown); one rule's or all."""
        text = arsa.rsa_text(self.result)
        if rule is None:
            return text
        from flexbed.commands.rsa import _one_rule
        from flexbed.dynamics.frequency.response_spectrum import RULES
        return _one_rule(text, RULES.index(rule))

    def save(self, prefix: str | Path) -> list[Path]:
        """Write ``PREFIX.h5`` and ``PREFIX.csv`` (as ``flexbed rsa -o PREFIX``)."""
        from flexbed.files.response_spectrum import write_rsa
        h5 = check_destination(Path(f"{prefix}.h5"))
        csv = check_destination(Path(f"{prefix}.csv"))
        write_rsa(h5, self.scene, self.result)
        write_text(csv, arsa.rsa_csv(self.result))
        return [h5, csv]


class Motion:
    """A synthesised base acceleration (:func:`synthesise`): ``synthesis``
    the :class:`flexbed.dynamics.spectrum_synthesis.Synthesis` (``time``,
    ``acceleration`` [m/s²], ``frequency``, ``target``, ``achieved``,
    ``error_db``, ``end_velocity``, ``end_displacement``, …), and
    ``drive(direction)``: the ``[[base.drive]]`` table that reads it."""

    def __init__(self, spectrum: SpectrumFile, axis: str, syn):
        self.spectrum, self.axis, self.synthesis = spectrum, axis, syn
        self.path: Path | None = None

    def csv_text(self) -> str:
        s = self.synthesis
        return "time_s,acceleration_m_s2\n" + "\n".join(
            f"{t:.9g},{a:.12g}" for t, a in zip(s.time, s.acceleration)) + "\n"

    def save(self, prefix: str | Path, plot: bool = True) -> list[Path]:
        """Write ``PREFIX.csv`` (curve data) and, with ``plot``,
        ``PREFIX-srs.png`` (achieved against target)."""
        csv = check_destination(Path(f"{prefix}.csv"))
        out = [csv]
        write_text(csv, self.csv_text())
        self.path = csv.resolve()
        if plot:
            from flexbed.dynamics.pulses import STANDARD_GRAVITY
            from flexbed.plots.spectrum import plot_synthesis
            png = check_destination(Path(f"{prefix}-srs.png"))
            plot_synthesis(png, f"{self.spectrum.name} {self.axis}", self.synthesis,
                           STANDARD_GRAVITY)
            out.append(png)
        return out

    def drive(self, direction: str | None = None) -> dict:
        """The ``[[base.drive]]`` table of the saved curve (call :meth:`save` first)."""
        if self.path is None:
            raise ValueError("save the motion first (Motion.save): a drive reads its file")
        return {"direction": direction or self.axis, "shape": "curve", "file": str(self.path)}


def _spectrum(check: Arguments, spectrum) -> SpectrumFile:
    if isinstance(spectrum, SpectrumFile):
        return spectrum
    if isinstance(spectrum, (str, Path)) and str(spectrum):
        return read_spectrum(spectrum)
    check.bad("spectrum", spectrum, "a design spectrum file (str or pathlib.Path) or a "
                                    "SpectrumFile")


@limited()
def response_spectrum(scene: SceneFile, spectrum, *, damping: float | None = None,
                      max_frequency: float | None = None, modes: ModesData | None = None,
                      equilibrium=None) -> SpectrumResponse:
    """The response-spectrum analysis of a scene against a design spectrum.

    Parameters
    ----------
    scene : SceneFile
    spectrum : path of a design spectrum file, or a SpectrumFile
    damping : ζ [1], must be the spectrum's (default: it)
    max_frequency : leave out the modes above it [Hz]
    modes, equilibrium : as in :func:`flexbed.modal` (``equilibrium`` may be
        this scene's :class:`~flexbed.api.frequency.Modal`: its modes reused)
    """
    check = Arguments("response_spectrum")
    scene, modes = check.scene(scene), check.modes(modes)
    spec = _spectrum(check, spectrum)
    damping = check.real(damping, "damping")
    max_frequency = check.real(max_frequency, "max_frequency", positive=True)
    from flexbed.files.spectrum import check_damping
    check_damping(spec, damping)
    mt = mounted_for(scene, modes, equilibrium, check)
    return SpectrumResponse(scene, arsa.response_spectrum(scene, mt, spec, damping=damping,
                                                          max_frequency=max_frequency))


def synthesise(spectrum, *, axis: str = "z", band: tuple[float, float] | None = None,
               tolerance_db: float = 1.5, seed: int = 0) -> Motion:
    """A base acceleration matching the spectrum's ``axis`` on ``band`` [Hz]
    within ``tolerance_db`` at every check frequency (wavelets iterated;
    NumericalError when no attempt meets it).

    Parameters
    ----------
    spectrum : path of a design spectrum file, or a SpectrumFile
    axis : "x", "y" or "z"
    band : (f_lo, f_hi) [Hz] (default: the axis's first and last breakpoints)
    tolerance_db : [dB]; seed : int
    """
    from flexbed.commands.synthesise import check_request
    from flexbed.dynamics.spectrum_synthesis import synthesise as dsynth
    from flexbed.errors import NumericalError

    check = Arguments("synthesise")
    axis = check.string("", "axis", axis, ("x", "y", "z"))
    band = check.band(band)
    tol = check.real(tolerance_db, "tolerance_db", positive=True, optional=False)
    seed = check.integer(seed, "seed", minimum=0, maximum=MAX_SEED)
    spec = _spectrum(check, spectrum)
    design, lo, hi = check_request(spec, axis, band, tol)
    syn = dsynth(design, lo, hi, tolerance_db=tol, goal_db=min(1.0, 2.0 * tol / 3.0), seed=seed)
    if not syn.converged:
        k = int(abs(syn.error_db).argmax())
        raise NumericalError(f"{spec.source.name}: axis {axis}: no synthesis within "
                             f"±{tol:g} dB: {syn.error_db[k]:+.2f} dB at "
                             f"{syn.frequency[k]:.4g} Hz (try another seed or a wider tolerance)")
    return Motion(spec, axis, syn)

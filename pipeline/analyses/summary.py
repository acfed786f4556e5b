"""The tables of ``flexbed run`` that no single stage writes: the bed's
modes as CSV and the run's summary in Markdown (the stages' own tables,
built where the stages are, go in as text)."""

from __future__ import annotations

from pathlib import Path

from flexbed.files.modes import ModesData

__all__ = ["modes_csv", "summary_markdown"]

#: what the comparison's columns mean, as the summary says it
_COMPARISON_NOTE = (
    "d = vertical motion of the equipment relative to the base, from its static "
    "position; delay from the cross-correlation with the rigid case, searched over "
    "± half the period of the rigid response (\"beyond\" when the best shift is at "
    "that edge); decay = peak |d| over the second half of the free vibration / over "
    "its first half.")


def modes_csv(data: ModesData) -> str:
    """The bed's elastic modes, one row each: number, frequency [Hz], shape
    label and symmetry."""
    rows = ["mode,frequency_Hz,shape,symmetry"] + [
        f"{k + 1},{f:.10g},{lab},{sym}" for k, (f, lab, sym)
        in enumerate(zip(data.frequency, data.labels, data.symmetry))]
    return "\n".join(rows) + "\n"


def summary_markdown(name: str, source: Path, *, modes_table: str, equilibrium_table: str,
                     t_end: float, integrator: str, comparison_table: str,
                     point_tables: list[tuple[str, str]], files: list[Path],
                     mount_table: str = "") -> str:
    """The summary of a whole run (``<name>-summary.md``).

    Parameters
    ----------
    name : str
        The scene's output name.
    source : Path
        The scene file.
    modes_table, equilibrium_table, comparison_table : str
        The stages' tables as the terminal shows them (the bed's modes, the
        rigid bed's equilibrium, the comparison in Markdown).
    mount_table : str
        The mounts' static loads and deflections at that equilibrium
        (Markdown, :func:`flexbed.stages.plausibility.mount_table`); none:
        no section.
    t_end : float
        End of the simulations [s].
    integrator : str
    point_tables : list of (case, table)
        The points of interest's peaks per compared case (none: no section).
    files : list of Path
        Every file written, listed by name.
    """
    lines = [f"# {name}: summary", "", f"Scene: `{source}`.", "", "## Bed modes", "",
             "```", modes_table, "```", "",
             "## Static equilibrium (rigid bed, the paper's Table 2)", "", "```",
             equilibrium_table, "```", ""]
    if mount_table:
        lines += ["### Mounts at rest", "",
                  "Static force [N] and deflection [mm] along each mount's directions u1, u2, "
                  "u3 (extension positive; rigid bed).", "", mount_table, ""]
    lines += ["## Rigid, flexible and damped flexible bed", "",
              f"0-{t_end:g} s, {integrator}. " + _COMPARISON_NOTE, "", comparison_table, ""]
    if point_tables:
        lines += ["## Points of interest", "",
                  "Peak displacement from t = 0, speed and acceleration; absolute (inertial) "
                  "and relative to the scene's reference body (in its frame).", ""]
        for case, table in point_tables:
            lines += [f"### {case}", "", table, ""]
    lines += ["## Files", ""]
    lines += [f"- `{Path(f).name}`" for f in files]
    return "\n".join(lines) + "\n"

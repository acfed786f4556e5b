"""Making and writing a run's results file so that an interrupt loses nothing.

A run's results file needs its history (:func:`flexbed.dynamics.history.history`,
computed from the samples) before it is written. A SIGINT or SIGTERM that
arrives while the history is computed or the file written would otherwise
lose the whole run: here that work is done again with the signals held
back (:func:`flexbed.interrupts.held`), the file is marked incomplete
(root attributes ``complete`` false and ``message`` naming the signal and
the time the samples reach), and the interrupt is handed back for the
command to end with (exit 130 or 143). An interrupt that stopped the
integration itself is already marked in the run
(:attr:`flexbed.dynamics.integrate.Run.interrupt`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable

from flexbed.files.results import write_results_contents
from flexbed.interrupts import held, signal_name

__all__ = ["kept_contents", "write_kept"]

Contents = tuple[dict, dict]


def _mark(contents: Contents, exc: BaseException) -> Contents:
    """The contents marked incomplete by ``exc`` (unless already incomplete)."""
    ds, attrs = contents
    root = dict(attrs.get("", {}))
    if root.get("complete", False):
        t = ds["time"].data
        t_end = float(t[-1]) if len(t) else 0.0
        root["complete"] = False
        root["message"] = (f"interrupted ({signal_name(exc)}) while the results were "
                           f"written; the samples reach t = {t_end:.6g} s")
    return ds, {**attrs, "": root}


def kept_contents(make: Callable[[], Contents], interrupt: BaseException | None = None
                  ) -> tuple[dict, dict, BaseException | None]:
    """``make()`` (a results file's datasets and attrs: computes the history),
    made again with the signals held if an interrupt arrives meanwhile.

    Returns (datasets, attrs, interrupt): the interrupt the command must end
    with — ``interrupt`` (what stopped the integration), or the one that
    arrived while the contents were made (then they are marked incomplete)
    — or None."""
    try:
        ds, attrs = make()
        return ds, attrs, interrupt
    except KeyboardInterrupt as exc:
        late = exc
    with held():                       # a further signal changes nothing: the first decides
        ds, attrs = _mark(make(), late)
    return ds, attrs, interrupt or late


def write_kept(path: Path, make: Callable[[], Contents],
               interrupt: BaseException | None = None) -> BaseException | None:
    """Write the results file ``make()`` describes to ``path`` (atomically),
    whatever interrupt arrives meanwhile.

    Returns the interrupt the command must end with (see
    :func:`kept_contents`; one that arrives while the file is written marks
    it incomplete too, and it is written again with the signals held), or
    None."""
    ds, attrs, interrupt = kept_contents(make, interrupt)
    try:
        write_results_contents(path, ds, attrs)
        return interrupt
    except KeyboardInterrupt as exc:   # atomic_write removed its temporary file
        late = exc
    with held():
        write_results_contents(path, *_mark((ds, attrs), late))
    return interrupt or late

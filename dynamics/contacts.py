"""Bump-stop contacts during a run: held between the instants the
integrators locate, switched there.

A bump stop (:class:`flexbed.dynamics.laws.BumpStop`) adds a contact force
past its gap; the kernel adds it where Δx is past the gap
(:func:`flexbed.dynamics.kernel.rhs.evaluate`, section 4), which is what
the statics, the linearisation and the outputs use. An integrator instead
*holds* each stop's contact (none, compression, extension) through a
segment, so that the right-hand side it steps through stays smooth, and
watches each stop's margin

    m = min(Δx + g_c, g_e − Δx)   (free: positive while no stop touches),
    m = −(Δx + g_c)               (compression contact: positive while it lasts),
    m = Δx − g_e                  (extension contact),

after every step. When a margin turns negative within a step, the instant
is located by the Illinois method on m(τ), τ in the step, the state at τ
being the stepper's own step from the step's start to τ (accurate to its
tolerances, for every stepper alike; SciPy's steppers use their dense
output); the run goes on from there as from a breakpoint, the contact
switched (one-sided values: the new segment never evaluates the old
contact). The held contacts live in the kernel's work arrays
``w_contact`` and ``w_hold`` for the run's duration only (:meth:`Contacts.held`).
"""

from __future__ import annotations

from contextlib import contextmanager
from dataclasses import dataclass

import numpy as np

__all__ = ["Contacts", "ContactEvent", "MAX_EVENTS"]

#: a run that switches contacts more often than this is stopped (a grazing
#: stop chattering, or a gap that the motion crosses at every step)
MAX_EVENTS = 100_000


@dataclass(frozen=True, slots=True)
class ContactEvent:
    """A contact that began or ended: time [s], mount index, direction
    (0, 1, 2), side (−1 compression, +1 extension) and ``begins``."""

    t: float
    mount: int
    direction: int
    side: int
    begins: bool


class Contacts:
    """The bump stops of a compiled system, watched through one run.

    Parameters
    ----------
    system : System
        :class:`flexbed.dynamics.system.System`; its laws' ``stopped``
        entries are watched.
    """

    def __init__(self, system):
        self.system = system
        bank = system.laws
        self.entries = np.asarray(bank.stopped, dtype=np.intp)   # (n,) rows 3 m + k
        self.gap = bank.stop_gap[self.entries]                   # (n, 2)
        self.mode = np.zeros(self.entries.size)                  # −1, 0, +1
        self.events: list[ContactEvent] = []
        self._dy = np.empty(system.ny)

    def __bool__(self) -> bool:
        return bool(self.entries.size)

    def deflections(self, t: float, y: np.ndarray, seg_end: float) -> np.ndarray:
        """Δx (n,) [m] of the watched entries at the state y (ny,)."""
        self.system.rhs_into(t, np.ascontiguousarray(y), self._dy, seg_end)
        return self.system.data.w_dx.reshape(-1)[self.entries]

    def margins(self, x: np.ndarray, mode: np.ndarray | None = None) -> np.ndarray:
        """The margins (n,) [m] of the module docstring (positive: the mode holds)."""
        mode = self.mode if mode is None else mode
        gc, ge = self.gap[:, 0], self.gap[:, 1]
        free = np.minimum(x + gc, ge - x)
        return np.where(mode < 0, -(x + gc), np.where(mode > 0, x - ge, free))

    def start(self, t: float, y: np.ndarray, seg_end: float) -> None:
        """Take the contacts of the state at the run's start (by Δx) and
        hold them in the kernel."""
        x = self.deflections(t, y, seg_end)
        self.mode = np.where(x < -self.gap[:, 0], -1.0, np.where(x > self.gap[:, 1], 1.0, 0.0))
        self._write()

    def _write(self) -> None:
        self.system.data.w_contact[self.entries] = self.mode

    @contextmanager
    def held(self):
        """The kernel holds the contacts of :attr:`mode` inside (the
        integrator's view), and decides them by Δx again after."""
        d = self.system.data
        try:
            if self:
                d.w_hold[0] = 1.0
                self._write()
            yield self
        finally:
            if self:
                d.w_hold[0] = 0.0
                d.w_contact[:] = 0.0

    def crossed(self, t: float, y: np.ndarray, seg_end: float) -> np.ndarray:
        """Indices of the entries whose margin is negative at (t, y)."""
        return np.flatnonzero(self.margins(self.deflections(t, y, seg_end)) < 0.0)

    def locate(self, which: np.ndarray, t0: float, t1: float, state_at, seg_end: float):
        """The earliest instant in (t0, t1] where an entry of ``which``
        changes its contact, and that entry.

        state_at : callable(τ) -> y (ny,), the state at τ in [t0, t1]
        (the stepper's step from t0); the margins are positive at t0 and
        those of ``which`` negative at t1. Returns (τ, entry index, y(τ)),
        τ the bracket's end past the crossing (its width at most
        4 eps max(1, |t1|)).
        """
        best = None
        for j in which:
            def g(tau, j=j):
                y = state_at(tau)
                return self.margins(self.deflections(tau, y, seg_end))[j], y
            a, b = t0, t1
            ga = self.margins(self.deflections(t0, state_at(t0), seg_end))[j]
            gb, yb = g(t1)
            side = 0
            tol = 4.0 * np.finfo(float).eps * max(1.0, abs(t1))
            for _ in range(200):
                if b - a <= tol or gb == 0.0:
                    break
                c = b - gb * (b - a) / (gb - ga)
                if not (a < c < b):
                    c = 0.5 * (a + b)
                gc, yc = g(c)
                if gc < 0.0:
                    b, gb, yb = c, gc, yc
                    if side == -1:
                        ga *= 0.5
                    side = -1
                else:
                    a, ga = c, gc
                    if side == 1:
                        gb *= 0.5
                    side = 1
            if best is None or b < best[0]:
                best = (b, int(j), yb)
        return best

    def switch(self, j: int, t: float, y: np.ndarray, seg_end: float) -> list[ContactEvent]:
        """Switch entry j's contact at t (the state y there), and every
        other entry's whose margin is negative there too (stops crossed at
        the same instant, as on symmetric mounts), and hold them."""
        x = self.deflections(t, y, seg_end)
        crossed = set(np.flatnonzero(self.margins(x) < 0.0).tolist()) | {int(j)}
        out = []
        for i in sorted(crossed):
            old = self.mode[i]
            if old != 0.0:
                new, side, begins = 0.0, int(old), False
            else:
                side = -1 if x[i] + self.gap[i, 0] <= self.gap[i, 1] - x[i] else 1
                new, begins = float(side), True
            self.mode[i] = new
            il = int(self.entries[i])
            out.append(ContactEvent(float(t), il // 3, il % 3, side, begins))
        self._write()
        self.events.extend(out)
        if len(self.events) > MAX_EVENTS:
            ev = out[0]
            raise RuntimeError(f"more than {MAX_EVENTS} bump-stop contacts (mount {ev.mount}, "
                               f"direction {ev.direction + 1} at t = {t:.6g} s): a stop "
                               f"chattering")
        return out

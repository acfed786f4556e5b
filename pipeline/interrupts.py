"""SIGINT and SIGTERM as one exception, and sections that hold them back.

The command line (:func:`flexbed.cli.main`) installs :func:`handlers`:
both signals raise :class:`Interrupted` (raised again, by a SIGALRM
50 µs later, when the handler ran inside a finalizer or a ctypes
callback, where the exception would be lost), a :class:`KeyboardInterrupt`
that carries the signal's name and its exit code (128 + the signal's
number: 130 for SIGINT, 143 for SIGTERM). Everything that already keeps
what was computed on a Ctrl-C (the integrators return their samples
marked incomplete) does the same on a SIGTERM, and the atomic writes
remove their temporary files for both.

:func:`held` holds the signals back while what was computed is written:
a signal that arrives inside it is recorded, and acted on once the file
being written is finished. Light: the
standard library only.
"""

from __future__ import annotations

import signal
import sys
import threading
from contextlib import contextmanager
from typing import Iterator

__all__ = ["Interrupted", "handlers", "held", "signal_name", "exit_code", "kept", "message",
           "take_interrupt", "was_interrupted"]

_SIGNALS = (signal.SIGINT, signal.SIGTERM)


class Interrupted(KeyboardInterrupt):
    """A SIGINT or SIGTERM received by the command line.

    signum : int; name : "SIGINT" or "SIGTERM"; exit_code : 128 + signum.
    ``str()`` is the signal's name.
    """

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = int(signum)

    @property
    def name(self) -> str:
        return signal.Signals(self.signum).name

    @property
    def exit_code(self) -> int:
        return 128 + self.signum


def signal_name(exc: BaseException) -> str:
    """The signal an interrupt came from ("SIGINT" for a plain KeyboardInterrupt)."""
    return exc.name if isinstance(exc, Interrupted) else "SIGINT"


def exit_code(exc: BaseException) -> int:
    """The exit status for an interrupt: 128 + the signal's number."""
    return exc.exit_code if isinstance(exc, Interrupted) else 128 + signal.SIGINT


def kept(exc: BaseException, what: str) -> BaseException:
    """``exc`` with what was kept said (``what``: "at t = … s; the samples
    … are in FILE (marked incomplete)"), for :func:`message`."""
    exc.kept = what
    return exc


def message(exc: BaseException, command: str | None) -> str:
    """The one line the command line prints for an interrupt."""
    head = f"flexbed {command}" if command else "flexbed"
    what = getattr(exc, "kept", "")
    return f"{head}: interrupted ({signal_name(exc)})" + (f" {what}" if what else "")


#: the interrupts :func:`_raise` raised since :func:`handlers` began
_raised: list[int] = []


def _raise(signum, frame):
    _raised.append(signum)
    raise Interrupted(signum)


#: interrupts raised inside a finalizer, where they were lost: raised again
#: by :func:`_raise_lost` when SIGALRM comes (:func:`_unraisable`)
_lost: list[int] = []
#: True while :func:`_unraisable`'s hook runs (an exception raised there
#: would be lost too)
_in_hook = False

#: the delay of the timer that raises a lost interrupt again [s]: long
#: enough for the hook to return first (the timer's handler, run inside
#: the hook, sets it again), short against the code that runs next (numba's
#: compiler, cut in a ctypes callback, runs on into "no compiled object
#: yet": :func:`take_interrupt` lets the command line report such an error
#: as the interrupt it follows)
_AGAIN = 5e-5


def _raise_lost(signum, frame):
    if _in_hook:                                 # would be lost again: later
        signal.setitimer(signal.ITIMER_REAL, _AGAIN)
    elif _lost:
        signum = _lost.pop()
        _raised.append(signum)
        raise Interrupted(signum)


def _unraisable(hook):
    """A :data:`sys.unraisablehook` that does not lose an interrupt: a
    signal whose handler ran inside a finalizer (``__del__``: llvmlite
    frees its objects that way while numba compiles) or a ctypes callback
    (llvmlite's object cache) raised there, where Python can only print
    "Exception ignored in …" and go on, as if no Ctrl-C had come. The
    interrupt is recorded instead and a timer set (one C call: nothing
    here waits, so no second signal can land in this hook while it does):
    50 µs later SIGALRM raises it again in the Python code that
    runs next (and, landing in a finalizer again, comes back here; landing
    in this hook, sets the timer again). Anything else goes to ``hook``,
    unless an interrupt came first: a finalizer that then fails (an object
    the interrupt left half-built) is its consequence, and its "Exception
    ignored … Traceback" would break the interrupted run's one line (the
    likely cause of a traceback seen once, its text not kept, in the test
    of a first run stopped while it compiles)."""
    def unraisable(info):
        global _in_hook
        _in_hook = True
        try:
            if isinstance(info.exc_value, Interrupted):
                _lost.append(info.exc_value.signum)
                signal.setitimer(signal.ITIMER_REAL, _AGAIN)
                return
            if _raised or _lost:
                return      # a finalizer failing after an interrupt cut what it frees
            hook(info)
        finally:
            _in_hook = False
    return unraisable


def take_interrupt() -> Interrupted | None:
    """The interrupt an error followed, taken (a lost one's timer then
    raises nothing), or None: one lost in a finalizer or a callback and
    not raised again yet, else the last one raised.

    Code may turn an interrupt into an error of its own: numba's compiler,
    its object cache's callback cut, raises "no compiled object yet";
    CPython's ``PyCapsule_Import``, its module's import interrupted (NumPy
    being imported), an ImportError, the interrupt dropped. The command
    line reports such an error as the interrupt. The timer may still fire
    on entry here: callers catch :class:`KeyboardInterrupt` around the
    call."""
    if _lost:
        return Interrupted(_lost.pop())
    return Interrupted(_raised[-1]) if _raised else None


def was_interrupted() -> bool:
    """Whether an interrupt was raised, or lost and waits to be raised
    again (:func:`take_interrupt`), since :func:`handlers` began."""
    return bool(_lost or _raised)


def _in_main_thread() -> bool:
    return threading.current_thread() is threading.main_thread()


@contextmanager
def handlers() -> Iterator[None]:
    """Inside the block, SIGINT and SIGTERM raise :class:`Interrupted`; the
    previous handlers are restored afterwards (a no-op outside the main
    thread, where Python cannot set handlers)."""
    if not _in_main_thread():
        yield
        return
    old = {s: signal.signal(s, _raise) for s in _SIGNALS}
    old[signal.SIGALRM] = signal.signal(signal.SIGALRM, _raise_lost)
    old_hook = sys.unraisablehook
    sys.unraisablehook = _unraisable(old_hook)
    try:
        yield
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0.0)
        _lost.clear()
        _raised.clear()
        sys.unraisablehook = old_hook
        for s, h in old.items():
            signal.signal(s, h)


@contextmanager
def held() -> Iterator[list]:
    """Hold SIGINT and SIGTERM back inside the block.

    A signal that arrives is recorded (its number appended to the yielded
    list) instead of interrupting; the caller decides what to do with it
    once the block is done. A no-op outside the main thread."""
    pending: list[int] = []
    if not _in_main_thread():
        yield pending
        return

    def record(signum, frame):
        if signum != signal.SIGALRM:
            pending.append(signum)
        elif _lost:                                  # a lost interrupt's timer
            pending.append(_lost.pop())

    old = {s: signal.signal(s, record) for s in _SIGNALS}
    if _lost or signal.getsignal(signal.SIGALRM) is _raise_lost:
        old[signal.SIGALRM] = signal.signal(signal.SIGALRM, record)
    try:
        yield pending
    finally:
        for s, h in old.items():
            signal.signal(s, h)

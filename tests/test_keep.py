"""What an interrupt leaves of a results file, in-process: the contents are
made again with the signals held, and the file is marked incomplete."""

import os
import signal

import numpy as np

from flexbed.files.results import read_results
from flexbed.files.store import Dataset
from flexbed.interrupts import Interrupted, handlers, held
from flexbed.stages.keep import write_kept


def _contents():
    t = np.linspace(0.0, 2.0, 5)
    ds = {"time": Dataset(t, "s"), "bodies/position": Dataset(np.zeros((5, 1, 3)), "m"),
          "bodies/euler_parameters": Dataset(np.ones((5, 1, 4)), "1")}
    return ds, {"": {"complete": True, "message": "completed"}}


def test_an_interrupt_while_the_contents_are_made_is_kept(tmp_path):
    calls = []

    def make():
        calls.append(1)
        if len(calls) == 1:
            raise Interrupted(signal.SIGTERM)
        return _contents()

    out = tmp_path / "r.h5"
    got = write_kept(out, make)
    assert isinstance(got, Interrupted) and got.exit_code == 143 and len(calls) == 2
    c = read_results(out)
    assert c.attrs[""]["complete"] is False
    assert c.attrs[""]["message"] == ("interrupted (SIGTERM) while the results were written; "
                                      "the samples reach t = 2 s")
    assert [p.name for p in tmp_path.iterdir()] == ["r.h5"]


def test_the_integration_interrupt_is_handed_back_and_the_file_written(tmp_path):
    first = KeyboardInterrupt()
    out = tmp_path / "r.h5"
    assert write_kept(out, _contents, first) is first
    assert read_results(out).attrs[""]["complete"] is True   # as the run says


def test_held_records_the_signal_and_handlers_raise_it():
    before = signal.getsignal(signal.SIGTERM)
    with handlers():
        with held() as pending:
            os.kill(os.getpid(), signal.SIGTERM)
            os.kill(os.getpid(), signal.SIGINT)
        assert pending == [signal.SIGTERM, signal.SIGINT]
        try:
            os.kill(os.getpid(), signal.SIGTERM)
            for _ in range(1000):
                pass
        except Interrupted as exc:
            assert exc.exit_code == 143 and str(exc) == "SIGTERM"
        else:
            raise AssertionError("SIGTERM did not interrupt")
    assert signal.getsignal(signal.SIGTERM) == before

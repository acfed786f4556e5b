"""A worker process killed once a study's table holds its first row: the
lost-worker tests of ``test_sweep.py`` and ``test_study_cluster_faults.py``."""

from __future__ import annotations

import os
import signal
import threading
import time
from pathlib import Path


def kill_after_the_first_row(csv_path: Path, pid: int) -> tuple[threading.Thread, list]:
    """A started thread that sends SIGKILL to ``pid`` once ``csv_path``
    holds a row (within 120 s), and the list it appends the row count
    then written to."""
    killed: list = []

    def watch():
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline:
            if csv_path.exists() and len(csv_path.read_text().splitlines()) > 1:
                killed.append(len(csv_path.read_text().splitlines()) - 1)
                os.kill(pid, signal.SIGKILL)
                return
            time.sleep(0.02)

    thread = threading.Thread(target=watch, daemon=True)
    thread.start()
    return thread, killed

"""A fork server for the ``flexbed`` command lines the documentation tests
run: the command still runs whole, in a process of its own, through
:func:`flexbed.cli.main` with its own arguments, folder, environment,
standard streams and exit status, but forked from a process that has
imported NumPy, SciPy, numba, h5py and flexbed's commands once, instead of
importing them again (about a second of CPU per command line). The same
for ``python -c CODE [ARG ...]`` and ``python SCRIPT [ARG ...]`` (the
documentation's code blocks and scripts): run as the interpreter runs them
(``__main__``, ``sys.argv``, ``sys.path[0]``, the traceback and exit status
of an uncaught exception), forked; any other form of ``python`` is the real
interpreter, exec'd in the forked process.

``start(folder)`` starts the server and writes into ``folder`` the
executables ``flexbed`` and ``python`` that forward their arguments to it:
put ``folder`` first on the PATH of the shell that runs the page's lines.
Each request is served by a child of the server which forks the command
and waits for it, so the exit
status the shell sees is the command's own, after its interpreter has shut
down (a signal that ends it gives 128 + its number, as the shell reports).

Run as a script, ``python command_server.py SOCKET`` is the server.
"""

from __future__ import annotations

import json
import os
import runpy
import signal
import socket
import subprocess
import sys
import types
from pathlib import Path

#: what every command imports anyway, imported once by the server: every
#: command's module and the plotting modules with matplotlib (its Agg
#: backend, which flexbed.plots.figure selects: about 0.6 s of CPU for each
#: command that draws a figure). Not Dask's ``distributed``: a study's
#: command starts its cluster as a fresh process would.
PRELOAD = ("numpy", "scipy.linalg", "scipy.sparse", "h5py", "numba", "flexbed.cli",
           *(f"flexbed.commands.{name}" for name in (
               "scene", "modes", "static", "modal", "frf", "random", "simulate", "compare",
               "post", "stress", "transmitted", "srs", "qualify", "rsa", "synthesise", "run",
               "sweep", "optimize")),
           "flexbed.stages.simulation", "flexbed.dynamics.statics",
           *(f"flexbed.plots.{name}" for name in (
               "figure", "frequency", "random", "runs", "spectrum", "srs", "stress", "study",
               "transmitted")))

#: the ``flexbed`` a page's lines call: sends its arguments, folder,
#: environment and standard streams to the server, exits with the status
#: the server reports (no site import: it starts in milliseconds)
CLIENT = '''#!{python} -S
import json, os, socket, sys
s = socket.socket(socket.AF_UNIX)
s.connect({address!r})
socket.send_fds(s, [b"r"], [0, 1, 2])
msg = json.dumps([{kind!r}, sys.argv[1:], os.getcwd(), dict(os.environ)]).encode()
s.sendall(len(msg).to_bytes(8, "big") + msg)
reply = b""
while chunk := s.recv(64):
    reply += chunk
sys.exit(int(reply) if reply else 1)
'''


def _recv_exactly(conn: socket.socket, n: int) -> bytes:
    data = b""
    while len(data) < n:
        chunk = conn.recv(n - len(data))
        if not chunk:
            raise ConnectionError("the client went away")
        data += chunk
    return data


def _run_command(fds: list[int], kind: str, argv: list[str], cwd: str, env: dict) -> None:
    """In the forked command process: take the client's streams, folder and
    environment, run the command line as the ``flexbed`` script (``kind``
    "flexbed") or the interpreter (``kind`` "python") does, exit."""
    signal.signal(signal.SIGTERM, signal.SIG_DFL)
    for target, fd in enumerate(fds):
        os.dup2(fd, target)
        os.close(fd)
    os.chdir(cwd)
    os.environ.clear()
    os.environ.update(env)
    if kind == "python":
        _pool_sizes(env)
        _run_python(argv)
    sys.argv = ["flexbed", *argv]
    from flexbed.cli import script
    script()


def _pool_sizes(env: dict) -> None:
    """The BLAS and OpenMP pools at the sizes the client's environment asks
    (``OPENBLAS_NUM_THREADS``, ``OMP_NUM_THREADS``), as a fresh interpreter
    would start them: the server's were started before that environment."""
    from threadpoolctl import threadpool_limits
    for name, api in (("OPENBLAS_NUM_THREADS", "blas"), ("OMP_NUM_THREADS", "openmp")):
        if env.get(name, "").isdigit() and int(env[name]) >= 1:
            threadpool_limits(int(env[name]), user_api=api)


def _run_python(argv: list[str]) -> None:
    """``python -c CODE [ARG ...]`` or ``python SCRIPT [ARG ...]`` as the
    interpreter runs them, in this process; exits. Any other form (an
    option, ``-m``, no argument) execs the real interpreter."""
    if argv[:1] == ["-c"] and len(argv) >= 2:
        source = "<string>"
        sys.argv, sys.path[0] = ["-c", *argv[2:]], ""
        main = sys.modules["__main__"] = types.ModuleType("__main__")
        run = lambda: exec(compile(argv[1], source, "exec"), main.__dict__)  # noqa: E731
    elif argv and not argv[0].startswith("-"):
        script = source = os.path.abspath(argv[0])
        sys.argv, sys.path[0] = list(argv), os.path.dirname(script)
        run = lambda: runpy.run_path(script, run_name="__main__")  # noqa: E731
    else:
        os.execv(sys.executable, [sys.executable, *argv])
    try:
        run()
    except SystemExit:
        raise
    except BaseException:                  # noqa: BLE001 - as the interpreter reports it
        import traceback
        exc_type, exc, tb = sys.exc_info()
        while tb is not None and tb.tb_frame.f_code.co_filename != source:
            tb = tb.tb_next                # the frames from the user's code on, as python shows
        traceback.print_exception(exc_type, exc, tb)
        sys.exit(1)
    sys.exit(0)


def _serve_one(conn: socket.socket) -> None:
    """In the child serving one request: fork the command, wait for it, send
    its exit status."""
    _, fds, _, _ = socket.recv_fds(conn, 1, 3)
    size = int.from_bytes(_recv_exactly(conn, 8), "big")
    kind, argv, cwd, env = json.loads(_recv_exactly(conn, size))
    pid = os.fork()
    if pid == 0:
        conn.close()
        _run_command(fds, kind, argv, cwd, env)
    for fd in fds:
        os.close(fd)
    _, status = os.waitpid(pid, 0)
    code = os.waitstatus_to_exitcode(status)
    conn.sendall(str(code if code >= 0 else 128 - code).encode())


def _reap(block: bool = False) -> None:
    """Wait for the serving children that have finished (all, if ``block``):
    their CPU time, the commands' included, counts in the server's and so in
    the test run's."""
    while True:
        try:
            pid, _ = os.waitpid(-1, 0 if block else os.WNOHANG)
        except ChildProcessError:
            return
        if pid == 0:
            return


def _stop(signum, frame) -> None:
    """SIGTERM: wait for the serving children, then stop."""
    _reap(block=True)
    sys.exit(0)


def serve(address: str) -> None:
    """Import :data:`PRELOAD`, listen on the Unix socket ``address``, say
    "ready" on stdout, and serve each connection in a forked child."""
    import gc
    import importlib
    for name in PRELOAD:
        importlib.import_module(name)
    # what the imports made, out of the collector's sight: a forked command
    # neither scans nor (at its exit) copies those pages, 0.3 s of CPU each
    gc.freeze()
    signal.signal(signal.SIGTERM, _stop)
    listener = socket.socket(socket.AF_UNIX)
    listener.bind(address)
    listener.listen(16)
    print("ready", flush=True)
    while True:
        _reap()
        conn, _ = listener.accept()
        if os.fork() == 0:
            listener.close()
            # the command's process leaves _serve_one as the script would,
            # by SystemExit or an exception, through the interpreter's exit
            _serve_one(conn)
            os._exit(0)
        conn.close()


def start(folder: Path) -> subprocess.Popen:
    """Start the server on a socket in ``folder`` (a short path: a Unix
    socket's is at most 107 bytes) and write ``folder/flexbed`` and
    ``folder/python``; returns the server's process (terminate it when done)."""
    address = str(folder / "server.sock")
    server = subprocess.Popen([sys.executable, __file__, address], stdin=subprocess.DEVNULL,
                              stdout=subprocess.PIPE, text=True)
    if server.stdout.readline().strip() != "ready":
        server.kill()
        raise RuntimeError("the flexbed command server did not start")
    for kind in ("flexbed", "python"):
        client = folder / kind
        client.write_text(CLIENT.format(python=sys.executable, address=address, kind=kind))
        client.chmod(0o755)
    return server


if __name__ == "__main__":
    serve(sys.argv[1])

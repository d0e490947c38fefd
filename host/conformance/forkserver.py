"""One process that has imported the harness, forking a child per test file run in the
loop: ``run-tests.py`` starts its MicroPython once per file (57 files, and a feature check),
and a fresh CPython that imports the harness, numpy and the plant costs about 0.8 s of
each run's second before the rig starts. ``python -m host.conformance`` starts this
server for its runs in the loop; the wrapper it gives ``run-tests.py``
(:mod:`host.conformance.inloop`) sends its arguments, folder and board here, and prints
what comes back, exactly as it would have printed them itself.

Each file runs in a child forked from the server, which never runs a rig itself: the child
starts from the state a fresh process has after its imports, its stdout and stderr are
kept and sent back with the console and the exit status. A child dies with the server,
the server with the command that started it (``host/core/children.py``).

Protocol, on a Unix socket: the request and the reply are each one JSON object, the
request ending when the client shuts its side for writing.
"""

import json
import os
import socket
import sys
import tempfile

from host.conformance import inloop
from host.core.children import die_with_parent


def _child(conn, listener, request: dict) -> None:
    """In the forked child: run the file, send the reply, end (never returns)."""
    status = 1
    try:
        die_with_parent()
        listener.close()
        os.chdir(request["cwd"])
        os.environ[inloop.BOARD_ENV] = request["board"]
        out, err = tempfile.TemporaryFile(), tempfile.TemporaryFile()
        sys.stdout.flush()
        sys.stderr.flush()
        os.dup2(out.fileno(), 1)
        os.dup2(err.fileno(), 2)
        console, code = inloop.run(*inloop.parse(request["argv"]))
        sys.stdout.flush()
        sys.stderr.flush()
        out.seek(0)
        err.seek(0)
        reply = {"console": console, "status": code, "stdout": out.read().decode(errors="replace")}
        reply["stderr"] = err.read().decode(errors="replace")
        conn.sendall(json.dumps(reply).encode())
        status = 0
    finally:
        os._exit(status)


def serve(path: str) -> None:
    """Answer requests at ``path``, one at a time (``run-tests.py -j 1``), until killed."""
    inloop.preload()  # (what every run needs, imported once, before the forks)
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as listener:
        listener.bind(path)
        listener.listen(4)
        print("ready", flush=True)
        while True:
            conn, _ = listener.accept()
            with conn:
                request = json.loads(inloop.read_all(conn))
                pid = os.fork()
                if pid == 0:
                    _child(conn, listener, request)
                os.waitpid(pid, 0)


if __name__ == "__main__":
    serve(sys.argv[1])

"""Before any rig starts: is there a MicroPython interpreter? When the tests collected use
``make_rig`` and there is none, the session stops with one line saying the one command to
run (``mpy-fil setup``), not a traceback per test. Registered as its own pytest11 entry
point (pyproject.toml)."""

import pytest

from host.core import interpreter
from host.core.errors import SetupError
from host.pytest_plugin import mpy_versions


def pytest_collection_finish(session):
    if session.config.option.collectonly or not any(
        "make_rig" in getattr(i, "fixturenames", ()) for i in session.items
    ):
        return
    if mpy_versions.versions(session.config):
        mpy_versions.check(session)  # --mpy-version A,B: each of them
        return
    try:
        interpreter.find()
    except SetupError as e:
        pytest.exit(f"mpy-fil: {e}", returncode=pytest.ExitCode.USAGE_ERROR)

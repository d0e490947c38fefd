"""``pytest --mpy-version 1.25,1.28``: every rig test once per MicroPython version.

A test that makes a rig (``make_rig``, ``rig``) is parametrized by the versions asked for
(its id ends ``[mpy1.28]``, after its own parameters); its rigs run that version's interpreter
(``$MPY_FIL_MICROPYTHON`` for the test's length: :func:`selected_for`, read by the firmware
over its rig file's ``[interpreter] version``) and JUnit's ``micropython`` property names the
version and the interpreter's own version line. Without the option nothing changes: each rig
runs its rig file's version, else the default (``make test`` stays on one version). Before any
rig starts, each version asked for must have its interpreter (:func:`check`): the session stops
with the command that builds the missing one (docs/versions.md).
"""

import os

import pytest

from host.core import interpreter
from host.core.errors import SetupError

OPTION = "--mpy-version"
PARAM = "hil_mpy_version"
RIG_FIXTURES = {"make_rig", "rig"}


def addoption(group) -> None:
    group.addoption(
        OPTION,
        metavar="A,B",
        help="run every rig test once per MicroPython version (e.g. 1.25,1.28; ids show it: [mpy1.28]); "
        f"known: {', '.join(interpreter.RELEASES)} (docs/versions.md)",
    )


def versions(config) -> list[str]:
    """The versions asked for, as the harness names them (``1.28.0`` → ``1.28``), in order,
    each once; a usage error names an unknown one."""
    text = config.getoption(OPTION, None)
    if not text:
        return []
    found = []
    for item in text.split(","):
        if not item.strip():
            continue
        try:
            version = interpreter.release(item.strip()).version
        except SetupError as e:
            raise pytest.UsageError(f"{OPTION} {text}: {e}") from None
        if version not in found:
            found.append(version)
    if not found:
        raise pytest.UsageError(f"{OPTION}: expected versions such as 1.25,1.28, got {text!r}")
    return found


def generate(metafunc) -> None:
    wanted = versions(metafunc.config)
    if not wanted or not RIG_FIXTURES & set(metafunc.fixturenames):
        return
    if PARAM not in metafunc.fixturenames:
        metafunc.fixturenames.append(PARAM)  # (the test asks for no such argument: its rigs do)
    metafunc.parametrize(PARAM, wanted, ids=[f"mpy{v}" for v in wanted], indirect=True, scope="function")


def selected_for(node) -> str | None:
    """The version this test runs (its ``--mpy-version`` parameter), or None."""
    callspec = getattr(node, "callspec", None)
    return callspec.params.get(PARAM) if callspec is not None else None


class Selected:
    """``$MPY_FIL_MICROPYTHON`` set to a test's version while its rigs start and run, and
    put back as it was when the test's rigs are stopped."""

    def __init__(self, version: str | None):
        self.version = version
        self.before = os.environ.get(interpreter.VERSION_ENV)

    def __enter__(self):
        if self.version:
            os.environ[interpreter.VERSION_ENV] = self.version
        return self

    def __exit__(self, *exc):
        if not self.version:
            return
        if self.before is None:
            os.environ.pop(interpreter.VERSION_ENV, None)
        else:
            os.environ[interpreter.VERSION_ENV] = self.before


def record(node, version: str | None) -> None:
    """JUnit's ``micropython`` property: the version a test's rigs ran and its version line."""
    try:
        path = interpreter.find(version)
        line = interpreter.version_line(path)
        node.user_properties.append(("micropython", f"{interpreter.release(version).version}: {line}"))
    except (SetupError, OSError) as e:
        node.user_properties.append(("micropython", f"{interpreter.release(version).version}: {e}"))


def check(session) -> None:
    """Each version asked for has an interpreter, before any rig starts."""
    for version in versions(session.config):
        try:
            interpreter.find(version)
        except SetupError as e:
            pytest.exit(f"mpy-fil: {OPTION} {version}: {e}", returncode=pytest.ExitCode.USAGE_ERROR)


def header(config) -> str | None:
    wanted = versions(config)
    if not wanted:
        return None
    lines = []
    for version in wanted:
        try:
            path = interpreter.find(version)
            lines.append(f"micropython {version}: {interpreter.version_line(path)} ({path})")
        except SetupError as e:
            lines.append(f"micropython {version}: not available ({e})")
    return "\n".join(lines)

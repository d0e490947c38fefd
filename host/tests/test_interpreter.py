"""Interpreter discovery: MICROPYTHON overrides the build, with a clear error if wrong."""

import pytest

from host.core import interpreter
from host.core.errors import SetupError


def test_micropython_override_must_be_an_executable(monkeypatch, tmp_path):
    monkeypatch.setenv("MICROPYTHON", str(tmp_path / "nope"))
    with pytest.raises(SetupError, match=r"MICROPYTHON=.*nope is not an executable file"):
        interpreter.find()


def test_micropython_override_is_used(monkeypatch):
    built = interpreter.default_path()
    monkeypatch.setenv("MICROPYTHON", str(built))
    assert interpreter.find() == built
    assert interpreter.version(built).startswith("MicroPython v1.25.0")


def test_build_is_cached(capsys):
    interpreter.build()  # the binary exists: nothing is fetched or compiled
    assert "up to date" in capsys.readouterr().out

"""Interpreter discovery: MICROPYTHON overrides the build, with a clear error if wrong."""

from pathlib import Path

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


# The mirror: taken from the machine's apt sources, never named in the repository.

ONE_LINE = """\
# a comment
deb [arch=amd64 signed-by=/usr/share/keyrings/other.gpg] https://repo.example/node nodistro main
deb http://mirror.example/debian-security bookworm-security main
deb [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://mirror.example/debian/ bookworm main contrib
"""

DEB822 = """\
Types: deb
URIs: http://disabled.example/debian
Suites: trixie
Components: main
Enabled: no

Types: deb deb-src
URIs: file:/srv/local-mirror/debian
  http://second.example/debian
Suites: trixie trixie-updates
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
"""


def test_the_mirror_is_the_first_enabled_debian_main_archive_of_the_machines_sources(tmp_path, monkeypatch):
    from host.core import aptsources

    monkeypatch.delenv(aptsources.OVERRIDE, raising=False)
    listed = tmp_path / "sources.list"
    listed.write_text(ONE_LINE)
    modern = tmp_path / "debian.sources"
    modern.write_text(DEB822)
    assert aptsources.debian_mirror([listed]) == "http://mirror.example/debian"
    assert aptsources.debian_mirror([modern]) == "file:/srv/local-mirror/debian", "Enabled: no is skipped"
    line = interpreter.sources_line([modern])
    keyring, suite = interpreter.DEBIAN_KEYRING, interpreter.DEBIAN_SUITE
    assert line == f"deb-src [signed-by={keyring}] file:/srv/local-mirror/debian {suite} main"


def test_no_debian_archive_is_a_setup_error_naming_the_files_and_the_override(tmp_path, monkeypatch):
    from host.core import aptsources

    monkeypatch.delenv(aptsources.OVERRIDE, raising=False)
    other = tmp_path / "nodesource.list"
    other.write_text("deb https://repo.example/node nodistro main\ndeb http://x.example/d bookworm-security main\n")
    with pytest.raises(SetupError, match=r"no Debian archive .*nodesource\.list.*DEBIAN_MIRROR="):
        aptsources.debian_mirror([other])
    monkeypatch.setenv(aptsources.OVERRIDE, "http://given.example/debian/")
    assert aptsources.debian_mirror([other]) == "http://given.example/debian"


def test_this_machines_apt_sources_are_read_where_apt_config_says():
    from host.core import aptsources

    files = aptsources.source_files()
    assert all(p.is_file() for p in files)
    assert any(e.is_debian_main_archive() for e in aptsources.entries(files)) or not files


def test_no_mirror_host_is_named_in_the_repository():
    import re
    import subprocess

    from host.core.paths import REPO

    tracked = subprocess.run(["git", "-C", str(REPO), "ls-files"], capture_output=True, text=True, check=True)
    pattern = re.compile(
        r"\b[\w.-]*\.debian\.(?:org|net)\b|\bmirrors?\.[\w-]+\.[a-z]{2,}|\b(?:pypi\.org|files\.pythonhosted\.org)\b"
    )
    named = []
    for rel in tracked.stdout.split():
        path = REPO / rel
        if path.is_file() and path.suffix not in (".png", ".gif", ".ico"):
            for match in pattern.finditer(path.read_text(errors="replace")):
                named.append(f"{rel}: {match.group(0)}")
    assert not named, f"expected no package registry or mirror host in the repository, found: {named}"


def test_the_interpreter_we_build_has_no_ffi():
    """No board has ``ffi`` (a firmware could call the host's libc through it): our build
    leaves it out (``MAKE_OPTIONS``), and keeps the modules a rig file may give back."""
    import subprocess

    built = interpreter.default_path()
    probe = """
for m in ("ffi", "socket", "_thread"):
    try:
        __import__(m)
        print(m, "in")
    except ImportError:
        print(m, "out")
"""
    said = subprocess.run([str(built), "-c", probe], capture_output=True, text=True, timeout=30).stdout.split("\n")
    assert said[:3] == ["ffi out", "socket in", "_thread in"], (
        f"{built} (MAKE_OPTIONS {interpreter.MAKE_OPTIONS}): {said}"
    )


def _stale_checkout_build(monkeypatch, tmp_path) -> tuple[Path, list]:
    """A checkout's build folder under tmp_path with a binary whose identity file was written
    before the patches changed; compiling recorded, never done."""
    monkeypatch.setattr(interpreter.paths, "CHECKOUT", True)
    monkeypatch.setattr(interpreter.paths, "BUILD", tmp_path / "build")
    monkeypatch.delenv(interpreter.VERSION_ENV, raising=False)
    target = interpreter.default_path()
    target.parent.mkdir(parents=True)
    target.write_text("#!/bin/sh\necho 'MicroPython v1.25.0'\n")
    target.chmod(0o755)
    interpreter._identity_file(target).write_text(interpreter._identity_text("standard", None))
    ours = interpreter.patches_text
    monkeypatch.setattr(interpreter, "patches_text", lambda version=None: ours(version) + "\n# changed\n")
    compiled = []
    monkeypatch.setattr(interpreter, "_compile", lambda *a, **k: compiled.append(a))
    monkeypatch.setattr(interpreter, "ensure_tools", lambda: None)
    monkeypatch.setattr(interpreter, "fetch_source", lambda *a, **k: tmp_path / "tree")
    return target, compiled


def test_a_stale_checkout_build_names_what_changed_and_is_not_rebuilt_under_running_tests(monkeypatch, tmp_path):
    """A test session (make test) runs on the binary make setup built: a test that found it out
    of date and rebuilt it took it from under the other workers, which found no interpreter."""
    target, compiled = _stale_checkout_build(monkeypatch, tmp_path)
    assert not interpreter.current(target, "standard")
    assert interpreter.changed_inputs(target, "standard") == ["patches"]
    with pytest.raises(SetupError, match=r"out of date \(patches changed since it was built\).*make setup") as e:
        interpreter.build()
    assert compiled == [], f"expected no compile under a test session, got {compiled}"
    log = (target.parent.parent / interpreter.BUILD_LOG).read_text()
    assert "micropython: patches;" in log and "test host/tests/test_interpreter.py::" in log, log
    assert str(target.parent.parent / interpreter.BUILD_LOG) in str(e.value)


def test_outside_a_test_session_a_stale_checkout_build_is_rebuilt_and_logged(monkeypatch, tmp_path):
    target, compiled = _stale_checkout_build(monkeypatch, tmp_path)
    monkeypatch.delenv("PYTEST_CURRENT_TEST")
    assert interpreter.build() == target and len(compiled) == 1, compiled
    log = (target.parent.parent / interpreter.BUILD_LOG).read_text().splitlines()
    assert len(log) == 1 and "micropython: patches;" in log[0] and "; test " not in log[0], log


def test_the_identity_file_names_each_input_and_a_changed_c_module_file_by_name(monkeypatch, tmp_path):
    target, _ = _stale_checkout_build(monkeypatch, tmp_path)
    text = interpreter._identity_file(target).read_text().splitlines()
    names = [line.split(" ", 1)[1] for line in text[1:]]
    assert names[:3] == ["options", "patches", "manifest.py"] and "cmod/_hilfast/_hilfast.c" in names, names
    recorded = dict(reversed(line.split(" ", 1)) for line in text[1:])
    recorded["cmod/_hilfast/_hilfast.c"] = "0" * 16
    interpreter._identity_file(target).write_text(text[0] + "\n" + "".join(f"{h} {n}\n" for n, h in recorded.items()))
    assert interpreter.changed_inputs(target, "standard") == ["cmod/_hilfast/_hilfast.c", "patches"]

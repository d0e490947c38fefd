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

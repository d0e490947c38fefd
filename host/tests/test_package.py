"""The package as a user's repository gets it: the wheel and sdist built from this
repository, the wheel installed in a fresh virtual environment in a scratch folder outside
the repository, every CLI command run from there, and docs/ci.md's recipe run as printed
on a copy of examples/pico_bot.

Nothing is downloaded: the fresh environment gets the wheel with ``--no-deps`` and sees
the project's own environment's packages through a ``.pth`` line (not its editable install
of this checkout: ``.pth`` files of a folder named in a ``.pth`` line are not read). The
interpreter is the project's (``MICROPYTHON``); MicroPython is not rebuilt. The scratch
folder is removed at the end."""

import os
import re
import shutil
import subprocess
import sys
import sysconfig
import tarfile
import tempfile
import zipfile
from pathlib import Path

import pytest
import tomllib

from host.core import interpreter
from host.core.paths import REPO

pytestmark = pytest.mark.hil
VERSION = tomllib.loads((REPO / "pyproject.toml").read_text())["project"]["version"]
CI_DOC = REPO / "docs" / "ci.md"
BUILD_TIMEOUT_S = 300


class Scratch:
    """A folder outside the repository with the built wheel and sdist, a fresh venv with
    the wheel installed, a per-user cache of its own and a user's robot (pico_bot)."""

    def __init__(self, root: Path):
        self.root = root
        self.dist = root / "dist"
        self.venv = root / "venv"
        self.robot = root / "robot"
        self.cache = root / "cache"
        subprocess.run(
            [sys.executable, "-m", "build", "--no-isolation", "-o", str(self.dist), str(REPO)],
            check=True,
            capture_output=True,
            timeout=BUILD_TIMEOUT_S,
        )
        self.wheel = next(self.dist.glob("*.whl"))
        self.sdist = next(self.dist.glob("*.tar.gz"))
        subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(self.venv)], check=True, timeout=60)
        python = self.venv / "bin" / "python"
        purelib = subprocess.run(
            [str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
        Path(purelib, "project-packages.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
        self.pip_install(self.wheel)
        launcher = self.venv / "bin" / "pytest"  # (what pip install of pytest, a dependency, would write)
        launcher.write_text(f"#!{python}\nimport sys\nfrom pytest import console_main\nsys.exit(console_main())\n")
        launcher.chmod(0o755)
        shutil.copytree(REPO / "examples" / "pico_bot", self.robot)

    def pip_install(self, wheel: Path) -> None:
        pip = [sys.executable, "-m", "pip", "--python", str(self.venv / "bin" / "python")]
        subprocess.run([*pip, "install", "-q", "--no-deps", "--no-index", str(wheel)], check=True, timeout=120)

    def env(self, **extra) -> dict:
        """The user's shell: the venv first on PATH, nothing of this checkout, the cache here."""
        ours = ("PYTHONPATH", "VIRTUAL_ENV", "MICROPYTHON")  # (and this session's PYTEST_* variables)
        env = {k: v for k, v in os.environ.items() if k not in ours and not k.startswith("PYTEST_")}
        env.update(PATH=f"{self.venv / 'bin'}:/usr/bin:/bin", XDG_CACHE_HOME=str(self.cache), MPLBACKEND="Agg")
        env.update(extra)
        return {k: v for k, v in env.items() if v is not None}

    def sh(self, command: str, cwd: Path | None = None, timeout_s: float = 240, **env) -> subprocess.CompletedProcess:
        return subprocess.run(
            ["bash", "-c", command],
            cwd=cwd or self.root,
            env=self.env(**env),
            capture_output=True,
            text=True,
            timeout=timeout_s,
        )


@pytest.fixture(scope="module")
def scratch():
    with tempfile.TemporaryDirectory(prefix="mpy-fil-package-") as folder:
        yield Scratch(Path(folder))
    assert not Path(folder).exists()


@pytest.fixture(scope="module")
def micropython() -> str:
    return str(interpreter.find())


def test_the_wheel_carries_what_the_harness_needs_and_not_the_tests(scratch):
    names = set(zipfile.ZipFile(scratch.wheel).namelist())
    for needed in (
        "host/_data/firmware/apps/rover/main.py",
        "host/_data/firmware/apps/rover/rig.toml",
        "host/_data/firmware/apps/vacuum/mission.json",
        "host/_data/firmware/boards/rpi_pico/board.py",
        "host/_data/firmware/lib/hcsr04.py",  # (harness_lib)
        "host/_data/examples/pico_bot/rig.toml",
        "host/shim/machine.py",
        "host/core/micropython/manifest.py",  # (the interpreter's build)
        "host/shim/cmod/_hilfast/_hilfast.c",  # (its user C module)
        "host/shim/cmod/_hilfast/micropython.mk",
        "host/core/aptsources.py",  # (its deb-src line)
        "sim_plant/catalogue/__init__.py",
    ):
        assert needed in names, f"expected {needed} in {scratch.wheel.name}"
    tests = sorted(n for n in names if "/tests/" in n)
    assert not tests, f"expected no tests in the wheel, found {tests[:5]}"
    with tarfile.open(scratch.sdist) as sdist:
        members = {m.name.split("/", 1)[-1] for m in sdist.getmembers()}
    assert {"setup.py", "pyproject.toml", "firmware/apps/rover/main.py", "examples/pico_bot/rig.toml"} <= members


def test_every_cli_command_works_from_the_installed_package(scratch, micropython):
    done = scratch.sh("mpy-fil --version")
    assert done.stdout.strip() == f"mpy-fil {VERSION}", done.stdout + done.stderr
    where = scratch.sh("python -c 'import host; print(host.__file__)'").stdout
    assert where.startswith(str(scratch.venv)), f"expected the installed package, imported {where}"

    listed = scratch.sh("mpy-fil list")
    assert listed.returncode == 0 and "  rover " in listed.stdout and "rpi_pico" in listed.stdout, listed.stderr

    run = scratch.sh("mpy-fil run --app rover --seconds 1", MICROPYTHON=micropython)
    assert run.returncode == 0, run.stderr
    out = scratch.root / "build" / "runs" / "rover-room-seed0"
    assert f"trace folder: {out}" in run.stdout, run.stdout
    assert "  | rover on esp32-devkitc control every 50 ms" in run.stdout, "expected the firmware's console"
    assert "  console.log " in run.stdout and "  plots/trajectory.png " in run.stdout, run.stdout

    rig = scratch.sh("mpy-fil run rig.toml --seconds 2", cwd=scratch.robot, MICROPYTHON=micropython)
    assert rig.returncode == 0, rig.stderr
    assert "pico_bot: press start" in rig.stdout and (scratch.robot / "build" / "runs").is_dir(), rig.stdout

    check = scratch.sh("mpy-fil check rig.toml", cwd=scratch.robot)
    assert check.returncode == 0 and check.stdout.startswith("rig.toml: ok"), check.stdout + check.stderr

    setup = scratch.sh("mpy-fil setup", MICROPYTHON=micropython)
    assert setup.returncode == 0 and "micropython: MicroPython v1.25.0+ds-1 on" in setup.stdout, setup.stderr
    site = scratch.sh("python -c 'import sysconfig; print(sysconfig.get_paths()[\"purelib\"])'").stdout.strip()
    assert not (Path(site) / "build").exists(), "expected nothing written into site-packages"


def test_no_interpreter_says_the_one_command_to_run(scratch, tmp_path):
    empty = tmp_path / "cache"  # (no build in it, none on PATH, MICROPYTHON unset)
    run = scratch.sh("mpy-fil run --app rover --seconds 1", XDG_CACHE_HOME=str(empty))
    assert run.returncode == 1 and "Traceback" not in run.stderr, run.stderr
    assert run.stderr.count("\n") == 1 and run.stderr.rstrip().endswith("run `mpy-fil setup`"), run.stderr
    tests = scratch.sh("python -m pytest -q -p no:cacheprovider", cwd=scratch.robot, XDG_CACHE_HOME=str(empty))
    assert tests.returncode == 4 and "run `mpy-fil setup`" in tests.stdout, tests.stdout[-2000:]
    assert "Traceback" not in tests.stdout and "passed" not in tests.stdout, tests.stdout[-2000:]


def ci_commands() -> list[str]:
    """The ``run:`` lines of docs/ci.md's workflow, in order."""
    block = re.search(r"```yaml\n(.*?)```", CI_DOC.read_text(), re.S).group(1)
    return [m.group(1).strip() for m in re.finditer(r"^\s*- run: (.+)$", block, re.M)]


def test_the_ci_recipe_runs_as_printed_on_a_copy_of_pico_bot(scratch, micropython):
    commands = ci_commands()
    install = [c for c in commands if c.startswith("pip install")]
    assert install == [f"pip install mpy-fil=={VERSION}"], "expected the recipe to pin this release"
    ours = commands[commands.index(install[0]) + 1 :]
    assert ours[0] == "mpy-fil setup" and ours[1].startswith("pytest"), ours
    repo = scratch.robot  # the user's repository: pico_bot's folder as it is
    for command in ours:
        done = scratch.sh(command, cwd=repo, timeout_s=600, MICROPYTHON=micropython)
        assert done.returncode == 0, f"{command}: {done.stdout[-3000:]}{done.stderr[-2000:]}"
    assert re.search(r"\b4 passed\b", done.stdout), done.stdout[-2000:]
    junit = (repo / "build" / "junit.xml").read_text()
    assert 'tests="4"' in junit and 'failures="0"' in junit, junit[:500]
    assert (repo / "build" / "hil" / "report.html").is_file()


def test_setup_builds_into_the_per_user_cache_and_a_checkout_into_its_build(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    cache = interpreter.build_root(checkout=False)
    assert cache == tmp_path / "xdg" / "mpy-fil" / "micropython"
    assert interpreter.default_path(cache) == cache / "1.25.0+ds-1" / "micropython", "versioned"
    assert interpreter.build_root(checkout=True) == REPO / "build" / "micropython"
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert interpreter.build_root(checkout=False) == tmp_path / "home" / ".cache" / "mpy-fil" / "micropython"


@pytest.mark.parametrize(("printed", "used"), [("MicroPython v1.25.0 on 2025-01-01", True), ("v1.22.2", False)])
def test_a_micropython_on_path_is_used_only_at_the_pinned_version(monkeypatch, tmp_path, printed, used):
    fake = tmp_path / "bin" / "micropython"
    fake.parent.mkdir()
    fake.write_text(f"#!/bin/sh\necho '{printed}'\n")
    fake.chmod(0o755)
    monkeypatch.setenv("PATH", f"{fake.parent}:/usr/bin:/bin")
    assert interpreter.on_path() == (fake if used else None)
    if not used:
        assert "needs MicroPython 1.25" in interpreter.version_problem(fake)


def test_no_interpreter_in_a_clone_says_make_setup(monkeypatch, tmp_path):
    from host.core import paths
    from host.core.errors import SetupError

    monkeypatch.delenv("MICROPYTHON", raising=False)
    monkeypatch.setattr(paths, "BUILD", tmp_path / "build")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.setenv("PATH", "/nonexistent")
    with pytest.raises(SetupError) as raised:
        interpreter.find()
    assert str(raised.value).endswith(": run `make setup`"), raised.value
    assert str(tmp_path / "build" / "micropython" / "1.25.0+ds-1" / "micropython") in str(raised.value)

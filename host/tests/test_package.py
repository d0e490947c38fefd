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
        # (--ignore-installed: the project's environment, seen through the .pth line, has this
        # checkout's editable install, which pip would take for the wheel's and skip it)
        install = [*pip, "install", "-q", "--no-deps", "--no-index", "--ignore-installed", str(wheel)]
        subprocess.run(install, check=True, timeout=120)

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
        "mpy_fil/host/_data/firmware/apps/rover/main.py",
        "mpy_fil/host/_data/firmware/apps/rover/rig.toml",
        "mpy_fil/host/_data/firmware/apps/vacuum/mission.json",
        "mpy_fil/host/_data/firmware/boards/rpi_pico/board.py",
        "mpy_fil/host/_data/firmware/lib/hcsr04.py",  # (harness_lib)
        "mpy_fil/host/_data/examples/pico_bot/rig.toml",
        "mpy_fil/host/shim/machine.py",
        "mpy_fil/host/core/micropython/manifest.py",  # (the interpreter's build)
        "mpy_fil/host/shim/cmod/_hilfast/_hilfast.c",  # (its user C module)
        "mpy_fil/host/shim/cmod/_hilfast/micropython.mk",
        "mpy_fil/host/core/aptsources.py",  # (its deb-src line)
        "mpy_fil/sim_plant/catalogue/__init__.py",
        "mpy_fil/host/_data/docs/ci.md",  # (mpy-fil docs)
        "mpy_fil/host/_data/docs/rig-api.md",
    ):
        assert needed in names, f"expected {needed} in {scratch.wheel.name}"
    loose = sorted(n for n in names if not n.startswith(("mpy_fil/", "mpy_fil-")))
    assert not loose, f"expected every module under mpy_fil/ (host/, sim_plant/ are a user's), got {loose[:5]}"
    cli = zipfile.ZipFile(scratch.wheel).read("mpy_fil/host/cli.py").decode()
    assert "from mpy_fil.host.core import stop_signals" in cli and "\nfrom host." not in cli, "imports under mpy_fil"
    tests = sorted(n for n in names if "/tests/" in n)
    assert not tests, f"expected no tests in the wheel, found {tests[:5]}"
    with tarfile.open(scratch.sdist) as sdist:
        members = {m.name.split("/", 1)[-1] for m in sdist.getmembers()}
    assert {"setup.py", "pyproject.toml", "firmware/apps/rover/main.py", "examples/pico_bot/rig.toml"} <= members


def test_every_cli_command_works_from_the_installed_package(scratch, micropython):
    done = scratch.sh("mpy-fil --version")
    assert done.stdout.strip() == f"mpy-fil {VERSION}", done.stdout + done.stderr
    where = scratch.sh("python -c 'import mpy_fil.host; print(mpy_fil.host.__file__)'").stdout
    assert where.startswith(str(scratch.venv)), f"expected the installed package, imported {where}"
    generic = scratch.sh("python -c 'import host'")
    assert "No module named 'host'" in generic.stderr, "expected no top-level host package installed"

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

    docs = scratch.sh("mpy-fil docs && mpy-fil docs ci && mpy-fil docs readme && mpy-fil docs shim --path")
    assert docs.returncode == 0, docs.stderr
    assert "  rig-api          The Rig API" in docs.stdout, docs.stdout[:3000]
    assert (REPO / "docs" / "ci.md").read_text().rstrip() in docs.stdout, "the page, whole"
    assert "# mpy-fil: MicroPython robot firmware in the loop" in docs.stdout, "the README, from the metadata"
    assert docs.stdout.rstrip().endswith("/host/_data/docs/shim.md") and str(scratch.venv) in docs.stdout

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


def ci_workflow() -> str:
    return re.search(r"```yaml\n(.*?)```", CI_DOC.read_text(), re.S).group(1)


def ci_commands() -> list[str]:
    """The ``run:`` lines of docs/ci.md's workflow, in order."""
    return [m.group(1).strip() for m in re.finditer(r"^\s*- run: (.+)$", ci_workflow(), re.M)]


def ci_step(uses: str) -> dict[str, list[str]]:
    """The ``with:`` of the workflow's step that uses ``uses``: each key's lines (a ``|``
    block's lines, or the one value)."""
    step = re.search(rf"uses: {re.escape(uses)}\n\s+with:\n((?:\s{{8,}}.*\n)+)", ci_workflow())
    assert step, f"expected a step using {uses} with a with: block in docs/ci.md"
    found: dict[str, list[str]] = {}
    key = None
    for line in step.group(1).splitlines():
        m = re.match(r"\s+(\w+): ?(.*)$", line)
        if m and m.group(2) != "|":
            key = None
            found[m.group(1)] = [m.group(2).split("  #")[0].strip()]
        elif m:
            key = m.group(1)
            found[key] = []
        elif key:
            found[key].append(line.strip())
    return found


def test_the_ci_recipe_caches_the_interpreters_folder_alone_keyed_on_this_release():
    """Before: `.cache/mpy-fil/micropython`, 183 MB of source, apt lists and objects, keyed
    on the interpreter alone (its binary holds the shim's C code of a release)."""
    cache = ci_step("actions/cache@v4")
    assert cache["path"] == [f".cache/mpy-fil/micropython/{interpreter.DEBIAN_VERSION}"], cache
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("XDG_CACHE_HOME", "/ws/.cache")
        folder = interpreter.default_path(interpreter.build_root(checkout=False)).parent.parent
    assert folder == Path("/ws") / cache["path"][0], "expected the version's folder, where mpy-fil setup looks"
    assert VERSION in cache["key"][0] and interpreter.DEBIAN_VERSION in cache["key"][0], cache["key"]


def test_the_ci_recipe_runs_as_printed_and_uploads_every_rigs_folder_when_the_robot_is_not_at_the_root(
    scratch, micropython
):
    """Before: with the rig file in a folder of the repository, the uploaded paths held the
    report but no trace folder or plot, and JUnit named folders outside them."""
    commands = ci_commands()
    install = [c for c in commands if c.startswith("pip install")]
    assert install == [f"pip install mpy-fil=={VERSION}"], "expected the recipe to pin this release"
    ours = commands[commands.index(install[0]) + 1 :]
    assert ours[0] == "mpy-fil setup" and ours[1].startswith("pytest"), ours
    repo = scratch.root / "repo"  # the user's repository: pico_bot in a folder of its own
    shutil.copytree(scratch.robot, repo / "firmware" / "pico_bot", ignore=shutil.ignore_patterns("build"))
    cache = scratch.root / "ci-cache"  # the cache as actions/cache restores it: the cached folder alone
    cached = cache / ci_step("actions/cache@v4")["path"][0].removeprefix(".cache/")
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("XDG_CACHE_HOME", str(cache))
        looked_at = interpreter.default_path(interpreter.build_root(checkout=False))
    key = interpreter.build_key()  # (this release's build, beside any other's in the version's folder)
    assert cached / key / "micropython" == looked_at, "expected the interpreter in the cached folder (else it builds)"
    looked_at.parent.mkdir(parents=True)
    shutil.copy2(micropython, looked_at)
    for command in ours:
        done = scratch.sh(command, cwd=repo, timeout_s=600, XDG_CACHE_HOME=str(cache))
        assert done.returncode == 0, f"{command}: {done.stdout[-3000:]}{done.stderr[-2000:]}"
        if command == "mpy-fil setup":
            assert f"up to date: {looked_at}" in done.stdout, done.stdout
    assert re.search(r"\b4 passed\b", done.stdout), done.stdout[-2000:]
    inside_cache = sorted(p.relative_to(cached).as_posix() for p in cached.rglob("*"))
    assert inside_cache == [key, f"{key}/micropython"], f"expected nothing else in the cached folder: {inside_cache}"

    uploaded = [repo / p.rstrip("/") for p in ci_step("actions/upload-artifact@v4")["path"]]
    junit_file = repo / "build" / "junit.xml"
    assert junit_file in uploaded and (repo / "build" / "hil") in uploaded, uploaded
    junit = junit_file.read_text()
    assert 'tests="4"' in junit and 'failures="0"' in junit, junit[:500]
    assert (repo / "build" / "hil" / "report.html").is_file()
    inside = lambda path: any(path == u or path.is_relative_to(u) for u in uploaded)  # noqa: E731
    headers = sorted(repo.rglob("header.json"))
    assert len(headers) >= 4 and all(inside(h) for h in headers), [str(h.relative_to(repo)) for h in headers]
    plots = sorted(repo.rglob("trajectory.png"))
    assert plots and all(inside(p) for p in plots), [str(p.relative_to(repo)) for p in plots]
    folders = re.findall(r'<property name="rig\d+\.artefacts" value="([^"]+)"', junit)
    assert len(folders) >= 4, junit[:2000]
    for folder in folders:
        assert not Path(folder).is_absolute() and inside((junit_file.parent / folder).resolve()), folder
        assert (junit_file.parent / folder / "header.json").is_file(), folder


def test_setup_builds_into_the_per_user_cache_and_a_checkout_into_its_build(monkeypatch, tmp_path):
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    cache = interpreter.build_root(checkout=False)
    assert cache == tmp_path / "xdg" / "mpy-fil" / "micropython"
    key = interpreter.build_key()
    assert interpreter.default_path(cache) == cache / "1.25.0+ds-1" / key / "micropython", "versioned, keyed by build"
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


# -- a user's repository with parts of its own (docs/own-parts.md) ---------------------------

OWN_PARTS_DOC = REPO / "docs" / "own-parts.md"


def own_parts_files() -> dict[str, str]:
    """docs/own-parts.md's files: each code block whose info string names a file."""
    blocks = re.findall(r"^```\w+ ([\w./-]+)\n(.*?)^```", OWN_PARTS_DOC.read_text(), re.S | re.M)
    return dict(blocks)


def own_parts_commands() -> list[str]:
    """The page's ``sh`` block: the commands its reader runs, in order."""
    block = re.search(r"^```sh\n(.*?)^```", OWN_PARTS_DOC.read_text(), re.S | re.M)
    assert block, f"expected a ```sh block of commands in {OWN_PARTS_DOC}"
    return [line for line in block.group(1).splitlines() if line.strip()]


@pytest.fixture(scope="module")
def yard(scratch) -> Path:
    """The user's repository docs/own-parts.md writes, outside ours, file by file, with
    packages ``host`` and ``sim_plant`` of its own."""
    repo = scratch.root / "yardbot"
    files = own_parts_files()
    listed = re.search(r"^```text\n(.*?)^```", OWN_PARTS_DOC.read_text(), re.S | re.M).group(1).split()
    assert sorted(files) == sorted(listed), f"expected the page's blocks to be the files it lists: {sorted(files)}"
    for name, text in files.items():
        (repo / name).parent.mkdir(parents=True, exist_ok=True)
        (repo / name).write_text(text)
    (repo / "pyproject.toml").write_text('[project]\nname = "yardbot"\nversion = "0"\n')  # (its root: build/ there)
    for package in ("host", "sim_plant"):  # folders of common names of its own (before: the wheel's shadowed them)
        (repo / package).mkdir()
        (repo / package / "__init__.py").write_text(f'OWNER = "yardbot"  # the user\'s own {package}\n')
    (repo / "conftest.py").write_text(
        "import host\nimport sim_plant\n\nassert host.OWNER == sim_plant.OWNER == 'yardbot', 'the user\\'s own'\n"
    )
    return repo


def test_a_repository_with_its_own_chip_world_host_and_sim_plant_runs_as_docs_own_parts_md_says(
    scratch, yard, micropython
):
    """The page's repository, with ``host/`` and ``sim_plant/`` packages of its own beside
    (its conftest.py imports them): before, the wheel installed top-level ``host`` and
    ``sim_plant``, which a repository's folders of those names shadowed (its pytest could
    not load our plugin)."""
    said = {}
    for command in own_parts_commands():
        done = scratch.sh(command, cwd=yard, MICROPYTHON=micropython)
        assert done.returncode == 0, f"{command} in {yard}: {done.stdout[-3000:]}{done.stderr[-2000:]}"
        said[command.split()[1]] = done.stdout
    assert said["check"].startswith("rig.toml: ok") and "beacon beacon" in said["check"], said["check"]
    page = said["parts"]
    assert "## Part `beacon`" in page and "## World `yard`" in page, page[:2000]
    assert "| `address` | `42` | a whole number from 8 to 119 |" in page, "its options with their bounds"
    assert re.search(r"\b1 passed\b", said["-m"]), said["-m"][-2000:]

    out_of_bounds = (yard / "rig.toml").read_text().replace('bus = "i2c0"', 'bus = "i2c0"\naddress = 200')
    (yard / "bad.toml").write_text(out_of_bounds)
    refused = scratch.sh("mpy-fil check bad.toml", cwd=yard)
    assert refused.returncode != 0, refused.stdout
    assert "[[plant.parts]] #3 (beacon) address: expected a whole number from 8 to 119, got 200" in refused.stderr

    both = scratch.sh("python -c 'import host, mpy_fil.host; print(host.OWNER, mpy_fil.host.__file__)'", cwd=yard)
    assert both.stdout.startswith(f"yardbot {scratch.venv}"), both.stdout + both.stderr

    run = scratch.sh("mpy-fil run rig.toml --seconds 3", cwd=yard, MICROPYTHON=micropython)
    assert run.returncode == 0, run.stderr[-2000:]
    trace = yard / "build" / "runs" / "yardbot-default-seed0"
    assert "beacon_distance_m" in (trace / "truth.csv").read_text().splitlines()[0], "its truth in the trace"
    panels = scratch.sh(
        "python -c 'import sys; from mpy_fil.host.artefacts.folder import load_trace;"
        " from mpy_fil.host.report.views import signal_panels;"
        ' [print(p.title.split(":")[0], [l.label for l in p.lines]) for p in signal_panels(load_trace(sys.argv[1]))]\''
        f" {trace}",
        cwd=yard,
    )
    assert "Rangers ['beacon_distance_m (truth)']" in panels.stdout, panels.stdout + panels.stderr
    assert (trace / "plots" / "signals.png").is_file()

"""A user's own robot under pytest: which files are tests, where a run writes, and how to
run a failed test again (docs/rig-file.md, "Tests beside a rig").

- **The firmware's own files are not tests.** A ``.py`` file inside a rig's firmware folder
  (``[firmware] dir`` and ``lib`` of a ``rig*.toml`` in its folder or a folder above it) is
  not collected when it imports a module only MicroPython has (``machine``, ``micropython``,
  ``rp2``, ``esp32``, …) or names ``micropython`` (a ``@micropython.viper`` function), cannot be
  parsed by CPython, or matches one of that rig file's
  ``[tests] exclude`` patterns. The tests of the harness (``make_rig``) import none of them.
- **A rig file named on the command line is a test**: ``pytest path/to/rig.toml`` runs the
  rig for ``--hil-rig-seconds`` (30 s, as ``mpy-fil run``) and checks its budgets and its
  ``[report.judge]`` (what ``make hil RIG=…`` runs when no test is beside the rig).
- **Where a run writes**: a rig made from a rig file outside this repository writes under
  ``build/hil/`` at the root of the user's repository (``host.core.paths.output_root``:
  not in a firmware folder of its own); a test outside the repository, under its
  repository's ``build/hil/`` (beside itself when it is in none); ours
  under the repository's ``build/hil/``; ``--hil-out DIR`` puts them all under DIR.
- **make_rig("rig.toml")** resolves a relative rig path against the calling test file's
  folder, then the current directory; a missing file's error names both.
- **Rerun lines** name the interpreter that has the plugin and the options that put the
  session where it was (``--rootdir``, ``-c``, ``-o``), from the folder it ran in.
"""

import ast
import fnmatch
import os
import re
import shlex
import sys
from pathlib import Path

import pytest

from host.core.errors import ConfigError
from host.core.paths import REPO, output_root, project_root
from host.rig.config.tomlfile import read_toml

MICROPYTHON_ONLY = frozenset(
    "machine micropython rp2 esp esp32 network bluetooth ubluetooth pyb neopixel utime uasyncio "
    "uos usys ustruct umachine framebuf onewire ds18x20 dht espnow".split()
)
"""Modules a board has and CPython has not: a file importing one is firmware."""
RIG_SECONDS = 30.0
"""A rig file run as a test runs this long (virtual seconds), as ``mpy-fil run``."""
HOW_TO_WRITE_A_TEST = """\
A test of your own, beside the rig file (test_{name}.py):

    def test_{name}_keeps_its_budgets(make_rig):
        rig = make_rig("{rig}", seed=1)   # (relative to this test file's folder)
        rig.run_for(20)                    # virtual seconds
        # assert "..." in rig.console      # what your firmware prints (a firmware exception fails the test)
        for budget in rig.budgets.values():
            budget.check()
"""


def _in_repo(path: Path) -> bool:
    return Path(path).resolve().is_relative_to(REPO)


# -- the firmware's own files ----------------------------------------------------------------


def _rig_files_over(folder: Path, stop: Path):
    """Rig files in ``folder`` and each folder above it, up to ``stop`` (or the root)."""
    for here in (folder, *folder.parents):
        yield from sorted(here.glob("rig*.toml"))
        if here == stop:
            return


def _firmware_folders(rig_file: Path) -> tuple[list[Path], list[str]]:
    """A rig file's firmware folders and its ``[tests] exclude`` patterns (a rig file that
    cannot be read names none: its own test says why)."""
    try:
        data = read_toml(rig_file, "rig file", 1 << 20)
    except ConfigError:
        return [], []
    firmware = data.get("firmware") if isinstance(data.get("firmware"), dict) else {}
    names = [firmware.get("dir", ".")] + [x for x in firmware.get("lib", []) if isinstance(x, str)]
    folders = [(rig_file.parent / n).resolve() for n in names if isinstance(n, str)]
    tests = data.get("tests") if isinstance(data.get("tests"), dict) else {}
    return folders, [p for p in tests.get("exclude", []) if isinstance(p, str)]


def micropython_imports(path: Path) -> list[str] | None:
    """The MicroPython-only modules a file imports or names (``@micropython.native`` needs no
    import on a board); None: CPython cannot parse it."""
    try:
        tree = ast.parse(path.read_bytes(), str(path))
    except (SyntaxError, ValueError, OSError):
        return None
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found += [a.name.split(".")[0] for a in node.names]
        elif isinstance(node, ast.ImportFrom) and node.module and not node.level:
            found.append(node.module.split(".")[0])
        elif isinstance(node, ast.Name) and node.id == "micropython":  # @micropython.viper needs no import
            found.append(node.id)
    return sorted(set(found) & MICROPYTHON_ONLY)


def firmware_file(path: Path, stop: Path) -> str | None:
    """Why ``path`` is the firmware's own file and no test (None: it may be a test)."""
    path = Path(path).resolve()
    for rig_file in _rig_files_over(path.parent, stop.resolve()):
        folders, patterns = _firmware_folders(rig_file)
        rel = path.relative_to(rig_file.parent.resolve()).as_posix()
        if any(fnmatch.fnmatch(rel, p) or fnmatch.fnmatch(path.name, p) for p in patterns):
            return f"{rig_file}: [tests] exclude"
        if not any(path.is_relative_to(f) for f in folders):
            continue
        modules = micropython_imports(path)
        if modules is None:
            return f"in the firmware folder of {rig_file}, and not CPython"
        if modules:
            return f"in the firmware folder of {rig_file}, imports {', '.join(modules)}"
    return None


def ignore_firmware(collection_path: Path, config) -> bool | None:
    """pytest_ignore_collect: True for a firmware file (rig files looked for up to the
    session's root folder, or the file system's for a file outside it)."""
    if collection_path.suffix != ".py" or collection_path.name == "conftest.py":
        return None
    root = config.rootpath if collection_path.is_relative_to(config.rootpath) else Path(collection_path.anchor)
    return True if firmware_file(collection_path, root) else None


# -- a rig file as a test -----------------------------------------------------------------


def _named_on_command_line(config, path: Path) -> bool:
    where = config.invocation_params.dir
    return any((where / arg.split("::")[0]).resolve() == path.resolve() for arg in config.args)


class RigFile(pytest.File):
    """A rig file named on the command line: one test, the rig's own budgets and judge."""

    def collect(self):
        yield pytest.Function.from_parent(self, name="test_rig_budgets", callobj=_rig_budgets)


def collect_rig_file(file_path: Path, parent):
    if file_path.suffix == ".toml" and _named_on_command_line(parent.config, file_path):
        return RigFile.from_parent(parent, path=file_path)
    return None


def _rig_budgets(make_rig, request):
    """The rig for --hil-rig-seconds: every budget it declares holds, and its [report.judge]."""
    from host.campaign.judges import declared

    seconds = request.config.getoption("--hil-rig-seconds", None) or RIG_SECONDS
    rig = make_rig(str(request.node.path), seed=1)
    rig.run_for(seconds)
    problems = []
    for budget in rig.budgets.values():
        try:
            budget.check()
        except AssertionError as e:
            problems.append(str(e))
    ok, _figures, message = declared(rig, True, {"seconds": seconds})
    if not ok:
        problems.append(f"[report.judge]: {message}")
    if problems:  # (raised, not asserted: the same lines whether pytest rewrote this module or not)
        raise AssertionError(f"{request.node.path} for {seconds:g} s:\n" + "\n".join(f"  {p}" for p in problems))


def how_to_write_a_test(rig_file: Path) -> str:
    name = re.sub(r"\W+", "_", rig_file.parent.name).strip("_") or "mybot"
    return HOW_TO_WRITE_A_TEST.format(name=name, rig=rig_file.name)


# -- paths: the rig file a test names, where its rigs write ----------------------------------


def _looks_like_a_path(app) -> bool:
    """A rig file's (or its folder's) path, not an app's name nor an App a test built."""
    return isinstance(app, Path) or (isinstance(app, str) and (app.endswith(".toml") or "/" in app))


def app_key(app, base: Path) -> str:
    """One name for an app: our app's name, or its rig file's whole path (a folder: its
    rig.toml; relative: to ``base``)."""
    if not isinstance(app, (str, Path)):
        return repr(app)
    if not _looks_like_a_path(app) and not (base / app / "rig.toml").is_file():
        return str(app)
    path = base / app
    return str((path / "rig.toml" if path.is_dir() else path).resolve())


def resolve_rig(app, test_file: Path | None):
    """``make_rig``'s app: a relative rig path against the test file's folder, then the
    current directory. An app's name (``"rover"``) stays as it is."""
    if not isinstance(app, (str, Path)):
        return app  # (an App of the test's own)
    if not _looks_like_a_path(app) or Path(app).is_absolute():
        if not _looks_like_a_path(app) and test_file is not None and (test_file.parent / app / "rig.toml").is_file():
            return str(test_file.parent / app)
        return app
    tried = [test_file.parent] if test_file is not None else []
    tried.append(Path.cwd())
    for folder in tried:
        if (folder / app).exists():
            return str(folder / app)
    where = " and ".join(f"{f} ({what})" for f, what in zip(tried, ("the test file's folder", "the current directory")))
    if len(tried) == 1:
        where = f"{tried[0]} (the current directory)"
    raise ConfigError(f"make_rig: no rig file {str(app)!r}: tried it relative to {where}")


def artefacts_root(node, app) -> Path:
    """Where a test's rigs write: --hil-out, else build/hil/ beside a user's rig file (or
    test file), else the repository's build/hil/."""
    chosen = node.config.getoption("--hil-out", None)
    if chosen:
        base = Path(chosen)
    elif _looks_like_a_path(app) and not _in_repo(app):
        rig = Path(app)
        base = output_root(rig / "rig.toml" if rig.is_dir() else rig) / "hil"  # (never in its firmware folder)
    elif not _in_repo(node.path):
        base = (project_root(node.path.parent) or node.path.parent) / "build" / "hil"
    else:
        base = REPO / "build" / "hil"
    name = re.sub(r"[^A-Za-z0-9_.-]+", "_", node.nodeid.split("::", 1)[-1])
    return base.resolve() / node.path.stem / name


# -- the rerun line -------------------------------------------------------------------------


def _shown(path: Path, here: Path) -> str:
    return os.path.relpath(path, here) if Path(path).is_relative_to(here) else str(path)


def rerun_command(item, extra: str = "") -> str:
    """A command that runs this one test again as it ran: this interpreter (which has the
    plugin), from the folder the session ran in, with the options that placed it."""
    config = item.config
    here = config.invocation_params.dir
    args = [_shown(Path(sys.executable), here), "-m", "pytest"]
    if config.option.rootdir:
        args += ["--rootdir", str(config.rootpath)]
    if config.option.inifilename:
        args += ["-c", str(config.inipath)]
    for override in config.option.override_ini or []:
        args += ["-o", override]
    if config.getoption("--hil-out", None):
        args += ["--hil-out", str(Path(config.getoption("--hil-out")).resolve())]
    test = _shown(item.path, here) + item.nodeid[len(item.nodeid.split("::", 1)[0]) :]
    args.append(test)
    line = " ".join(shlex.quote(a) for a in args) + extra
    return f"cd {shlex.quote(str(here))} && {line}"

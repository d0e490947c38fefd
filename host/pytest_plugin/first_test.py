"""A session that collected no test, where a rig file or a firmware folder is: how to write
the first test.

The README's quick start (``pip install mpy-fil``, ``mpy-fil setup``, ``pytest``) ends at
pytest's "no tests ran" in a repository that has its firmware and a rig file but no test
yet. Then the session ends with the rig files found under the folders it was given (or a
firmware folder with no rig file: a ``main.py`` that imports a module only MicroPython
has), the test to write beside one, the command that runs a rig file's own budgets as a
test, and ``mpy-fil init`` for a firmware with no rig file. A session whose tests were all
deselected (``-k``, ``-m``) is not one of these.
"""

import os
from pathlib import Path

from host.pytest_plugin.userpath import how_to_write_a_test, micropython_imports

NO_TESTS_COLLECTED = 5
MAX_DEPTH = 4  # folders below the session's own
MAX_FOLDERS = 2000  # looked into at most
MAX_SHOWN = 3
SKIPPED = frozenset({"build", "dist", "node_modules", "__pycache__", "venv", "site-packages"})


def summary(terminalreporter, exitstatus, config) -> None:
    """``pytest_terminal_summary``: the hint, when nothing was collected."""
    if int(exitstatus) != NO_TESTS_COLLECTED or terminalreporter.stats.get("deselected"):
        return
    here = config.invocation_params.dir
    rigs, firmware = look(_starts(config))
    if not rigs and not firmware:
        return
    terminalreporter.section("firmware in the loop: no test yet")
    for line in lines(rigs, firmware, here):
        terminalreporter.write_line(line)


def lines(rigs: list[Path], firmware: list[tuple[Path, list[str]]], here: Path) -> list[str]:
    out = []
    if rigs:
        shown = ", ".join(_shown(r, here) for r in rigs[:MAX_SHOWN]) + _more(rigs)
        out.append(f"no test ran; a rig file is here with no test beside it: {shown}")
        out += how_to_write_a_test(rigs[0]).rstrip().splitlines()
        out.append(f"Meanwhile `pytest {_shown(rigs[0], here)}` runs the rig's own budgets as a test.")
    for folder, modules in firmware[:MAX_SHOWN]:
        where = _shown(folder, here)
        out.append(f"no test ran; a firmware folder is here with no rig file: {where} (main.py imports {modules[0]})")
        out.append(f"`mpy-fil init {where}` writes a commented rig file for it, with the pins its code uses.")
    out.append("The Rig API (run_for, expect, truth, budgets): `mpy-fil docs rig-api`; the set-up: `mpy-fil docs ci`.")
    return out


def look(starts: list[Path]) -> tuple[list[Path], list[tuple[Path, list[str]]]]:
    """Rig files (``rig*.toml``) under ``starts``, and firmware folders with none of their
    own or above them."""
    rigs, firmware, seen = [], [], 0
    for start in starts:
        for folder, names, files in os.walk(start):
            names[:] = sorted(n for n in names if not n.startswith(".") and n not in SKIPPED)
            depth = len(Path(folder).relative_to(start).parts)
            if depth >= MAX_DEPTH:
                names[:] = []
            seen += 1
            if seen > MAX_FOLDERS:
                break
            here = Path(folder)
            mine = sorted(here / f for f in files if f.startswith("rig") and f.endswith(".toml"))
            rigs += mine
            if "main.py" in files and not mine:
                modules = micropython_imports(here / "main.py")
                if modules:
                    firmware.append((here, modules))
    firmware = [(f, m) for f, m in firmware if not any(r.parent == f or r.parent in f.parents for r in rigs)]
    return rigs, firmware


def _starts(config) -> list[Path]:
    """The folders the session was given (its arguments, else where it ran)."""
    here = config.invocation_params.dir
    folders = []
    for arg in config.args or [str(here)]:
        path = (here / arg.split("::")[0]).resolve()
        if path.is_dir() and path not in folders:
            folders.append(path)
    return folders


def _shown(path: Path, here: Path) -> str:
    return os.path.relpath(path, here) if path.is_relative_to(here) else str(path)


def _more(items: list) -> str:
    return f" (and {len(items) - MAX_SHOWN} more)" if len(items) > MAX_SHOWN else ""

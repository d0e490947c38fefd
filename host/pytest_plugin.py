"""pytest plugin: rigs as fixtures, and the timing-budget table.

``make_rig(app="rover", seed=..., ...)`` starts a rig (interpreter + shim + firmware +
plant) whose artefacts go to ``build/hil/<test>/``; every rig a test made is stopped
when the test ends, pass or fail. ``rig`` is a started rover rig. With ``--hil-table``
the budget statistics of every rig are printed at the end of the session.
"""

import json
import os
import re
from pathlib import Path

import pytest

from host import interpreter
from host.boards import REPO
from host.budgets import format_table
from host.errors import SetupError
from host.runner import Rig

ARTEFACTS = REPO / "build" / "hil"
_rows: list[dict] = []


def pytest_addoption(parser):
    group = parser.getgroup("hil", "firmware in the loop")
    group.addoption("--hil-table", action="store_true", help="print the timing-budget table at the end")


def pytest_report_header(config):
    try:
        path = interpreter.find()
        return f"micropython: {interpreter.version(path)} ({path})"
    except SetupError as e:
        return f"micropython: not available ({e})"


def artefacts_for(node) -> "ARTEFACTS":
    name = re.sub(r"[^A-Za-z0-9_.-]+", "_", node.nodeid.split("::", 1)[-1])
    return ARTEFACTS / node.module.__name__.rsplit(".", 1)[-1] / name


@pytest.fixture
def make_rig(request):
    rigs: list[Rig] = []

    flashed = _flashed_firmware()

    def factory(app="rover", **kwargs) -> Rig:
        kwargs.setdefault("artefacts", artefacts_for(request.node) / f"rig{len(rigs)}")
        if flashed and app == flashed["app"] and not {"main_dir", "firmware_dir", "plant"} & set(kwargs):
            kwargs.setdefault("firmware_dir", flashed["dir"])
            kwargs.setdefault("board", flashed["board"])
        rig = Rig(app, **kwargs)
        rigs.append(rig)
        rig.start()
        return rig

    yield factory
    for rig in rigs:
        rig.stop()
        scenario = request.node.name
        for row in rig.budget_rows():
            if row["count"]:
                _rows.append({"scenario": scenario, **row})


def _flashed_firmware() -> dict | None:
    """HIL_FIRMWARE=<board folder>: run the scenarios of the app flashed there
    (``make hil FIRMWARE=build/vboard/<board>/fs``), from the flashed files."""
    folder = os.environ.get("HIL_FIRMWARE")
    if not folder:
        return None
    manifest = Path(folder).resolve().parent / "flashed.json"
    if not manifest.is_file():
        raise pytest.UsageError(f"HIL_FIRMWARE={folder}: no {manifest}; flash it first with make flash")
    info = json.loads(manifest.read_text())
    return {"dir": Path(folder).resolve(), "app": info["app"], "board": info["board"]}


@pytest.fixture
def rig(make_rig) -> Rig:
    return make_rig()


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    if config.getoption("--hil-table") and _rows:
        terminalreporter.section("timing budgets (us of virtual time unless marked wall)")
        terminalreporter.write_line(format_table(_rows))

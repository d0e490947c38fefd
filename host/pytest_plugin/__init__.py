"""pytest plugin: rigs as fixtures, and the timing-budget table.

``make_rig(app="rover", seed=..., ...)`` starts a rig (interpreter + shim + firmware +
plant) whose artefacts go to ``build/hil/<test>/`` (the project's, or beside a user's rig
file: :mod:`host.pytest_plugin.userpath`, which also keeps a firmware's own files out of
collection and makes a rig file named on the command line a test); every rig a test made is stopped
when the test ends, pass or fail. ``@pytest.mark.hil_budget(name, max_ms=...)`` or
``make_rig(..., budget_limits={name: {...}})`` sets a test's own budget limits
(:mod:`host.pytest_plugin.budget_marks`). ``rig`` is a started rover rig. With ``--hil-table``
the budget statistics of every rig are printed at the end of the session, after each
scenario's result line (what a test recorded with ``record_property("result", text)``);
with ``--hil-report PATH`` every rig records a trace folder and the session ends by writing
one HTML report (docs/traces.md). Without it, every rig records as it runs and a failed
test's rigs leave their whole trace folder and plots beside its console (``--hil-keep``:
``failed``, the default; ``none`` records nothing, as ``make test`` runs). A long mission
shows its progress on one line. SIGTERM or SIGHUP stops a session as Ctrl-C does, and
nothing it started outlives it (:mod:`host.pytest_plugin.stopping`). A failure the harness
raised leads its report with the message (:mod:`host.pytest_plugin.failure`); a session
that collects no test beside a rig file says how to write one
(:mod:`host.pytest_plugin.first_test`); JUnit's artefacts properties are relative to the
JUnit file (:func:`junit_path`).
"""

import dataclasses
import json
import os
from pathlib import Path

import pytest

from host.core import interpreter
from host.core.errors import SetupError
from host.core.paths import REPO
from host.link.transport import busy_poll_wanted, cores
from host.pytest_plugin import budget_marks, failure, first_test, hil_coverage, mpy_versions, stopping, userpath
from host.pytest_plugin.session_report import RIGS_ATTRIBUTE, SessionReport, is_worker, rig_record
from host.pytest_plugin.terminal_line import clear_progress_lines, mission_progress
from host.report.session import plot_one
from host.rig import Rig
from host.rig.config import verdicts
from host.rig.loop.spec import Recording, RigSpec

_rigs = pytest.StashKey[list]()  # the rigs a test made, for its failure report
_records = pytest.StashKey[list]()  # what the report needs of each, once stopped
_failed = pytest.StashKey[bool]()  # the test's setup or call failed: keep its rigs' traces
_busy_poll = pytest.StashKey[bool]()  # this process's rigs may spin on their link
_flashed = pytest.StashKey[dict | None]()  # HIL_FIRMWARE: the app and folder flashed
SPEC_KEYWORDS = {f.name for f in dataclasses.fields(RigSpec)} - {"app", "options"}
RECORDING_KEYWORDS = {f.name for f in dataclasses.fields(Recording)}


def pytest_addoption(parser):
    group = parser.getgroup("hil", "firmware in the loop")
    group.addoption(
        "--hil-table",
        action="store_true",
        help="at the end, a line per scenario with its worst budget (and the table of those that failed or missed)",
    )
    group.addoption(
        "--hil-table-full", action="store_true", help="--hil-table, with the table of every budget of every rig"
    )
    group.addoption(
        "--hil-report",
        metavar="PATH",
        type=Path,
        help="record every rig and write an HTML report of the session to PATH",
    )
    group.addoption(
        "--hil-record-long",
        action="store_true",
        help="with --hil-report (refused without): record the rigs of tests marked long too "
        "(a failed sweep's rerun line adds it)",
    )
    group.addoption(
        "--hil-keep",
        choices=("failed", "none"),
        default="failed",
        help="failed (default): every rig records, and a failed test's rigs write their trace folder and plots; "
        "none: record nothing (faster; only console.log is kept)",
    )
    group.addoption(
        "--hil-out",
        metavar="DIR",
        type=Path,
        help="the rigs' artefacts under DIR (default: build/hil/ beside a user's rig file, the project's build/hil/)",
    )
    group.addoption(
        "--hil-rig-seconds",
        metavar="S",
        type=float,
        help=f"a rig file named as a test runs this long (virtual seconds; default {userpath.RIG_SECONDS:g})",
    )
    hil_coverage.addoption(group)
    mpy_versions.addoption(group)  # --mpy-version A,B: every rig test once per MicroPython version


def pytest_generate_tests(metafunc):
    mpy_versions.generate(metafunc)


LONG_MARK_HELP = (
    "long: a slow scenario (a sweep over many seeds); with --hil-report its rigs record nothing "
    "(its result line and budgets are in the report; a failure's rerun line adds --hil-record-long)"
)


def pytest_configure(config):
    _options_that_need_another(config)
    mpy_versions.versions(config)  # --mpy-version: an unknown version is a usage error, before collection
    config.stash[_flashed] = _flashed_firmware()
    stopping.install(config, is_worker(config))  # SIGTERM, SIGHUP: stopped as by Ctrl-C, nothing left running
    if not is_worker(config):  # under pytest-xdist, the controller reports what workers ran
        config.pluginmanager.register(SessionReport(config), "hil-session-report")
        if config.stash[_flashed]:
            config.pluginmanager.register(FlashSummary(config.stash[_flashed]), "hil-from-flash")
    # a rig's host spins on its link while the firmware computes (docs/clock.md): with a
    # worker on every core that spin takes the core of another worker's rig
    config.stash[_busy_poll] = busy_poll_wanted() and not (is_worker(config) and _every_core_has_a_worker())
    config.addinivalue_line("markers", "hil: runs firmware in the loop (MicroPython + plant)")
    config.addinivalue_line("markers", LONG_MARK_HELP)
    config.addinivalue_line("markers", budget_marks.MARK_HELP)
    hil_coverage.configure(config)  # --hil-coverage (docs/coverage.md)


def _options_that_need_another(config) -> None:
    """An option that would do nothing without another is refused, saying which."""
    if config.getoption("--hil-record-long", False) and not config.getoption("--hil-report", None):
        raise pytest.UsageError(
            "--hil-record-long: expected with --hil-report PATH (without a report, the rigs of tests marked "
            "long record as every other rig does: --hil-keep)"
        )


def pytest_collection_modifyitems(items):
    """A test that makes a rig runs firmware in the loop: it is a hil test, marked or not
    (``make hil RIG=…`` selects a user's tests by that mark)."""
    for item in items:
        if {"make_rig", "rig"} & set(getattr(item, "fixturenames", ())) and not item.get_closest_marker("hil"):
            item.add_marker(pytest.mark.hil)


def pytest_ignore_collect(collection_path, config):
    """A firmware's own files are not tests (:mod:`host.pytest_plugin.userpath`)."""
    return userpath.ignore_firmware(collection_path, config)


def pytest_collect_file(file_path, parent):
    """A rig file named on the command line is a test of its budgets; a Wokwi scenario
    file (``*.test.yaml``) a test of its steps (``host/scenario``)."""
    if file_path.name.endswith(".test.yaml"):
        from host.scenario.pytest_items import collect_scenario

        return collect_scenario(file_path, parent)
    return userpath.collect_rig_file(file_path, parent)


def _every_core_has_a_worker() -> bool:
    return int(os.environ.get("PYTEST_XDIST_WORKER_COUNT", "1")) >= cores()


@pytest.hookimpl(wrapper=True)
def pytest_runtest_makereport(item, call):
    report = yield
    failure.lead_with_message(item, call, report)  # (the harness's message first, not its source)
    if report.failed and report.when in ("setup", "call"):
        item.stash[_failed] = True
    if report.failed and item.stash.get(_rigs, None):
        report.sections.append(("firmware in the loop", _evidence(item)))
    if report.when == "teardown" and item.stash.get(_records, None):
        setattr(report, RIGS_ATTRIBUTE, item.stash[_records])  # sent on by pytest-xdist
    return report


def _properties(node, key: str, rig, rows: list[dict]) -> None:
    """A rig's seed, artefacts and budgets as the test's properties (JUnit XML carries them;
    the artefacts folder relative to the JUnit file's, :func:`junit_path`)."""
    node.user_properties += [(f"{key}.seed", rig.seed), (f"{key}.artefacts", junit_path(node.config, rig.artefacts))]
    _budget_properties(node, key, rows)


def _budget_properties(node, key: str, rows: list[dict]) -> None:
    for row in rows:
        text = f"count={row['count']} max={row['max']} misses={row['misses']} limit={row['limit']}"
        node.user_properties.append((f"{key}.budget.{row['budget']}", text))
        node.user_properties.append((f"{key}.budget.{row['budget']}.verdict", f"{row['verdict']}: {row['why']}"))


def junit_path(config, path) -> str:
    """``path`` as a JUnit file's property gives it: relative to the folder of the JUnit
    file (``--junitxml``), so that it resolves from that file wherever the file and the
    folders beside it are copied (a CI artefact holding both: docs/ci.md); absolute
    without a JUnit file, or on another drive."""
    xml = config.getoption("xmlpath", None)
    if not path or not xml:
        return str(path or "")
    folder = (config.invocation_params.dir / Path(xml).expanduser()).resolve().parent
    try:
        return Path(os.path.relpath(Path(path).resolve(), folder)).as_posix()
    except ValueError:
        return str(path)


def _evidence(item) -> str:
    """Where a failed hil test's evidence is, and how to run it again."""
    lines = [
        f"{rig.app.name} rig{i}: seed {rig.seed}, virtual t={rig.t_us / 1e6:.6f} s, artefacts {rig.artefacts}"
        for i, rig in enumerate(item.stash[_rigs])
    ]
    extra = ""
    if _unrecorded_long(item):  # (as it ran: under a report, which a sweep's seeds may need)
        report = item.config.getoption("--hil-report").resolve().with_name("rerun.html")
        extra = f" --hil-report {report} --hil-record-long"
    lines.append(f"rerun: {userpath.rerun_command(item, extra)}")
    lines.append("(it records the whole trace)")
    return "\n".join(lines)


def _unrecorded_long(node) -> bool:
    """A test marked long under a report: its rigs record nothing (--hil-record-long: they do)."""
    config = node.config
    return (
        bool(config.getoption("--hil-report", None))
        and node.get_closest_marker("long") is not None
        and not config.getoption("--hil-record-long", False)
    )


def pytest_terminal_summary(terminalreporter, exitstatus, config):
    """No test collected beside a rig file or a firmware: how to write the first one."""
    first_test.summary(terminalreporter, exitstatus, config)


def pytest_report_header(config):
    matrix = mpy_versions.header(config)
    if matrix:
        return matrix
    try:
        path = interpreter.find()
        return f"micropython: {interpreter.version(path)} ({path})"
    except SetupError as e:
        return f"micropython: not available ({e})"


def artefacts_for(node, app: str | Path = "rover") -> Path:
    """build/hil/<test module>/<test>/: beside a user's rig file (or test file), under this
    repository's build/ for ours, or under --hil-out (:func:`userpath.artefacts_root`)."""
    return userpath.artefacts_root(node, app)


@pytest.fixture
def make_rig(request):
    rigs: list[Rig] = request.node.stash.setdefault(_rigs, [])
    report = bool(request.config.getoption("--hil-report", None))
    recording = report and not _unrecorded_long(request.node)
    keep_failed = not report and request.config.getoption("--hil-keep", "none") == "failed"

    flashed = request.config.stash.get(_flashed, None)
    marked = budget_marks.marked_limits(request.node)
    version = mpy_versions.selected_for(request.node)  # --mpy-version: this test's MicroPython
    selected = mpy_versions.Selected(version).__enter__()
    request.addfinalizer(lambda: selected.__exit__(None, None, None))  # (after the rigs stopped, even on errors)

    def factory(app="rover", budget_limits: dict | None = None, mission_s: float | None = None, **kwargs) -> Rig:
        app = userpath.resolve_rig(app, getattr(request.node, "path", None))
        kwargs.setdefault("artefacts", artefacts_for(request.node, app) / f"rig{len(rigs)}")
        if flashed:
            _from_flash(request.node, flashed, app, kwargs)
        if recording:
            kwargs.setdefault("record", True)
            kwargs.setdefault("trace", True)
        elif keep_failed:
            kwargs.setdefault("record", True)
        label = f"{request.node.name} rig{len(rigs)}"
        kwargs.setdefault("progress", mission_progress(request.config, label, mission_s))
        kwargs.setdefault("busy_poll", request.config.stash.get(_busy_poll, True))
        kwargs.setdefault("coverage", hil_coverage.data_file(request.config, request.node.nodeid, len(rigs)))
        rig = rig_from_keywords(app, **kwargs)
        budget_marks.apply(rig, marked, f"@pytest.mark.{budget_marks.MARK}")
        limits = {k: budget_marks.in_us(k, v, "make_rig budget_limits") for k, v in (budget_limits or {}).items()}
        budget_marks.apply(rig, limits, "make_rig budget_limits")
        rigs.append(rig)
        rig.start()
        return rig

    yield factory
    _finish_rigs(request, [(f"rig{i}", rig) for i, rig in enumerate(rigs)], recording, keep_failed)
    if rigs:  # (the version the rigs ran: this test's, else the rig file's, else the default)
        firmware = getattr(rigs[0], "firmware", None)
        mpy_versions.record(request.node, firmware.micropython() if hasattr(firmware, "micropython") else version)


def _finish_rigs(request, labelled: list, recording: bool, keep_failed: bool) -> None:
    """After a test: each of its rigs stopped, its budgets' verdicts stamped and its record
    kept for the report (plotted on a worker, or when kept because the test failed)."""
    records = request.node.stash.setdefault(_records, [])
    failed = request.node.stash.get(_failed, False)
    for label, rig in labelled:
        kept = keep_failed and failed and rig.recorder is not None
        if keep_failed and not failed:
            drop_recording(rig)
        rig.stop()
        rows = verdicts.rows_of(rig.budgets.values(), failed)  # (after the test: its check()s are known)
        verdicts.stamp(rig.artefacts if rig.recorder else None, rows)
        _properties(request.node, label, rig, rows)
        # a pytest-xdist worker plots its rigs as it goes; one session plots them all at its end
        plot = (recording and is_worker(request.config)) or kept
        plots = plot_one(rig.artefacts) if plot and rig.recorder else ([], "")
        records.append(rig_record(label, rig, rows, plots))


@pytest.fixture
def make_boards(request):
    """A rig file with several boards (docs/multi-board.md) as a started
    :class:`~host.rig.loop.boardset.BoardSet`: ``make_boards("rig.toml", seed=1)`` (a path
    relative to the test file's folder, then the current directory), each board's folder
    under the test's artefacts (``build/hil/<test module>/<test>/boards<n>/<board>/``);
    stopped after the test."""
    from host.rig.config.boardfile import load_boards
    from host.rig.loop.boardset import BoardSet

    sets = []
    report = bool(request.config.getoption("--hil-report", None))
    recording = report and not _unrecorded_long(request.node)
    keep_failed = not report and request.config.getoption("--hil-keep", "none") == "failed"
    marked = budget_marks.marked_limits(request.node)

    def factory(rig_file, seed: int = 0, budget_limits: dict | None = None, **kwargs):
        path = userpath.resolve_rig(str(rig_file), getattr(request.node, "path", None))
        kwargs.setdefault("artefacts", artefacts_for(request.node, path) / f"boards{len(sets)}")
        if recording or keep_failed:  # (as make_rig's: the report's lanes, a failed test's whole traces)
            kwargs.setdefault("record", True)
            kwargs.setdefault("trace", True)
        n, nodeid = len(sets), request.node.nodeid
        if hil_coverage.data_file(request.config, nodeid, n) is not None:  # (--hil-coverage: each board's own file)
            kwargs.setdefault("coverage", lambda board: hil_coverage.data_file(request.config, f"{nodeid}::{board}", n))
        boards = BoardSet(load_boards(path), seed=seed, **kwargs)
        budget_marks.apply_to_boards(boards, marked, f"@pytest.mark.{budget_marks.MARK}")
        limits = {k: budget_marks.in_us(k, v, "make_boards budget_limits") for k, v in (budget_limits or {}).items()}
        budget_marks.apply_to_boards(boards, limits, "make_boards budget_limits")
        sets.append(boards)
        return boards.start()

    yield factory
    for n, boards in enumerate(sets):  # (each board a rig of the report, named boards<n>.<board>)
        labelled = [(f"boards{n}.{name}", rig) for name, rig in boards.rigs.items() if isinstance(rig, Rig)]
        try:
            _finish_rigs(request, labelled, recording, keep_failed)
        finally:
            boards.stop()
        failed = request.node.stash.get(_failed, False)  # (the budgets across boards: boards<n>.budget.<name>)
        _budget_properties(request.node, f"boards{n}", verdicts.rows_of(boards.budgets.values(), failed))


def rig_from_keywords(app, plant_options: dict | None = None, **kwargs) -> Rig:
    """``make_rig``'s keywords, sorted: the spec's fields (``plant_options`` its options),
    the recording's, and a plant, budgets or target of the test's own."""
    unknown = sorted(set(kwargs) - SPEC_KEYWORDS - RECORDING_KEYWORDS - {"plant", "budgets", "target"})
    if unknown:
        raise TypeError(f"make_rig: unexpected keywords {', '.join(unknown)}")
    spec = RigSpec(app, options=plant_options or {}, **{k: v for k, v in kwargs.items() if k in SPEC_KEYWORDS})
    recording = Recording(**{k: v for k, v in kwargs.items() if k in RECORDING_KEYWORDS})
    return Rig(spec, recording, **{k: v for k, v in kwargs.items() if k in ("plant", "budgets", "target")})


def drop_recording(rig) -> None:
    """A passed test's rig: forget what it recorded (stop() then writes no trace folder).
    A rig the test stopped itself has written its folder already."""
    if rig.recorder is not None and getattr(rig, "_started", False):
        rig.recorder.close()
        rig.recorder = None


@pytest.hookimpl(tryfirst=True)
def pytest_runtest_logreport(report):
    """Clear a mission's progress line before the terminal writes the test's result."""
    clear_progress_lines()


def _flashed_firmware() -> dict | None:
    """HIL_FIRMWARE=<board folder>: run the scenarios of the app flashed there
    (``make hil FIRMWARE=build/vboard/<board>/fs``), from the flashed files; checked once,
    before any test runs."""
    folder = os.environ.get("HIL_FIRMWARE")
    if not folder:
        return None
    manifest = Path(folder).resolve().parent / "flashed.json"
    if not Path(folder).is_dir():
        raise pytest.UsageError(f"FIRMWARE={folder}: no such folder (make flash writes build/vboard/<board>/fs)")
    if not manifest.is_file():
        raise pytest.UsageError(f"FIRMWARE={folder}: no {manifest}; flash it first with make flash")
    try:
        info = json.loads(manifest.read_text())
        return {"dir": Path(folder).resolve(), "app": info["app"], "board": info["board"]}
    except (ValueError, KeyError, TypeError, RecursionError) as e:
        raise pytest.UsageError(f"FIRMWARE={folder}: {manifest} is damaged ({e}); flash again") from None


def _from_flash(node, flashed: dict, app, kwargs: dict) -> None:
    """Under FIRMWARE=: the flashed app's rigs run from the flashed files; a test that makes
    any other rig (another app, its own firmware folder or plant) is skipped, saying so."""
    same = userpath.app_key(app, Path.cwd()) == userpath.app_key(flashed["app"], REPO)
    if not same or {"main_dir", "firmware_dir", "plant"} & set(kwargs):
        what = "its own firmware folder or plant" if same else f"app {app}"
        pytest.skip(f"FIRMWARE={flashed['dir']} holds {flashed['app']}; this test runs {what}, not the flashed files")
    kwargs.setdefault("firmware_dir", flashed["dir"])
    kwargs.setdefault("board", flashed["board"])
    if ("from flash", str(flashed["dir"])) not in node.user_properties:
        node.user_properties.append(("from flash", str(flashed["dir"])))


class FlashSummary:
    """Under FIRMWARE=: at the end, the tests that ran the flashed files (the others were
    skipped, each saying why)."""

    def __init__(self, flashed: dict):
        self.flashed = flashed
        self.ran: list[tuple[str, str]] = []

    def pytest_runtest_logreport(self, report):
        if report.when == "call" and any(key == "from flash" for key, _ in report.user_properties):
            self.ran.append((report.nodeid, report.outcome))

    def pytest_terminal_summary(self, terminalreporter):
        where = f"{self.flashed['app']} flashed in {self.flashed['dir']}"
        terminalreporter.write_sep("-", f"ran from flash: {len(self.ran)} tests ({where})")
        for nodeid, outcome in sorted(self.ran):
            terminalreporter.write_line(f"{outcome.upper():7} {nodeid}")


@pytest.fixture
def hil_mpy_version(request) -> str | None:
    """The MicroPython version a ``--mpy-version`` test runs (None without the option)."""
    return getattr(request, "param", None)


@pytest.fixture
def rig(make_rig) -> Rig:
    return make_rig()

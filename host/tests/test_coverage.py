"""Firmware coverage (docs/coverage.md): the settrace variant, the tracer in the shim, the
coverage.py data per run and merged; the link trace the same with it on."""

from pathlib import Path

import coverage
import pytest
from coverage import CoverageData

from host.core import interpreter
from host.coverage import collector, session

RIG = """\
name = "covbot"
[firmware]
entry = "main.py"
[board.pins]
BTN = 4
[plant]
body = "bench"
[[plant.parts]]
kind = "button"
name = "btn"
active_low = false
presses = {presses}
[wiring]
BTN = "btn.out"
"""
MAIN = """\
from machine import Pin
from time import sleep_ms

import reaction

btn = Pin(4, Pin.IN, Pin.PULL_DOWN)
while True:
    if btn.value():
        reaction.high()
    else:
        reaction.low()
    sleep_ms(50)
"""
REACTION = """\
count = 0


def high():
    global count
    count += 1
    print("high", count)


def low():
    pass
"""
IF_LINE, HIGH_LINE, LOW_LINE = 8, 9, 11


def covbot(folder: Path, presses: str) -> Path:
    folder.mkdir()
    (folder / "rig.toml").write_text(RIG.format(presses=presses))
    (folder / "main.py").write_text(MAIN)
    (folder / "reaction.py").write_text(REACTION)
    return folder / "rig.toml"


def measured(make_rig, tmp_path, name: str, presses: str, **kw):
    rig_file = covbot(tmp_path / name, presses)
    data_file = tmp_path / "cov" / f".coverage.{name}"
    rig = make_rig(str(rig_file), coverage=data_file, **kw)
    rig.run_for(1.0)
    rig.stop()
    data = CoverageData(basename=str(data_file))
    data.read()
    return rig, data, rig_file.parent


@pytest.mark.hil
def test_a_branch_taken_only_when_the_sensor_reads_high_is_covered_only_then(make_rig, tmp_path, settrace):
    _, pressed, folder = measured(make_rig, tmp_path, "pressed", "[[0.5, 0.7]]")
    _, idle, idle_folder = measured(make_rig, tmp_path, "idle", "[]")
    main, reaction = str(folder / "main.py"), str(folder / "reaction.py")
    assert pressed.has_arcs() and set(pressed.measured_files()) >= {main, reaction}
    assert {IF_LINE, HIGH_LINE, LOW_LINE} <= set(pressed.lines(main))
    assert (IF_LINE, HIGH_LINE) in pressed.arcs(main) and (IF_LINE, LOW_LINE) in pressed.arcs(main)
    assert {6, 7} <= set(pressed.lines(str(folder / "reaction.py"))), "high()'s body, in the imported module"
    idle_main = str(idle_folder / "main.py")
    assert HIGH_LINE not in idle.lines(idle_main) and LOW_LINE in idle.lines(idle_main)
    assert (IF_LINE, HIGH_LINE) not in idle.arcs(idle_main)
    assert not idle.lines(str(idle_folder / "reaction.py")) or 6 not in idle.lines(str(idle_folder / "reaction.py"))
    assert pressed.measured_contexts() == {"covbot seed 0"} or len(pressed.measured_contexts()) == 1
    # coverage.py reads it with the firmware's source: the branch at line 8 partial when idle
    cov = coverage.Coverage(data_file=str(tmp_path / "cov" / ".coverage.idle"), branch=True, config_file=False)
    cov.load()
    analysis = cov._analyze(idle_main)
    assert HIGH_LINE in analysis.missing and IF_LINE in analysis.missing_branch_arcs()


@pytest.mark.hil
def test_the_link_trace_is_the_same_with_coverage_on(make_rig, tmp_path, settrace):
    rig_file = covbot(tmp_path / "bot", "[[0.2, 0.25], [0.6, 0.9]]")
    traces, consoles = [], []
    for n, data in enumerate((None, tmp_path / ".coverage.on")):
        rig = make_rig(str(rig_file), coverage=data, trace=True, artefacts=tmp_path / f"run{n}")
        rig.run_for(1.0)
        rig.stop()
        traces.append((tmp_path / f"run{n}" / "trace.jsonl").read_bytes())
        consoles.append((tmp_path / f"run{n}" / "console.log").read_bytes())
    assert traces[0] == traces[1] and consoles[0] == consoles[1]
    assert b"high 7" in consoles[1] and (tmp_path / ".coverage.on").is_file()


@pytest.mark.hil
def test_a_session_merges_its_runs_with_each_scenario_as_context(make_rig, tmp_path, settrace):
    measured(make_rig, tmp_path, "pressed", "[[0.5, 0.7]]")
    measured(make_rig, tmp_path, "idle", "[]")
    merged = session.merge(tmp_path / "cov")
    data = CoverageData(basename=str(merged))
    data.read()
    assert len(data.measured_files()) == 4, "two firmware folders of two files each"
    total = session.report(merged, tmp_path / "cov" / "html")
    assert 50 < total < 100 and (tmp_path / "cov" / "html" / "index.html").is_file()


def test_the_tracers_blocks_of_every_boot_are_merged_and_mapped_to_the_sources(tmp_path):
    text = "F main.py\nA -1,3 3,4 4,-1\nF /_hil/machine.py\nA 1,2\nF main.py\nA -1,3 3,5\nF /lib/motor.py\nA -2,3\n"
    arcs = collector.parse(text)
    assert arcs["main.py"] == {(-1, 3), (3, 4), (4, -1), (3, 5)}
    known = {"main.py": tmp_path / "main.py", "lib/motor.py": tmp_path / "lib" / "motor.py"}
    assert collector.source_of("main.py", known) == tmp_path / "main.py"
    assert collector.source_of("/lib/motor.py", known) == tmp_path / "lib" / "motor.py"
    assert collector.source_of("/_hil/machine.py", known) is None


def test_the_settrace_variant_is_the_standard_build_plus_line_tracing():
    tuned = interpreter.TUNED_OPTIONS.get(interpreter.DEFAULT_VERSION, ())
    assert interpreter.make_options("standard") == (*interpreter.MAKE_OPTIONS, *tuned)
    assert interpreter.MAKE_OPTIONS == (
        "VARIANT=standard",
        "MICROPY_PY_SSL=0",
        "MICROPY_PY_BTREE=0",
        "MICROPY_PY_FFI=0",
        "USER_C_MODULES=host/shim/cmod",
    ), "the standard build's command is unchanged"
    assert interpreter._absolute("USER_C_MODULES=host/shim/cmod").endswith("/host/shim/cmod/".rstrip("/"))
    assert (interpreter.PROJECT_ROOT / "host" / "shim" / "cmod").is_dir()
    traced = interpreter.make_options("settrace")
    assert traced[: len(interpreter.MAKE_OPTIONS) + len(tuned)] == (*interpreter.MAKE_OPTIONS, *tuned)
    assert "CFLAGS_EXTRA=-DMICROPY_PY_SYS_SETTRACE=1" in traced and "BUILD=build-settrace" in traced
    assert interpreter.variant_path("settrace").name == "micropython-settrace"
    assert interpreter.variant_path("standard") == interpreter.default_path()


def test_a_missing_variant_names_the_command_that_builds_it(monkeypatch, tmp_path):
    from host.core.errors import SetupError

    monkeypatch.setenv("MICROPYTHON_SETTRACE", str(tmp_path / "nope"))
    with pytest.raises(SetupError, match="MICROPYTHON_SETTRACE=.*nope is not an executable file"):
        interpreter.find_variant("settrace")
    with pytest.raises(SetupError, match="no interpreter variant 'fast'"):
        interpreter.variant_path("fast")


def test_the_hil_report_links_the_merged_coverage(tmp_path):
    from host.report.html import write_report

    html = tmp_path / "coverage" / "html" / "index.html"
    summary = {"total": 61.6, "html": html, "data": tmp_path / "coverage" / ".coverage"}
    text = write_report(tmp_path / "report.html", [], coverage=summary).read_text()
    assert '<a href="coverage/html/index.html">62% of lines and branches</a>' in text
    none = write_report(tmp_path / "r2.html", [], coverage={"error": "no rig ran"}).read_text()
    assert "firmware coverage: none (no rig ran)" in none

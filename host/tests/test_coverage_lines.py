"""Firmware coverage counts only firmware (not the user's tests beside it), marks lines as
MicroPython runs them (a `while True:` it has no bytecode for is run when the firmware goes
through it, as MicroPython itself says, never by running the file), and gives each line the
test that ran it as its context."""

from types import SimpleNamespace

import coverage
import pytest
from coverage import CoverageData

from host.coverage import collector, lines
from host.pytest_plugin import hil_coverage
from host.tests.test_coverage import IF_LINE, covbot

WHILE_LINE = 7  # main.py's `while True:` (host/tests/test_coverage.py)
USER_TEST = "def test_the_bot(make_rig):\n    rig = make_rig('rig.toml')\n    rig.run_for(1)\n"


def test_an_arc_over_a_line_micropython_has_no_code_for_is_the_parsers_path_through_it():
    possible = {(-1, 1), (1, 6), (6, 7), (7, 8), (8, 9), (9, 12), (12, 7)}
    recorded = {(-1, 1), (1, 6), (6, 8), (8, 9), (9, 12), (12, 8)}
    without_7 = frozenset({1, 6, 8, 9, 12})
    assert lines.bridged(recorded, possible, without_7) == possible
    with_7 = without_7 | {7}
    assert lines.bridged(recorded, possible, with_7) == recorded, "a line with code that did not run stays missed"


def test_micropython_says_which_lines_have_code_without_running_the_file(tmp_path, settrace):
    marker = tmp_path / "ran"
    source = tmp_path / "main.py"
    source.write_text(
        f"open({str(marker)!r}, 'w').write('x')\n"
        "def f():\n"
        "    n = 0\n"
        "    while True:\n"
        "        n += 1\n"
        "        if n > 3:\n"
        "            break\n"
        "    return n\n"
        "while True:\n"
        "    pass\n"
    )
    found = lines.micropython_lines(source, settrace)
    assert found is not None and not marker.exists(), "the file is compiled, never run"
    assert {1, 2, 3, 5, 6, 7, 8} <= found and 4 not in found and 9 not in found, sorted(found)
    (tmp_path / "bad.py").write_text("def (:\n")
    assert lines.micropython_lines(tmp_path / "bad.py", settrace) is None


@pytest.mark.hil
def test_a_run_counts_only_firmware_marks_while_true_run_and_carries_the_test_as_context(make_rig, tmp_path, settrace):
    rig_file = covbot(tmp_path / "bot", "[[0.5, 0.7]]")
    (tmp_path / "bot" / "test_bot.py").write_text(USER_TEST)
    (tmp_path / "bot" / "conftest.py").write_text("import pytest\n")
    data_file = tmp_path / "cov" / ".coverage.one"
    node = "tests/test_bot.py::test_the_bot"
    collector.name_context(data_file, node)
    rig = make_rig(str(rig_file), coverage=data_file)
    rig.run_for(1.0)
    rig.stop()
    data = CoverageData(basename=str(data_file))
    data.read()
    main = str(tmp_path / "bot" / "main.py")
    assert set(data.measured_files()) == {main, str(tmp_path / "bot" / "reaction.py")}, "no test file is firmware"
    assert data.measured_contexts() == {node}
    assert WHILE_LINE in data.lines(main) and IF_LINE in data.lines(main)
    cov = coverage.Coverage(data_file=str(data_file), branch=True, config_file=False)
    cov.load()
    analysis = cov._analyze(main)
    assert WHILE_LINE not in analysis.missing and not analysis.missing_branch_arcs(), analysis.missing


def test_the_plugin_names_each_data_file_with_its_tests_node_id(tmp_path):
    plugin = SimpleNamespace(folder=tmp_path)
    config = SimpleNamespace(pluginmanager=SimpleNamespace(get_plugin=lambda name: plugin))
    node = "hil_tests/test_rover.py::test_it_stops[seed 3]"
    path = hil_coverage.data_file(config, node, 0)
    assert collector.context_of(path, "the run's label") == node


@pytest.mark.parametrize(
    ("name", "test"),
    [("test_bot.py", True), ("bot_test.py", True), ("conftest.py", True), ("main.py", False), ("testing.py", False)],
)
def test_a_file_pytest_collects_is_not_firmware(name, test):
    assert collector.is_test_file(name) is test

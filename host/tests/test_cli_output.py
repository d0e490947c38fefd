"""What `mpy-fil run` and `mpy-fil check` tell: the firmware's console and every file a run
wrote (the moving picture too); a rig file that wires no pin said so, not just "ok"."""

import re
import subprocess
import sys

import pytest

from host.core.paths import REPO

pytestmark = pytest.mark.hil


def mpy_fil(*args: str, cwd=REPO) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "host.cli", *args], cwd=cwd, capture_output=True, text=True, timeout=240
    )


def test_run_shows_the_console_and_lists_the_files_it_wrote_with_the_gif(tmp_path):
    out = tmp_path / "run"
    done = mpy_fil("run", "--app", "rover", "--seconds", "20", "--out", str(out))
    assert done.returncode == 0, done.stderr
    assert re.search(rf"^console \(the last \d+ lines; all in {re.escape(str(out))}/console.log\):$", done.stdout, re.M)
    assert "  | rover on esp32-devkitc control every 50 ms" in done.stdout
    listed = re.findall(r"^  (\S+)  [\d.]+ k?M?B$", done.stdout, re.M)
    written = sorted(str(p.relative_to(out)) for p in out.rglob("*") if p.is_file())
    assert listed == written, f"expected every file listed: {written}\n{done.stdout}"
    assert "plots/trajectory.gif" in listed and "trace.vcd" in listed, listed


def test_check_says_when_no_pin_is_wired(tmp_path):
    rig = (REPO / "examples" / "pico_bot" / "rig.toml").read_text()
    (tmp_path / "main.py").write_text((REPO / "examples" / "pico_bot" / "main.py").read_text())
    unwired = re.sub(r"^\[wiring\]\n(?:(?!\[).*\n)*", "[wiring]\n\n", rig, flags=re.M)  # (an empty table)
    unwired = re.sub(r"^\[budgets\.loop\]\n(?:(?!\[).*\n)*", "", unwired, flags=re.M)  # (it needs a probe pin)
    assert "[wiring]\n\n" in unwired and 'PWMA = "motor_l.pwm"' not in unwired, unwired
    (tmp_path / "rig.toml").write_text(unwired)
    done = mpy_fil("check", "rig.toml", cwd=tmp_path)
    first = done.stdout.splitlines()[0]
    assert first == "rig.toml: loads, but 0 pins are wired: the firmware reads nothing from the plant", done.stdout
    assert ": ok" not in done.stdout and "[wiring]" in done.stdout
    wired = mpy_fil("check", str(REPO / "examples" / "pico_bot" / "rig.toml"))
    assert wired.stdout.splitlines()[0].endswith("rig.toml: ok"), wired.stdout


def test_check_of_a_rig_whose_parts_are_all_on_buses_is_ok_and_names_them(tmp_path):
    """Chips on a bus or a sensor's line need no [wiring]: a Wokwi project with only a DHT22
    is not 'the firmware reads nothing from the plant'."""
    import json

    diagram = {
        "version": 1,
        "parts": [
            {"type": "board-esp32-devkit-c-v4", "id": "esp", "attrs": {}},
            {"type": "wokwi-dht22", "id": "dht1", "attrs": {"temperature": "21.5"}},
        ],
        "connections": [["dht1:SDA", "esp:15", "green", []], ["dht1:GND", "esp:GND.1", "black", []]],
    }
    (tmp_path / "diagram.json").write_text(json.dumps(diagram))
    (tmp_path / "main.py").write_text("import dht\nfrom machine import Pin\nd = dht.DHT22(Pin(15))\n")
    done = mpy_fil("check", str(tmp_path))
    first = done.stdout.splitlines()[0]
    assert first.endswith("ok (0 pins wired; its parts are on dht:15)"), done.stdout + done.stderr


def test_check_of_a_rig_with_several_boards_checks_each_board_over_the_one_plant():
    done = mpy_fil("check", str(REPO / "examples" / "two_board_rover"))
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert lines[0].endswith("two_board_rover/rig.toml: 2 boards on one plant: motor, nav"), done.stdout
    assert "[[boards]] motor: ok" in lines and "[[boards]] nav: ok" in lines, done.stdout
    assert "wired to no pin" not in done.stdout, f"expected every signal wired to a board:\n{done.stdout}"


def test_run_of_a_rig_with_several_boards_writes_a_trace_folder_per_board_and_shows_each_console(tmp_path):
    out = tmp_path / "run"
    rig = str(REPO / "examples" / "two_board_rover")
    done = mpy_fil("run", rig, "--seconds", "1", "--no-plots", "--out", str(out))
    assert done.returncode == 0, done.stderr
    assert "board motor:\n" in done.stdout and "board nav:\n" in done.stdout, done.stdout
    assert f"all in {out}/nav/console.log" in done.stdout and "  | nav: go" in done.stdout, done.stdout
    for board in ("motor", "nav"):
        assert (out / board / "trace.jsonl").is_file() and (out / board / "truth.csv").is_file(), sorted(out.rglob("*"))
    refused = mpy_fil("run", rig, "--board", "x")
    assert refused.returncode == 2 and "argument --board: not for a rig file with several boards" in refused.stderr
    replayed = mpy_fil("replay", str(out), "--trust-folder")  # (each board from its own folder's recording)
    assert replayed.returncode == 0, replayed.stdout + replayed.stderr
    for board in ("motor", "nav"):
        said = re.search(rf"^board {board}:\n(?:.*\n)*?same outputs: (\d+) firmware outputs", replayed.stdout, re.M)
        assert said and int(said[1]) > 0, f"expected board {board} replayed to the same outputs:\n{replayed.stdout}"
        assert (out / "replay" / board / "trace.jsonl").is_file(), sorted((out / "replay").rglob("*"))
    other = mpy_fil("replay", str(out), "--firmware", str(rig))
    assert other.returncode == 2 and "a set's run folder replays each board's own firmware" in other.stderr
    unknown = mpy_fil("run", rig, "--world", "x")  # (a set's worlds are its rig file's, as a one-board rig's)
    assert unknown.returncode == 2 and "argument --world: unknown world 'x' for two_board_rover" in unknown.stderr


def test_run_of_a_rig_with_several_boards_with_coverage_measures_each_board_into_its_own_folder(tmp_path, settrace):
    out = tmp_path / "run"
    rig = str(REPO / "examples" / "two_board_rover")
    done = mpy_fil("run", rig, "--seconds", "0.5", "--no-plots", "--coverage", "--out", str(out))
    assert done.returncode == 0, done.stderr
    for board, entry in (("motor", "motor_rp2040"), ("nav", "nav_esp32")):
        html = out / board / "coverage" / "html" / "index.html"
        line = rf"^board {board}'s firmware coverage: (\d+)% of lines and branches: (\S+) "
        said = re.search(line, done.stdout, re.M)
        assert said and said[2] == str(html) and int(said[1]) > 0, f"expected {board}'s coverage line:\n{done.stdout}"
        assert html.is_file() and entry in html.read_text(), f"expected {board}'s firmware in {html}"
        other = "nav_esp32" if board == "motor" else "motor_rp2040"
        assert other not in html.read_text(), f"expected only board {board}'s own firmware in {html}"

"""Several boards in one lockstep (docs/multi-board.md): two boards of
host/tests/firmware/two_boards/ chatter over a UART between them and a GPIO line, each at
pseudo-random instants of its own; one virtual clock, each board its own interpreter."""

import json
import re
from pathlib import Path

import pytest

from host.core.errors import ConfigError, FirmwareError, FirmwareExited, FirmwareHung
from host.rig.config.boardfile import boards_from_data, load_boards
from host.rig.config.rigfile import load_rig
from host.rig.loop.boardset import BoardSet
from host.tests.conftest import run_cli
from host.tests.vcd_reader import gtkwave_round_trip, read_vcd

RIG = Path(__file__).parent / "firmware" / "two_boards" / "rig.toml"
TICKS0 = 2**30 - 10_000_000  # ticks_us at t=0 (docs/clock.md: 10 s before the wrap)
BYTE_US = 10 * 1e6 / 115_200  # a byte's 10 bits at the link's baud rate

pytestmark = pytest.mark.hil


def _records(folder: Path, board: str) -> list[dict]:
    return [json.loads(line) for line in (folder / board / "trace.jsonl").read_text().splitlines()]


def _run(folder: Path, seed: int = 1, seconds: float = 0.3) -> dict:
    with BoardSet(load_boards(RIG), seed=seed, trace=True, artefacts=folder) as boards:
        boards.run_for(seconds)
        assert boards.t_us == round(seconds * 1e6), f"expected the run to end at {seconds} s, got {boards.t_us} us"
        return {name: rig.trace_digest for name, rig in boards.rigs.items()} | {
            f"{name}.console": rig.console for name, rig in boards.rigs.items()
        }


def test_the_same_seed_gives_byte_identical_traces_for_every_board(tmp_path):
    first = _run(tmp_path / "a")
    second = _run(tmp_path / "b")
    for board in ("left", "right"):
        assert first[board] == second[board], (
            f"board {board}: expected the same link trace twice, got two digests "
            f"(traces in {tmp_path / 'a' / board} and {tmp_path / 'b' / board})"
        )
        assert first[f"{board}.console"] == second[f"{board}.console"], f"board {board}: consoles differ"
    assert first["left.console"].count("left got pong") >= 3, f"expected pongs back:\n{first['left.console']}"


def test_a_recorded_set_writes_one_vcd_with_a_scope_per_board_on_the_one_clock(tmp_path):
    with BoardSet(load_boards(RIG), seed=2, record=True, artefacts=tmp_path) as boards:
        boards.run_for(0.1)
    merged = read_vcd((tmp_path / "trace.vcd").read_text())  # (strict: codes, values, time, scopes)
    for board in ("left", "right"):
        own = read_vcd((tmp_path / board / "trace.vcd").read_text())
        assert own.vars, f"expected board {board}'s own VCD to hold its signals"
        for path, var in own.vars.items():  # (its own VCD's top scope is its app's, two_boards_<board>)
            there = f"two_boards.{board}.{path.split('.', 1)[1]}"
            assert there in merged.vars and merged.vars[there].type == var.type, f"expected {there} in the merged VCD"
            assert merged.changes.get(there) == own.changes.get(path), (
                f"expected {there} to change as {path} in board {board}'s own VCD: "
                f"{merged.changes.get(there, [])[:4]} for {own.changes.get(path, [])[:4]}"
            )
    edges = merged.timeline("two_boards.right.sensors.ready.out")
    assert len(edges) > 3, f"expected the right board's ready line to change, got {edges}"
    theirs = read_vcd(gtkwave_round_trip(tmp_path / "trace.vcd", tmp_path))  # (GTKWave reads it as written)
    assert theirs.timeline("two_boards.right.sensors.ready.out") == edges, "expected GTKWave to read the same edges"
    lines = (tmp_path / "trace.gtkw").read_text().splitlines()  # its save file: a group a board, then a role
    assert '[dumpfile] "trace.vcd"' in lines, lines[:6]
    traced = [line for line in lines if line.startswith("two_boards.")]
    assert sorted(traced) == sorted(merged.vars), f"expected every variable shown once: {traced}"
    groups = [line[1:] for line in lines if line.startswith("-")]
    assert groups[:2] == ["left", "sensors"] and groups.count("right") == 2, groups  # (begun and ended)


def test_a_gpio_edge_reaches_the_other_board_at_the_instant_it_was_written(tmp_path):
    with BoardSet(load_boards(RIG), seed=2, artefacts=tmp_path) as boards:
        boards.run_for(0.3)
        written = re.findall(r"left ready (\d) at (\d+)", boards["left"].console)
        seen = re.findall(r"right edge (\d) at (\d+)", boards["right"].console)
    assert len(seen) >= 20, f"expected at least 20 edges on the right, got {len(seen)} (artefacts: {tmp_path})"
    assert written[: len(seen)] == seen, f"expected each edge at its write's instant (artefacts: {tmp_path})"


def test_each_uart_byte_arrives_when_its_ten_bits_have_crossed_the_wire(tmp_path):
    _run(tmp_path, seed=3)
    sent = [r for r in _records(tmp_path, "left") if r.get("msg") == "UART_TX"]
    arrived = [c for r in _records(tmp_path, "right") if r.get("msg") == "STATE" for c in r["changes"] if c[2] == 2]
    assert len(sent) >= 3, f"expected pings sent, got {len(sent)} (artefacts: {tmp_path})"
    expected = []
    for record in sent:
        data = bytes.fromhex(record["data"])
        expected += [[record["t"] + round((i + 1) * BYTE_US), data[i : i + 1].hex()] for i in range(len(data))]
    got = [[c[0], c[4]] for c in arrived]
    assert got[: len(expected)] == expected[: len(got)], (
        f"expected each byte one byte time (86.8 us) after the one before, from the UART_TX's instant; "
        f"got {got[:8]} for {expected[:8]} (artefacts: {tmp_path})"
    )


def test_each_board_keeps_its_own_console_and_trace_folder(tmp_path):
    _run(tmp_path, seed=4, seconds=0.1)
    for board in ("left", "right"):
        console = (tmp_path / board / "console.log").read_text()
        assert f"{board} " in console and ("right" if board == "left" else "left ") not in console, console[:300]
        header = _records(tmp_path, board)[0]["header"]
        assert header["app"] == f"two_boards.{board}", header


def _with_firmware(tmp_path: Path, right_main: str, left_main: str | None = None) -> Path:
    """The two boards' rig in ``tmp_path``, the right board's main.py replaced (and the left's)."""
    folder = tmp_path / "rig"
    source = RIG.parent
    for item in ("left", "right"):
        (folder / item).mkdir(parents=True)
        (folder / item / "main.py").write_text((source / item / "main.py").read_text())
    (folder / "rig.toml").write_text(RIG.read_text())
    (folder / "right" / "main.py").write_text(right_main)
    if left_main is not None:
        (folder / "left" / "main.py").write_text(left_main)
    return folder / "rig.toml"


def test_a_board_that_raises_is_named_in_the_failure(tmp_path):
    rig = _with_firmware(tmp_path, "import time\ntime.sleep_ms(20)\nraise ValueError('right gave up')\n")
    with pytest.raises(FirmwareError) as failure:
        with BoardSet(load_boards(rig), seed=5, artefacts=tmp_path / "out") as boards:
            boards.run_for(0.1)
    message = str(failure.value)
    assert message.startswith("board right: firmware raised at virtual t=0.020000 s"), message
    assert "right gave up" in message and str(tmp_path / "out" / "right") in message, message
    assert "left ready" in (tmp_path / "out" / "left" / "console.log").read_text(), "expected left's console kept"


def test_a_board_whose_firmware_ends_fails_the_run_unless_the_set_allows_it(tmp_path):
    rig = _with_firmware(tmp_path, "import time\ntime.sleep_ms(20)\nprint('right done')\n")
    with pytest.raises(FirmwareExited, match=r"^board right: the firmware ended at virtual t=0\.020000 s"):
        with BoardSet(load_boards(rig), seed=5) as boards:
            boards.run_for(0.1)
    with BoardSet(load_boards(rig), seed=5, allow_exit=True) as boards:  # (mpy-fil run --allow-exit)
        boards.run_for(0.1)
        left, right = boards["left"].console, boards["right"].console
    assert boards.t_us == 100_000 and "right done" in right, right
    late = [int(t) - TICKS0 for t in re.findall(r"left ready \d at (\d+)", left)]
    assert late and late[-1] > 50_000, f"expected the left board on after the right ended, got its lines at {late}"
    code, text, err = run_cli("run", rig, "--seconds", "0.1", "--no-plots", "--allow-exit", "--out", tmp_path / "run")
    assert code == 0 and "right done" in text, f"exit {code}:\n{text}\n{err}"


def test_a_failing_run_of_a_set_shrinks_from_its_run_folder(tmp_path):
    """mpy-fil shrink of a set's run folder (a trace folder a board): the rig file, seed and
    world its boards' headers name, run again only when trusted; cut to the failure."""
    rig = _with_firmware(tmp_path, "import time\ntime.sleep_ms(20)\nraise ValueError('right gave up')\n")
    with pytest.raises(FirmwareError):
        with BoardSet(load_boards(rig), seed=5, trace=True, record=True, artefacts=tmp_path / "run") as boards:
            boards.run_for(0.3)
    code, text, err = run_cli("shrink", tmp_path / "run", "--out", tmp_path / "s", "--workers", 1)
    assert code == 2 and "--app RIG, or --trust-folder" in err, f"expected a rig file run only if trusted: {err}"
    code, text, err = run_cli("shrink", tmp_path / "run", "--trust-folder", "--out", tmp_path / "s", "--workers", 1)
    assert code == 0, f"exit {code}:\n{text}\n{err}"
    assert "fails as: error FirmwareError: board right: firmware raised at virtual t=# s" in text, text
    minimal = json.loads((tmp_path / "s" / "shrink.json").read_text())["minimal"]
    assert minimal["rig"] == str(rig) and minimal["seed"] == 5, minimal
    assert 0.02 <= minimal["seconds"] < 0.3, f"expected the run cut to just past 20 ms, got {minimal['seconds']} s"


def test_a_board_that_stops_answering_is_named_by_the_watchdog(tmp_path):
    # (a hard IRQ's handler that never returns, at the left board's first edge on READY: a
    # loop in the main program or a soft callback moves virtual time, as a board's does,
    # docs/mcu-time.md; one in a hard handler runs at its edge's instant)
    hangs = "from machine import Pin\nimport time\ndef edge(p):\n    while True:\n        pass\n"
    hangs += "Pin(5, Pin.IN).irq(edge, Pin.IRQ_RISING | Pin.IRQ_FALLING, hard=True)\n"
    hangs += "while True:\n    time.sleep_ms(10)\n"
    rig = _with_firmware(tmp_path, hangs)
    with pytest.raises(FirmwareHung) as failure:
        with BoardSet(load_boards(rig), seed=6, watchdog_s=1.0) as boards:
            boards.run_for(0.1)
    assert str(failure.value).startswith("board right: "), str(failure.value)


def test_a_mistake_in_a_board_table_names_the_file_the_board_and_the_field(tmp_path):
    rig = _with_firmware(tmp_path, "")
    data = {
        "plant": {"body": "bench", "parts": [{"kind": "board_uart", "name": "link"}]},
        "boards": [
            {"name": "left", "firmware": {"dir": "left"}, "board": {"pins": {"LINK_UART": 1}}, "wiring": {}},
            {"name": "right", "firmware": {"dir": "right"}, "board": {"pins": {"X_UART": 0}}, "wiring": {"Y": "a"}},
        ],
    }
    named = r"rig\.toml: \[\[boards\]\] right: \[wiring\] Y: board pins has no pin named Y"
    with pytest.raises(ConfigError, match=named):
        boards_from_data(rig, data)
    data["boards"][1]["name"] = "left"
    with pytest.raises(ConfigError, match=r"\[\[boards\]\] #2 name: a second board named 'left'"):
        boards_from_data(rig, data)


def test_a_one_board_loader_given_several_boards_says_what_to_use():
    with pytest.raises(ConfigError, match=r"\[\[boards\]\]: a rig file with several boards: run it as a BoardSet"):
        load_rig(RIG)


RESETS_ONCE = """\
import machine, time
try:
    open("booted").close()
    print("right booted again")
    while True:
        time.sleep_ms(10)
except OSError:
    open("booted", "w").close()
    time.sleep_ms(20)
    print("right resets")
    machine.reset()
"""


def test_a_board_that_resets_restarts_alone_and_the_others_go_on(tmp_path):
    rig = _with_firmware(tmp_path, RESETS_ONCE)
    with BoardSet(load_boards(rig), seed=7, artefacts=tmp_path / "out") as boards:
        boards.run_for(0.1)
        right, left = boards["right"], boards["left"]
        assert right.resets == 1 and "right booted again" in right.console, right.console
        assert left.resets == 0 and left.console.count("left ready") >= 10, left.console
        assert boards.t_us == 100_000


def test_every_board_records_the_one_plants_ground_truth_at_the_same_instants(tmp_path):
    with BoardSet(load_boards(RIG), seed=8, record=True, artefacts=tmp_path) as boards:
        boards.run_for(0.2)
    left, right = ((tmp_path / board / "truth.csv").read_text() for board in ("left", "right"))
    assert left == right and left.count("\n") >= 4, f"expected the same truth.csv in {tmp_path}/left and right"
    assert "ready.out" in (tmp_path / "right" / "signals.csv").read_text(), "expected the right board's input recorded"


SPINS = """\
import time
from machine import Pin
ready = Pin(4, Pin.OUT, value=0)
for n in range(4):
    t0 = t = time.ticks_us()
    while time.ticks_diff(t, t0) < 5000:  # a busy wait: 10 us a read past 50 reads
        t = time.ticks_us()
    ready.value(1 - n % 2)  # (at t: a read would take 10 us more)
    print("left ready", 1 - n % 2, "at", t)
while True:
    time.sleep_ms(100)
"""
SLEEPS = """\
import time
from machine import Pin
levels, at, n = bytearray(8), [0] * 8, 0  # (a hard handler runs with the heap locked: it allocates nothing)
both = Pin.IRQ_RISING | Pin.IRQ_FALLING
def edge(pin):
    global n
    levels[n], at[n] = pin.value(), time.ticks_us()
    n += 1
Pin(5, Pin.IN).irq(edge, both, hard=True)
time.sleep_ms(50)
for i in range(n):
    print("right edge", levels[i], "at", at[i])
while True:
    time.sleep_ms(100)
"""


def test_a_board_spins_alone_until_another_board_could_act(tmp_path):
    rig = _with_firmware(tmp_path, SLEEPS, SPINS)
    with BoardSet(load_boards(rig), seed=9, artefacts=tmp_path / "out") as boards:
        boards.run_for(0.06)
        left, right = boards["left"], boards["right"]
        written = re.findall(r"left ready (\d) at (\d+)", left.console)
        seen = re.findall(r"right edge (\d) at (\d+)", right.console)
        exchanges = left.stats.link_round_trips
    assert len(written) == 4 and seen == written, f"expected 4 edges seen where written:\n{written}\n{seen}"
    assert int(written[0][1]) - TICKS0 >= 5000, written
    # (a horizon of the next µs only: a sync every 10 us of each 5 ms spin, about 2,000)
    assert exchanges < 40, f"expected the spins alone up to the right board's wake, got {exchanges} exchanges"


def uart_pair_rig(name: str, faults: str = "") -> str:
    """Two boards, an ESP32 (left) and a Pico (right), on one board_uart (the link's options
    in ``faults``: its drop and damage chances)."""
    return f"""\
name = "{name}"
[plant]
body = "bench"
[[plant.parts]]
kind = "board_uart"
name = "link"
{faults}
[[boards]]
name = "left"
firmware = {{ dir = "left" }}
board = {{ family = "esp32", pins = {{ LINK_UART = 1 }} }}
wiring = {{ LINK_UART = "link.a" }}
[[boards]]
name = "right"
firmware = {{ dir = "right" }}
board = {{ family = "rpi_pico", pins = {{ LINK_UART = 0 }} }}
wiring = {{ LINK_UART = "link.b" }}
"""


BURSTS = """\
import time
from machine import UART
u = UART(1, 115200)
for n in range(4):
    u.write(bytes(range(n, n + 150)))  # (150 bytes: 13 ms on the wire)
    time.sleep_ms(50)
while True:
    time.sleep_ms(100)
"""

SLOW_READER = """\
import time
from machine import UART
u = UART(0, 115200)
got = b""
while True:
    time.sleep_ms(40)
    got += u.read() or b""
    print("right has", len(got), "sum", sum(got), "at", time.ticks_us())
"""


def test_a_board_no_change_can_wake_takes_the_bytes_in_flight_at_its_wake_not_a_round_each(tmp_path):
    rig = set_folder(tmp_path, {"left": BURSTS, "right": SLOW_READER}, uart_pair_rig("uart_pair"))
    with BoardSet(load_boards(rig), seed=1, artefacts=tmp_path / "out") as boards:
        boards.run_for(0.25)
        console, rounds = boards["right"].console, boards.rounds
    expected = sum(sum(range(n, n + 150)) for n in range(4))
    assert f"right has 600 sum {expected}" in console, f"expected the 600 bytes sent, in order, got:\n{console}"
    # (the left board's wakes, the right's, the run's end: about 12; a round a byte arriving: 600 more)
    assert rounds < 40, f"expected a round at each board's wake only, got {rounds} for 600 bytes in flight"


def test_a_board_of_a_set_is_not_run_alone(tmp_path):
    with BoardSet(load_boards(RIG), seed=10) as boards:
        with pytest.raises(ConfigError, match=r"board left is one of a set of boards: run the set"):
            boards["left"].run_for(0.01)
        boards.run_for(0.01)
        assert boards["left"].t_us == boards["right"].t_us == 10_000


def set_folder(folder: Path, mains: dict, rig: str) -> Path:
    """A rig file with several boards in ``folder``: each board's main.py (board -> text), its rig.toml."""
    for board, main in mains.items():
        (folder / board).mkdir()
        (folder / board / "main.py").write_text(main)
    (folder / "rig.toml").write_text(rig)
    return folder / "rig.toml"


REACTION_RIG = """\
name = "reaction"
[plant]
body = "bench"
[[plant.parts]]
kind = "wire"
name = "cmd"
[[boards]]
name = "left"
firmware = { dir = "left" }
board = { family = "esp32", pins = { CMD = 4 } }
wiring = { CMD = "cmd.in" }
[[boards]]
name = "right"
firmware = { dir = "right" }
board = { family = "rpi_pico", pins = { CMD = 5, ACK = 6 } }
wiring = { CMD = "cmd.out", ACK = "probe:ack" }
[budgets.command]
kind = "reaction"
stimulus = "left:cmd.in"
response = "right:probe:ack"
limit_us = LIMIT
description = "the right board acts on the left's command within {limit_ms:g} ms"
"""

COMMANDER = """\
import time
from machine import Pin
cmd = Pin(4, Pin.OUT, value=0)
for n in range(10):
    time.sleep_ms(17 + 3 * (n % 4))
    cmd.toggle()
while True:
    time.sleep_ms(100)
"""

ACTOR = """\
import time
from machine import Pin
ack = Pin(6, Pin.OUT, value=0)
got = []
Pin(5, Pin.IN).irq(lambda p: got.append(1), Pin.IRQ_RISING | Pin.IRQ_FALLING)
while True:
    if got:
        got.clear()
        time.sleep_us(3000)  # (the command's work: 3 ms)
        ack.toggle()
    time.sleep_ms(1)
"""


@pytest.mark.parametrize(("limit_us", "holds"), [(5000, True), (2000, False)])
def test_a_budget_across_boards_times_a_command_on_one_to_the_action_of_the_other(tmp_path, limit_us, holds):
    set_folder(tmp_path, {"left": COMMANDER, "right": ACTOR}, REACTION_RIG.replace("LIMIT", str(limit_us)))
    with BoardSet(load_boards(tmp_path / "rig.toml"), seed=1) as boards:
        boards.run_for(0.3)
    budget = boards.budgets["command"]
    stats = budget.stats()
    # each command seen at its edge, acted on at the main loop's next 1 ms tick plus 3 ms of work
    assert stats["count"] == 10 and 3000 <= stats["min"] <= stats["max"] <= 4000, stats
    if holds:
        budget.check()
    else:
        with pytest.raises(
            AssertionError, match=r"budget command: expected every value left:cmd\.in -> right:probe:ack <= 2000 us"
        ):
            budget.check()


def test_a_budget_across_boards_names_a_board_or_signal_it_cannot_see(tmp_path):
    set_folder(
        tmp_path,
        {"left": COMMANDER, "right": ACTOR},
        REACTION_RIG.replace("LIMIT", "5000").replace("right:probe:ack", "right:probe:nak"),
    )
    with pytest.raises(ConfigError, match=r"\[budgets\.command\] response: board right wires no pin to 'probe:nak'"):
        load_boards(tmp_path / "rig.toml")


def test_a_board_that_browns_out_boots_again_and_the_others_carry_on(tmp_path):
    """BoardSet.power_cycle: the right board loses power at 0.1 s (killed in its wait) and
    boots again at that instant; the left board's commands after it are acted on again."""
    set_folder(
        tmp_path, {"left": COMMANDER, "right": 'print("actor up")\n' + ACTOR}, REACTION_RIG.replace("LIMIT", "5000")
    )
    with BoardSet(load_boards(tmp_path / "rig.toml"), seed=1, artefacts=tmp_path / "out") as boards:
        boards.run_for(0.1)
        before = boards.budgets["command"].stats()["count"]
        boards.power_cycle("right")
        boards.run_for(0.2)
        console = boards["right"].console
        after = boards.budgets["command"].stats()["count"]
        assert boards["right"].resets == 1 and boards["left"].resets == 0
    assert console.count("actor up") == 2 and "[power lost and back at t=0.100000 s]" in console, console
    assert 3 <= before < after <= 10, f"expected commands acted on before and after the brownout: {before}, {after}"


SENDER = """\
import time
from machine import UART
u = UART(1, 115200)
time.sleep_ms(5)
u.write(bytes(range(200)))
while True:
    time.sleep_ms(100)
"""

RECEIVER = """\
import time
from machine import UART
u = UART(0, 115200)
time.sleep_ms(60)
got = u.read() or b""
print("right got", len(got), "bytes;", got.hex())
while True:
    time.sleep_ms(100)
"""


@pytest.mark.parametrize("faults", ["drop_p = 0.1", "flip_p = 0.1"])
def test_a_board_uart_loses_or_damages_bytes_as_its_faults_say_the_same_each_run(tmp_path, faults):
    set_folder(tmp_path, {"left": SENDER, "right": RECEIVER}, uart_pair_rig("uart_faults", faults))
    runs = []
    for _ in range(2):
        with BoardSet(load_boards(tmp_path / "rig.toml"), seed=4) as boards:
            boards.run_for(0.1)
            runs.append((boards["right"].console, boards.truth()))
    (console, truth), again = runs[0], runs[1]
    assert again == runs[0], "expected the same faults for the same seed"
    got = bytes.fromhex(console.split(";")[1].split()[0])
    sent = bytes(range(200))
    if faults.startswith("drop"):
        assert 5 <= truth["link_a_lost"] <= 40 and truth["link_a_damaged"] == 0, truth
        assert len(got) == 200 - truth["link_a_lost"] and set(got) <= set(sent), console
        assert got == bytes(b for b in sent if b in set(got)), "expected the bytes that arrived in their order"
    else:
        damaged = sum(1 for a, b in zip(sent, got) if a != b)
        assert len(got) == 200 and 5 <= damaged == truth["link_a_damaged"] <= 40, (damaged, truth)
        assert all(bin(a ^ b).count("1") == 1 for a, b in zip(sent, got) if a != b), "expected one bit flipped a byte"
    assert truth["link_b_lost"] == truth["link_b_damaged"] == 0, truth


@pytest.mark.hil
def test_each_boards_coverage_goes_to_its_own_data_file(tmp_path):
    """BoardSet(coverage=...): each board's firmware measured on the line-tracing
    interpreter (docs/coverage.md), into its own coverage.py data file: the commander's loop
    and the actor's reaction, each in its board's file only."""
    from coverage import CoverageData

    set_folder(tmp_path, {"left": COMMANDER, "right": ACTOR}, REACTION_RIG.replace("LIMIT", "5000"))
    files = {b: tmp_path / "cov" / f".coverage.{b}" for b in ("left", "right")}
    with BoardSet(load_boards(tmp_path / "rig.toml"), seed=1, coverage=files.get) as boards:
        boards.run_for(0.1)
    lines = {}
    for board, path in files.items():
        data = CoverageData(basename=str(path))
        data.read()
        lines[board] = {Path(f).parent.name: set(data.lines(f)) for f in data.measured_files()}
    assert {5, 6} <= lines["left"]["left"] and "right" not in lines["left"], lines["left"]
    assert {8, 9, 10} <= lines["right"]["right"] and "left" not in lines["right"], lines["right"]


def test_each_board_of_a_set_replays_from_its_own_trace_folder(tmp_path):
    """A board's trace folder names its board (``rig.toml::left``); replayed alone, the other
    board's bytes and levels as its recording holds them, it gives the same outputs (the
    UART line both ways: what it sent recorded as ``link.a:sent``)."""
    from host.rig.loop.replay import FirmwareChoice, replay

    with BoardSet(load_boards(RIG), seed=2, trace=True, record=True, artefacts=tmp_path / "run") as boards:
        boards.run_for(0.2)
    for board in ("left", "right"):
        header = json.loads((tmp_path / "run" / board / "header.json").read_text())
        assert header["spec"]["app"].endswith(f"two_boards/rig.toml::{board}"), header["spec"]["app"]
        result = replay(
            tmp_path / "run" / board, tmp_path / f"replay-{board}", choice=FirmwareChoice(trust_folder=True)
        )
        assert result.same and result.recorded >= 10, f"board {board}: {result.difference} ({result.folder})"


WORLDS_RIG = """\
name = "worlds"
[plant]
body = "differential"
room_w_m = 3.0
room_h_m = 2.0
start_pose = [0.5, 1.0, 0.0]
[[plant.parts]]
kind = "dc_motor"
name = "motor_l"
drives = "left"
[[plant.parts]]
kind = "dc_motor"
name = "motor_r"
drives = "right"
[[plant.parts]]
kind = "board_uart"
name = "link"
[worlds.default]
[worlds.wide]
room_w_m = 6.0
[[boards]]
name = "left"
firmware = { dir = "left" }
board = { family = "esp32", pins = { LINK_UART = 1 } }
wiring = { LINK_UART = "link.a" }
[[boards]]
name = "right"
firmware = { dir = "right" }
board = { family = "rpi_pico", pins = { LINK_UART = 0 } }
wiring = { LINK_UART = "link.b" }
"""


def test_a_set_runs_in_a_world_of_its_file_with_options_over_it(tmp_path):
    idle = "import time\nfrom machine import UART\nu = UART({})\nwhile True:\n    time.sleep_ms(50)\n"
    boards = load_boards(set_folder(tmp_path, {"left": idle.format(1), "right": idle.format(0)}, WORLDS_RIG))
    with BoardSet(boards, seed=1, world="wide", plant_options={"start_pose": [4.0, 1.0, 0.0]}) as wide:
        wide.run_for(0.05)
        bounds, x = wide.plant.world.bounds, wide.truth()["x_m"]
    assert bounds[2] == 6.0 and x == 4.0, (bounds, x)
    with pytest.raises(ConfigError, match=r"world: unknown world 'narrow' \(the file's worlds: default, wide\)"):
        BoardSet(boards, seed=1, world="narrow")


def test_diff_of_two_runs_of_a_set_compares_board_by_board(tmp_path):
    """mpy-fil diff A B of two sets' run folders: each board's trace folder with the other
    run's, its tables and plot under its name; the worst exit (docs/testing-tools.md)."""
    for run, seconds in (("a", 0.2), ("b", 0.2), ("c", 0.3)):  # (c: on for longer, more lines written)
        with BoardSet(load_boards(RIG), seed=1, trace=True, record=True, artefacts=tmp_path / run) as boards:
            boards.run_for(seconds)
    code, text, err = run_cli("diff", tmp_path / "a", tmp_path / "b", "--fail-on-output", "--out", tmp_path / "ab")
    assert code == 0, f"expected the same seed's runs the same, got exit {code}:\n{text}\n{err}"
    for board in ("left", "right"):
        assert f"board {board}:\n" in text and f"board {board}: same within the thresholds" in text, text
        assert (tmp_path / "ab" / board / "diff.png").is_file(), sorted((tmp_path / "ab").rglob("*"))
    code, text, err = run_cli("diff", tmp_path / "a", tmp_path / "c", "--fail-on-output", "--out", tmp_path / "ac")
    assert code == 1 and "board left: DIFFERS beyond the thresholds" in text, f"exit {code}:\n{text}\n{err}"
    code, text, err = run_cli("diff", tmp_path / "a", tmp_path / "c" / "left", "--out", tmp_path / "x")
    assert code == 2 and "holds the boards left, right and B" in err + text, f"exit {code}:\n{text}\n{err}"


SET_CAMPAIGN = """
[campaign]
rig = "RIG"
seconds = 1.0
step_s = 0.25
seeds = 2
budgets = ["motor:speed_loop"]
[[faultsets]]
name = "none"
[[faultsets]]
name = "motor_browns_out"
[[faultsets.faults]]
kind = "brownout"
board = "motor"
at_s = 0.4
"""


def test_a_campaign_of_a_set_gives_each_board_its_own_faults_and_budgets(tmp_path):
    """A campaign's rig may be a rig file with several boards: each harness fault names its
    board (a brown-out of the motor board), the budgets are the set's (a board's own as
    <board>:<name>), each run's trace folders one a board (docs/campaigns.md); a failing
    run shrinks as a one-board run does (docs/testing-tools.md)."""
    from host.campaign import load_campaign
    from host.campaign.runner import run_campaign

    rig = Path(__file__).parents[2] / "examples" / "two_board_rover" / "rig.toml"
    (tmp_path / "set.toml").write_text(SET_CAMPAIGN.replace("RIG", str(rig)))
    results = {r["key"]: r for r in run_campaign(load_campaign(str(tmp_path / "set.toml")), tmp_path / "out")}
    assert sorted(results) == [f"{s}/default/{n}" for s in ("motor_browns_out", "none") for n in (1, 2)], results
    for n in (1, 2):
        calm, cut = results[f"none/default/{n}"], results[f"motor_browns_out/default/{n}"]
        assert calm["passed"] and calm["resets"] == 0, calm
        assert calm["budgets"]["motor:speed_loop"]["misses"] == 0, calm["budgets"]
        # (the motor board boots again at 0.4 s: its speed loop misses a period, the run fails on it)
        assert cut["resets"] == 1 and not cut["passed"], cut
        assert cut["message"] == "expected the budgets kept, missed: motor:speed_loop (1 misses)", cut["message"]
        folder = Path(cut["artefacts"])
        assert "[power lost and back at t=0.4" in (folder / "motor" / "console.log").read_text(), folder
        assert "power lost" not in (folder / "nav" / "console.log").read_text(), f"expected the nav board on: {folder}"
    # mpy-fil shrink of a set's failing run: the brown-out kept, the run cut to just past it
    failing = tmp_path / "out" / "motor_browns_out" / "default" / "1"
    code, text, err = run_cli("shrink", failing, "--out", tmp_path / "s")
    assert code == 0 and "fails as: budget budgets: motor:speed_loop" in text, f"exit {code}:\n{text}\n{err}"
    assert re.search(r"^faults\[0\] brownout 0\.4 +- +kept$", text, re.M), text
    shrunk = json.loads((tmp_path / "s" / "shrink.json").read_text())["minimal"]
    assert shrunk["faults"] == [{"kind": "brownout", "board": "motor", "at_s": 0.4}], shrunk["faults"]
    assert 0.4 < shrunk["seconds"] < 1.0, f"expected the run cut to just past the brown-out, got {shrunk['seconds']} s"
    bad = SET_CAMPAIGN.replace('board = "motor"\n', "")
    (tmp_path / "bad.toml").write_text(bad.replace("RIG", str(rig)))
    named = r"'motor_browns_out': faults\[0\] \(brownout\) board: expected the board it acts on \(motor, nav\)"
    with pytest.raises(ConfigError, match=named):
        load_campaign(str(tmp_path / "bad.toml"))

"""A board as another board's I2C target (docs/multi-board.md, "I2C between boards"): the
master's I2C(0) wired to the MCU's ``machine.I2CTarget`` by a ``board_i2c`` part
(host/tests/firmware/i2c_boards/). Each transfer reaches the target's firmware at its
instant; the target answers from its memory or its hard IRQ handler as the port's
interrupt does (extmod/machine_i2c_target.c's state machine), on one virtual clock."""

import re
import shutil
import threading
from pathlib import Path

import pytest

from host.core.errors import ConfigError, FirmwareError, FirmwareHung
from host.rig.config.boardfile import boards_from_data, load_boards
from host.rig.loop.boardset import BoardSet

RIG = Path(__file__).parent / "firmware" / "i2c_boards" / "rig.toml"

pytestmark = pytest.mark.hil


def _run(rig: Path, folder: Path, seed: int = 1, seconds: float = 0.3, trace: bool = False) -> dict:
    with BoardSet(load_boards(rig), seed=seed, trace=trace, artefacts=folder) as boards:
        boards.run_for(seconds)
        out = {f"{name}.console": r.console for name, r in boards.rigs.items()}
        return out | {name: r.trace_digest for name, r in boards.rigs.items()}


def test_the_master_reads_the_targets_memory_and_its_writes_run_the_targets_handler_then(tmp_path):
    got = _run(RIG, tmp_path)
    master, mcu = got["master.console"], got["mcu.console"]
    reads = [(int(c), int(t)) for c, t in re.findall(r"master read (\d+) at (\d+)", master)]
    commands = [(int(v), int(a), int(t)) for v, a, t in re.findall(r"mcu command (\d+) at reg (\d+) at (\d+)", mcu)]
    assert "master scan [66]" in master, f"expected the target's address 0x42 in a scan:\n{master}"
    assert [c for c, _ in reads] == [1 + 4 * k for k in range(10)], (
        f"expected the MCU's counter (one a 5 ms loop) read every 20 ms: 1, 5, 9, ...; "
        f"got {reads} (artefacts: {tmp_path})"
    )
    assert commands == [(k, 8, reads[k][1]) for k in range(10)], (
        f"expected each command's END_WRITE handler at the master's write instant, register 8: {commands} "
        f"for the reads {reads} (artefacts: {tmp_path})"
    )
    assert "master nobody at 0x43 19" in master, f"expected ENODEV for an address no target took:\n{master}"


def test_the_same_seed_gives_the_same_traces_for_both_boards(tmp_path):
    first = _run(RIG, tmp_path / "a", seed=3, seconds=0.15, trace=True)
    second = _run(RIG, tmp_path / "b", seed=3, seconds=0.15, trace=True)
    for board in ("master", "mcu"):
        assert first[board] == second[board], f"board {board}: two digests (traces in {tmp_path / 'a' / board}, b)"
    done = (tmp_path / "a" / "mcu" / "trace.jsonl").read_text().count('"msg":"I2CT_DONE"')
    assert done >= 10, f"expected each transaction in the target's trace, got {done} (artefacts: {tmp_path / 'a'})"


HARD_TARGET = """\
import time
from machine import I2CTarget

# (a hard handler runs with the heap locked, as on an rp2: it allocates nothing)
events, n_events = bytearray(16), 0
OUT = (b"a", b"b", b"c")
n_out = 0
got = bytearray(1)
written, n_written = bytearray(4), 0

def on_i2c(t):
    global n_events, n_out, n_written
    flags = t.irq().flags()
    events[n_events] = flags
    n_events += 1
    if flags & I2CTarget.IRQ_READ_REQ:
        t.write(OUT[n_out])
        n_out += 1
    if flags & I2CTarget.IRQ_WRITE_REQ:
        t.readinto(got)
        written[n_written] = got[0]
        n_written += 1

t = I2CTarget(0, 0x42)
every = 63  # ADDR_MATCH_READ | ADDR_MATCH_WRITE | READ_REQ | WRITE_REQ | END_READ | END_WRITE
t.irq(on_i2c, trigger=every, hard=True)
try:
    t.irq(on_i2c, trigger=I2CTarget.IRQ_READ_REQ)
except ValueError as e:
    print("mcu", e)
t.irq(on_i2c, trigger=every, hard=True)
while True:
    time.sleep_ms(10)
    if n_events:
        print("mcu events", list(events[:n_events]), "written", list(written[:n_written]))
        n_events = 0
"""

HARD_MASTER = """\
import time
from machine import I2C
i2c = I2C(0, freq=100000)
time.sleep_ms(5)
i2c.writeto(0x42, b"\\x07\\x09")
print("master read", i2c.readfrom(0x42, 3))
while True:
    time.sleep_ms(100)
"""


def _rig_with(tmp_path: Path, master: str, mcu: str, mcu_family: str = "rpi_pico") -> Path:
    folder = tmp_path / "rig"
    shutil.copytree(RIG.parent, folder)
    (folder / "master" / "main.py").write_text(master)
    (folder / "mcu" / "main.py").write_text(mcu)
    rig = folder / "rig.toml"
    rig.write_text(rig.read_text().replace('family = "rpi_pico"', f'family = "{mcu_family}"'))
    return rig


def test_a_target_without_memory_is_served_by_its_hard_handler_event_by_event(tmp_path):
    """The events in the C's order for a write of two bytes, then a read of three (each
    READ_REQ answered with one byte the handler writes), as on an rp2."""
    got = _run(_rig_with(tmp_path, HARD_MASTER, HARD_TARGET), tmp_path / "out", seconds=0.05)
    assert "mcu hard IRQ required" in got["mcu.console"], got["mcu.console"]
    assert "master read b'abc'" in got["master.console"], got["master.console"]
    # ADDR_MATCH_WRITE 2, WRITE_REQ 8 twice, END_WRITE 32; ADDR_MATCH_READ 1, READ_REQ 4 thrice, END_READ 16
    expected = "mcu events [2, 8, 8, 32, 1, 4, 4, 4, 16] written [7, 9]"
    assert expected in got["mcu.console"], f"expected {expected!r}:\n{got['mcu.console']}"


ESP32_TARGET = """\
import time
from machine import I2CTarget
print("mcu has READ_REQ", hasattr(I2CTarget, "IRQ_READ_REQ"))
t = I2CTarget(0x42, mem=bytearray(4))
try:
    t.irq(lambda t: None, hard=True)
except ValueError as e:
    print("mcu", e)
while True:
    time.sleep_ms(10)
"""


def test_an_esp32_target_has_no_hard_irq_and_only_the_end_events(tmp_path):
    """ports/esp32/mpconfigport.h sets no MICROPY_PY_MACHINE_I2C_TARGET_HARD_IRQ: the
    request events are not there, hard=True is refused; id defaults to 0."""
    got = _run(_rig_with(tmp_path, HARD_MASTER, ESP32_TARGET, "esp32"), tmp_path / "out", seconds=0.03)
    assert "mcu has READ_REQ False" in got["mcu.console"] and "mcu hard IRQ unsupported" in got["mcu.console"], got
    assert "master read b'\\x00\\x00\\x00'" in got["master.console"], got["master.console"]


def test_a_board_i2c_naming_no_board_of_the_file_is_refused_with_its_field(tmp_path):
    data = {
        "plant": {
            "body": "bench",
            "parts": [{"kind": "board_i2c", "name": "bus", "controller": "master", "target": "mcu2"}],
        },
        "boards": [
            {"name": "master", "firmware": {"dir": "master"}, "board": {"family": "esp32", "pins": {}}, "wiring": {}},
            {"name": "mcu", "firmware": {"dir": "mcu"}, "board": {"family": "rpi_pico", "pins": {}}, "wiring": {}},
        ],
    }
    shutil.copytree(RIG.parent, tmp_path, dirs_exist_ok=True)
    with pytest.raises(ConfigError) as e:
        boards_from_data(tmp_path / "rig.toml", data)
    assert "[[plant.parts]] bus target: expected one of the boards master, mcu, got 'mcu2'" in str(e.value), e.value


# -- a host program as a board ---------------------------------------------------------

HOST_RIG = RIG.parent / "host_master.toml"
TICKS0 = 2**30 - 10_000_000  # a board's ticks_us at t=0 (docs/clock.md); a host program's is t itself


def test_a_host_program_masters_the_target_on_the_same_clock(tmp_path):
    got = _run(HOST_RIG, tmp_path)
    host, mcu = got["master.console"], got["mcu.console"]
    reads = [(int(c), int(t)) for c, t in re.findall(r"host read (\d+) at (\d+)", host)]
    commands = [(int(v), int(t) - TICKS0) for v, t in re.findall(r"mcu command (\d+) at reg 8 at (\d+)", mcu)]
    assert "host scan [66]" in host and "host nobody at 0x43 19" in host, host
    assert len(reads) == 10 and [c for c, _ in reads] == sorted(c for c, _ in reads), reads
    # each read takes 47 clocks at 400 kHz (118 us); the write after it starts at the read's print
    assert commands == [(k, reads[k][1]) for k in range(10)], (
        f"expected each command at its write's instant: {commands} {reads}"
    )
    assert reads[1][1] - reads[0][1] == 20_000 + 191, f"expected 20 ms of sleep plus two transfers' bus time: {reads}"
    assert "(the host program returned at t=0.2" in host, host


def test_a_host_programs_run_is_deterministic(tmp_path):
    first = _run(HOST_RIG, tmp_path / "a", seed=2, seconds=0.12, trace=True)
    second = _run(HOST_RIG, tmp_path / "b", seed=2, seconds=0.12, trace=True)
    assert first == second, f"expected the same consoles and digests twice (artefacts: {tmp_path})"


def _host_rig(tmp_path: Path, program: str) -> Path:
    folder = tmp_path / "rig"
    shutil.copytree(RIG.parent, folder)
    (folder / "master.py").write_text(program)
    return folder / "host_master.toml"


def test_a_host_program_that_raises_fails_the_run_naming_the_board_and_its_line(tmp_path):
    rig = _host_rig(tmp_path, "def main(board):\n    board.sleep_ms(3)\n    raise ValueError('master gave up')\n")
    with pytest.raises(FirmwareError) as e:
        _run(rig, tmp_path / "out")
    text = str(e.value)
    assert text.startswith("board master: the host program raised at virtual t=0.003000 s"), text
    assert "ValueError: master gave up" in text and 'master.py", line 3' in text, text


def test_a_host_program_that_never_waits_is_named_by_the_watchdog_and_leaves_no_thread(tmp_path):
    rig = _host_rig(tmp_path, "def main(board):\n    while True:\n        pass\n")
    with pytest.raises(FirmwareHung) as e:
        with BoardSet(load_boards(rig), seed=1, watchdog_s=0.5) as boards:
            boards.run_for(0.05)
    assert str(e.value).startswith("board master: the host program sent nothing for 0.5 s"), e.value


def test_stopping_a_set_ends_its_host_programs_thread(tmp_path):
    with BoardSet(load_boards(HOST_RIG), seed=1) as boards:
        boards.run_for(0.05)
    left = [t.name for t in threading.enumerate() if t.name.startswith("host program")]
    assert left == [], f"expected the host program's thread gone after stop, found {left}"


UART_RIG = """\
name = "uart_host"
[plant]
body = "bench"
[[plant.parts]]
kind = "board_uart"
name = "link"
[[boards]]
name = "node"
program = "node.py"
[[boards]]
name = "echo"
firmware = { dir = "echo" }
board = { family = "rpi_pico", pins = { LINK_UART = 0 } }
wiring = { LINK_UART = "link.b" }
"""

ECHO = """\
from machine import UART
u = UART(0, 115200, timeout=1000)
while True:
    line = u.readline()
    if line:
        u.write(line.upper())
"""

NODE = """\
def main(board):
    link = board.uart("link.a", 115200)
    for word in (b"ping", b"pong"):
        t0 = board.ticks_us()
        link.write(word + b"\\n")
        board.print("node sent", word, "got", link.readline(50), "after", board.ticks_us() - t0)
    board.print("node none", link.readline(5))
"""


def test_a_host_program_talks_to_a_board_over_a_uart_with_the_bytes_line_time(tmp_path):
    (tmp_path / "echo").mkdir()
    (tmp_path / "echo" / "main.py").write_text(ECHO)
    (tmp_path / "node.py").write_text(NODE)
    (tmp_path / "rig.toml").write_text(UART_RIG)
    got = _run(tmp_path / "rig.toml", tmp_path / "out", seconds=0.1)
    # 5 bytes there (434 us: 10 bits each at 115200 baud), 5 back, each arriving at its stop bit
    assert "node sent b'ping' got b'PING\\n' after 868" in got["node.console"], got
    assert "node sent b'pong' got b'PONG\\n' after 868" in got["node.console"], got
    assert "node none b''" in got["node.console"], got

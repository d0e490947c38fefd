"""Pins and a UART served from outside the rig (docs/external.md): a small script presses a
button at 50 ms, mirrors a trigger on an echo pin 1 ms later and answers each line on a UART;
the firmware's IRQs, the link trace and what the script was told agree to the µs; the same
run twice gives the same trace; a program that dies or answers out of protocol stops the run
naming the part and the rig file; no program outlives its rig."""

import json
import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from host.link import frames as F
from host.live import LiveRig
from sim_plant.catalogue.external import ExternalError

RIG = """
name = "external_lines"

[board]
family = "esp32"

[board.pins]
BUTTON = 4
TRIG = 5
ECHO = 18
DEV_UART = 1

[plant]
body = "bench"

[[plant.parts]]
kind = "external"
name = "dev"
command = "dev.py"
pins_in = ["trig"]
pins_out = [["echo", 0], ["button", 1]]
uart = true
baud = 9600
timeout_s = 2.0

[wiring]
BUTTON = "dev.button"
TRIG = "dev.trig"
ECHO = "dev.echo"
DEV_UART = "dev.uart"
"""
MAIN = """
import time

from machine import UART, Pin

T0 = time.ticks_us()


def now():
    return time.ticks_diff(time.ticks_us(), T0)


presses, echoes, trigs = [], [], []
button = Pin(4, Pin.IN, Pin.PULL_UP)
button.irq(lambda p: presses.append((now(), p.value())), Pin.IRQ_FALLING | Pin.IRQ_RISING)
echo = Pin(18, Pin.IN)
echo.irq(lambda p: echoes.append((now(), p.value())), Pin.IRQ_RISING | Pin.IRQ_FALLING)
trig = Pin(5, Pin.OUT, value=0)
uart = UART(1, baudrate=9600, tx=17, rx=16)
for i in range(3):
    time.sleep_ms(20)
    trigs.append(now())
    trig.value(1)
    time.sleep_us(10)
    trig.value(0)
time.sleep_ms(20)
uart.write(b"ping\\n")
got = b""
while not got.endswith(b"\\n"):
    time.sleep_ms(1)
    got += uart.read() or b""
print("reply", got)
while True:
    time.sleep_ms(100)
"""
DEV = """#!{python}
# A button pressed at 50 ms and let go at 150 ms; an echo pin that mirrors the trigger 1 ms
# later; a UART that answers each line with PONG:<line> 500 us after its last byte. Every
# request is kept in seen.log, the program's pid in pid.
import json
import os
import sys

open("pid", "w").write(str(os.getpid()))
line = b""
with open("seen.log", "w") as seen:
    for text in sys.stdin:
        msg = json.loads(text)
        seen.write(text)
        seen.flush()
        answer = {{}}
        if msg["op"] == "reset":
            answer = {{"pins": [[50000, "button", 0], [150000, "button", 1]]}}
        elif msg["op"] == "pins":
            answer = {{"pins": [[msg["t_us"] + 1000, "echo", msg["levels"]["trig"]]]}}
        elif msg["op"] == "uart":
            replies = []
            for t_us, byte in msg["bytes"]:
                line += bytes([byte])
                if byte == 10:
                    replies.append([t_us + 500, "PONG:" + line.decode()])
                    line = b""
            answer = {{"uart": replies}}
        print(json.dumps(answer), flush=True)
"""
BYTE_US = 10e6 / 9600


def project(tmp_path: Path, dev: str = DEV) -> Path:
    (tmp_path / "rig.toml").write_text(RIG)
    (tmp_path / "main.py").write_text(textwrap.dedent(MAIN))
    script = tmp_path / "dev.py"
    script.write_text(dev.format(python=sys.executable))
    script.chmod(0o755)
    return tmp_path / "rig.toml"


def trace_of(folder: Path) -> tuple[dict, list]:
    """The trace's handles by signal, and its records."""
    records = [json.loads(line) for line in (folder / "trace.jsonl").read_text().splitlines()]
    handles = {r["signal"]: r["handle"] for r in records if r.get("msg") == "CFG" and r.get("signal")}
    return handles, records


def changes_of(records: list, handle: int) -> list:
    """(t_us, level or bytes' hex) of each change the STATEs gave ``handle`` after its first
    value (once each: a rewound lookahead sends some again)."""
    changes = (c for r in records if r.get("msg") == "STATE" for c in r["changes"] if c[1] == handle)
    return sorted({(c[0], c[4] if c[2] == F.CH_BYTES else c[3]) for c in changes if c[0] > 0})


def alive(pid: int) -> bool:
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return False
    return stat.rsplit(")", 1)[1].split()[0] != "Z"


def test_a_script_serves_a_button_an_echo_pin_and_a_uart_at_the_instants_it_names(tmp_path):
    trace = tmp_path / "trace"
    with LiveRig.start(project(tmp_path), artefacts=trace) as rig:
        rig.run_until(console=r"reply .*\n", timeout_s=1)
        rig.run_until(t_us=200_000)
        assert "reply b'PONG:ping\\n'" in rig.console(), rig.console()
        presses, echoes, trigs = rig.eval("presses"), rig.eval("echoes"), rig.eval("trigs")
    pid = int((tmp_path / "pid").read_text())
    assert not alive(pid), f"expected the program (pid {pid}) to end with the rig; it is still there"
    handles, records = trace_of(trace)
    outs = [(r["t"], r["value"]) for r in records if r.get("msg") == "OUT" and r["handle"] == handles["dev.trig"]]
    trig_outs = [t for (t, value), (_, last) in zip(outs[1:], outs) if value != last]  # (its edges)
    rises = trig_outs[::2]
    assert len(rises) == 3 and [b - a for a, b in zip(trig_outs[::2], trig_outs[1::2])] == [10] * 3, trig_outs
    offset = rises[0] - trigs[0]  # (the firmware's clock from its boot; the trace's from the run's start)
    # the echo mirrors each trigger 1 ms later, to the µs, and fires the firmware's IRQ then
    assert [t + offset for t, _ in echoes] == [t + 1000 for t in trig_outs], (echoes, trig_outs)
    assert [level for _, level in echoes] == [1, 0] * 3
    assert changes_of(records, handles["dev.echo"]) == [(t + 1000, 1 - i % 2) for i, t in enumerate(trig_outs)]
    # the button falls at 50 ms and rises at 150 ms, as the script planned at reset
    assert [(t + offset, level) for t, level in presses] == [(50_000, 0), (150_000, 1)], presses
    assert changes_of(records, handles["dev.button"]) == [(50_000, 0), (150_000, 1)]
    # the script was told each trigger's edge and each byte's instant, as the trace has them
    seen = [json.loads(line) for line in (tmp_path / "seen.log").read_text().splitlines()]
    assert seen[0] == {
        "t_us": 0,
        "op": "reset",
        "levels": {"trig": 0},
        "outputs": {"echo": 0, "button": 1},
        "baud": 9600,
    }
    assert [m["t_us"] for m in seen if m["op"] == "pins"] == trig_outs
    (uart,) = [m for m in seen if m["op"] == "uart"]
    (tx,) = [r for r in records if r.get("msg") == "UART_TX"]
    assert uart["t_us"] == tx["t"] and bytes(b for _, b in uart["bytes"]) == b"ping\n"
    assert [t for t, _ in uart["bytes"]] == [tx["t"] + round((i + 1) * BYTE_US) for i in range(5)]
    # its reply reaches the firmware's RX from 500 µs after the last byte, 10 bits a byte
    start = uart["bytes"][-1][0] + 500
    rx = changes_of(records, handles["dev.uart"])
    assert [t for t, _ in rx] == [start + round((i + 1) * BYTE_US) for i in range(10)], rx
    assert "".join(data for _, data in rx) == b"PONG:ping\n".hex()


def test_the_same_script_and_firmware_give_the_same_trace_twice(tmp_path):
    rig_file, digests = project(tmp_path), []
    for _ in range(2):
        with LiveRig.start(rig_file, seed=1) as rig:
            rig.run_until(t_us=200_000)
            assert "reply b'PONG:ping\\n'" in rig.console(), rig.console()
            digests.append(rig.trace_digest)
    assert digests[0] is not None and digests[0] == digests[1], digests


DIES = """#!{python}
import json
import sys

for text in sys.stdin:
    if json.loads(text)["op"] == "pins":
        sys.stderr.write("cannot serve a trigger\\n")
        sys.exit(3)
    print("{{}}", flush=True)
"""
ANSWERS = """#!{python}
import json
import sys

for text in sys.stdin:
    msg = json.loads(text)
    print(json.dumps({answer}) if msg["op"] == "pins" else "{{}}", flush=True)
"""


def test_a_program_that_dies_stops_the_run_naming_the_part_the_rig_file_and_its_exit(tmp_path):
    rig_file = project(tmp_path, DIES)
    with LiveRig.start(rig_file) as rig:
        with pytest.raises(ExternalError) as raised:
            rig.run_until(t_s=0.2)
    message = str(raised.value)
    assert message.startswith(f"{rig_file}: [[plant.parts]] #1 (dev): its program {tmp_path / 'dev.py'} ended"), message
    assert "exit status 3 (its stderr ends: cannot serve a trigger)" in message
    assert '"op": "pins", "levels": {"trig": 1}' in message


@pytest.mark.parametrize(
    ("answer", "said"),
    [
        ('{{"pins": [[msg["t_us"] + 10, "bell", 1]]}}', r"expected one of its pins_out \(echo, button\), got 'bell'"),
        ('{{"pins": [[msg["t_us"], "echo", 1]]}}', "expected instants after"),
        ('{{"pins": [[msg["t_us"] + 10, "echo", 2]]}}', r"expected \[t_us, pin, 0 or 1\] in pins"),
        ('{{"uart": [[msg["t_us"], "\\u20ac"]]}}', "expected .t_us, a list of bytes 0..255 or a text"),
        ('{{"until_us": 5}}', "expected until_us after"),
    ],
)
def test_a_plan_out_of_protocol_stops_the_run_saying_what_was_expected(tmp_path, answer, said):
    rig_file = project(tmp_path, ANSWERS.replace("{answer}", answer))
    with LiveRig.start(rig_file) as rig:
        with pytest.raises(
            ExternalError, match=rf"^{re.escape(str(rig_file))}: \[\[plant.parts\]\] #1 \(dev\): {said}"
        ):
            rig.run_until(t_s=0.2)


CLOCK_RIG = """
name = "external_clock"

[board]
family = "esp32"

[board.pins]
CLK = 4
LED = 5

[plant]
body = "bench"

[[plant.parts]]
kind = "external"
name = "dev"
command = "clock.py"
pins_in = ["led"]
pins_out = [["clk", 0]]

[wiring]
CLK = "dev.clk"
LED = "dev.led"
"""
CLOCK_MAIN = """
import time

from machine import Pin

T0 = time.ticks_us()


def now():
    return time.ticks_diff(time.ticks_us(), T0)


edges, outs = [], []
clk = Pin(4, Pin.IN)
clk.irq(lambda p: edges.append((now(), p.value())), Pin.IRQ_RISING | Pin.IRQ_FALLING)
led = Pin(5, Pin.OUT, value=0)
for i in range(1, 31):
    outs.append(now())
    led.value(i % 2)
    time.sleep_us(3700)
while True:
    time.sleep_ms(100)
"""
CLOCK = """#!{python}
# A clock with no end: high 2.5 ms, low 2.5 ms; its plan one period at a time (until_us).
import json
import sys

with open("seen.log", "w") as seen:
    for text in sys.stdin:
        msg = json.loads(text)
        seen.write(text)
        answer = {{}}
        if msg["op"] in ("reset", "more"):
            t_us = msg["t_us"]
            answer = {{"pins": [[t_us + 2500, "clk", 1], [t_us + 5000, "clk", 0]], "until_us": t_us + 5000}}
        print(json.dumps(answer), flush=True)
"""


def test_an_endless_plan_is_asked_for_more_once_an_instant_and_played_exactly_across_rewinds(tmp_path):
    (tmp_path / "rig.toml").write_text(CLOCK_RIG)
    (tmp_path / "main.py").write_text(textwrap.dedent(CLOCK_MAIN))
    script = tmp_path / "clock.py"
    script.write_text(CLOCK.format(python=sys.executable))
    script.chmod(0o755)
    with LiveRig.start(tmp_path / "rig.toml", artefacts=tmp_path / "trace") as rig:
        rig.run_until(t_us=150_000)
        edges, outs = rig.eval("edges"), rig.eval("outs")
    handles, records = trace_of(tmp_path / "trace")
    led = [r["t"] for r in records if r.get("msg") == "OUT" and r["handle"] == handles["dev.led"]][1:]
    offset = led[0] - outs[0]
    assert [t - o for t, o in zip(led, outs)] == [offset] * 30, (led, outs)
    assert rig.rig.stats.rollbacks > 0, "expected the LED's writes to rewind the plant's lookahead"
    # every edge the firmware saw, at its instant: the plan played exactly, whatever the rewinds
    expected = [(2500 * k, k % 2) for k in range(1, 45)]
    # the firmware's IRQ saw each edge, in order, never before its instant (a few late: the
    # shim's, test_an_edge_inside_a_state_fires_its_irq_at_its_instant below)
    assert [level for _, level in edges] == [level for _, level in expected], edges
    assert all(t + offset >= t_edge for (t, _), (t_edge, _) in zip(edges, expected)), edges
    assert changes_of(records, handles["dev.clk"])[: len(expected)] == expected
    # more asked at each period's end; asked again only after news from an earlier instant (a
    # LED's edge the lookahead had passed: the plan from there was the program's to give again)
    seen = [json.loads(line) for line in (tmp_path / "seen.log").read_text().splitlines()]
    mores = [m["t_us"] for m in seen if m["op"] == "more"]
    assert sorted(set(mores))[:29] == [5000 * k for k in range(1, 30)], mores
    last = -1
    for m in seen[1:]:
        if m["op"] == "more":
            assert m["t_us"] > last, f"expected no more asked twice without news between, got {mores}"
        last = m["t_us"] if m["op"] == "more" else -1
    assert len(mores) > len(set(mores)), "expected the rewinds to ask some more again after news"


BUTTON_RIG = """
name = "button_edge"

[board]
family = "esp32"

[board.pins]
BUTTON = 4
LED = 5

[plant]
body = "bench"

[[plant.parts]]
kind = "button"
name = "b"
presses = [[0.061020, 0.5]]

[[plant.parts]]
kind = "probe"
name = "led"

[wiring]
BUTTON = "b.out"
LED = "led.in"
"""
BUTTON_MAIN = """
import time

from machine import Pin

T0 = time.ticks_us()
presses = []
button = Pin(4, Pin.IN, Pin.PULL_UP)
button.irq(lambda p: presses.append(time.ticks_diff(time.ticks_us(), T0)), Pin.IRQ_FALLING)
led = Pin(5, Pin.OUT, value=0)
for i in range(3):
    time.sleep_ms(20)
    led.value(1)
    time.sleep_us(10)
    led.value(0)
time.sleep_us(999)
while True:
    time.sleep_ms(100)
"""


def test_an_edge_fires_its_irq_at_its_instant_or_after_an_esp32_sleep_us_tail(tmp_path):
    """A press during a sleep_ms fires the ESP32's IRQ at its instant; one in the last 155 us
    of a sleep_us(999) (ports/esp32/mphalport.c, mp_hal_delay_us: mp_handle_pending only
    while more than 150 + 5 us are left) fires when the sleep returns, at 61,029 us, as on
    the board (docs/shim.md, "Where callbacks run")."""
    (tmp_path / "rig.toml").write_text(
        BUTTON_RIG.replace("presses = [[0.061020, 0.5]]", "presses = [[0.030, 0.031], [0.061020, 0.5]]")
    )
    (tmp_path / "main.py").write_text(textwrap.dedent(BUTTON_MAIN))
    with LiveRig.start(tmp_path / "rig.toml") as rig:
        rig.run_until(t_us=200_000)
        assert rig.eval("presses") == [30_000, 61_029], rig.eval("presses")


def test_checking_the_rig_file_never_starts_the_program(tmp_path):
    rig_file = project(tmp_path)
    result = subprocess.run([sys.executable, "-m", "host.cli", "check", str(rig_file)], capture_output=True, text=True)
    assert result.returncode == 0, result.stderr
    assert "dev.echo (level), dev.button (level), dev.uart (bytes)" in result.stdout, result.stdout
    started = sorted(p.name for p in tmp_path.iterdir() if p.name in ("pid", "seen.log"))
    assert started == [], f"expected mpy-fil check to start no program, found {started} in {tmp_path}"


def test_no_program_of_these_tests_outlives_its_rig(tmp_path_factory):
    """(last in this file) No child of this process still runs a script of these tests."""
    scripts = ("dev.py", "clock.py", "chip.py")
    left = []
    for proc in Path("/proc").iterdir():
        if not proc.name.isdigit():
            continue
        try:
            ppid = int((proc / "stat").read_text().rsplit(")", 1)[1].split()[1])
            cmdline = (proc / "cmdline").read_bytes().decode(errors="replace")
        except (OSError, ValueError, IndexError):
            continue
        if ppid == os.getpid() and any(s in cmdline for s in scripts) and alive(int(proc.name)):
            left.append(f"{proc.name}: {cmdline}")
    assert left == [], f"expected no program left after its rig stopped, found {left}"

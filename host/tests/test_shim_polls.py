"""A poll that never ends, named, of the pins and memory the shim reads itself (host/shim/
_hilpoll.py, host/rig/hardware/pollwatch.py): a pin nothing drives, an RP2040 register and a word of
plain memory through machine.mem32, each named once in the run's output with the answer,
since when, how many reads and what would change it, beside a chip's data-ready bit (a
bus poll); a button polled until a press that comes within the span is not named."""

import re

import pytest

from host.rig.loop.rig import run_header
from host.tests.conftest import FIRMWARE, bench_app, results

pytestmark = pytest.mark.hil

RP2040 = ("rp2", "Raspberry Pi Pico with RP2040")
ESP32 = ("esp32", "Generic ESP32 module with ESP32")
PLANT = {
    "body": "differential",
    "parts": [
        {"kind": "dc_motor", "name": "motor_l", "bridge": "tb6612", "drives": "left"},
        {"kind": "dc_motor", "name": "motor_r", "bridge": "tb6612", "drives": "right"},
        {"kind": "button", "name": "start", "presses": [[0.5, 0.6]]},
        {"kind": "button", "name": "stop"},
        {"kind": "lis3mdl", "name": "compass", "bus": "i2c0"},
    ],
}
PINS = {"BUTTON": 2, "STOP": 4}
WIRING = {"BUTTON": "start.out", "STOP": "stop.out"}
SPAN = re.compile(r"(\d+) times from virtual t=([\d.]+) s to t=([\d.]+) s and got (\S+) each time")


def run(make_rig, identity):
    app = bench_app("polls_forever", PLANT, board="pins", identity=identity, pins=PINS, wiring=WIRING)
    rig = make_rig(app, main_dir=FIRMWARE / "polls_forever", allow_exit=True)
    rig.run_for(7.0)
    rig.stop()
    return rig, results(rig.console), [text for _t, text in rig.bus_trace.notes if "a poll that never ends" in text]


def named(notes, what, r, rig):
    """The one note naming ``what``, its reads within the firmware's and over the span."""
    hits = [text for text in notes if what in text]
    assert len(hits) == 1, (
        f"expected one note naming {what!r}, got {hits}; all notes: {notes}; artefacts: {rig.artefacts}"
    )
    reads, since, t, answer = SPAN.search(hits[0]).groups()
    assert 10_000 <= int(reads) <= r[1], (hits[0], r)
    assert float(t) - float(since) >= 1.0, hits[0]
    return hits[0], answer


def test_a_pin_nothing_drives_a_register_and_plain_memory_polled_for_ever_are_each_named_once(make_rig):
    rig, r, notes = run(make_rig, RP2040)
    # the button's wait ended at its press (tens of thousands of reads, but within 0.5 s)
    assert r["button"][0] == 0 and r["button"][1] > 10_000 and 500_000 <= r["button"][2] < 501_000, r
    assert not [n for n in notes if "pin BUTTON" in n], notes
    for name in ("idle", "gpio_in", "sram", "zyxda"):
        assert r[name][2] > 1_100_000, (name, r)
    text, answer = named(notes, "pin 6 with Pin.value()", r["idle"], rig)
    assert answer == "1" and "wired to nothing in the rig, so nothing drives it" in text, text
    # the firmware's stack, from the harness's build (_hilfast.stack): its own frames, not the shim's
    assert 'main.py", line' in text and "in spin" in text and "_hil" not in text.split("stack")[-1], text
    text, answer = named(notes, "machine.mem32[0xd0000004]", r["gpio_in"], rig)
    assert int(answer, 16) == 1 << 2 | 1 << 6, text  # (the released button's and GPIO6's pull-ups)
    assert "the simulated RP2040's SIO GPIO_IN: the pads' levels, which the plant drives" in text, text
    text, answer = named(notes, "machine.mem32[0x20001000]", r["sram"], rig)
    assert answer == "0x00000000" and "no register of the simulated RP2040 there" in text, text
    assert "i2c0 0x1c register 0x27" in " ".join(notes) and "compass (Lis3mdlChip)" in " ".join(notes), notes
    bus = [n for n in notes if "i2c0 0x1c register 0x27" in n]
    assert len(bus) == 1 and 'main.py", line' in bus[0] and "in spin" in bus[0], bus  # (the shim's stack, asked)
    assert len(notes) == 4, notes
    assert [n["text"] for n in run_header(rig)["notes"]] == [text for _t, text in rig.bus_trace.notes]
    console_log = (rig.artefacts / "console.log").read_text()
    assert console_log.count("a poll that never ends") == 4, console_log[-3000:]


def test_a_driven_pin_names_its_part_and_an_esp32s_memory_is_plain(make_rig):
    rig, r, notes = run(make_rig, ESP32)
    text, answer = named(notes, "pin STOP (4) with Pin.value()", r["stop"], rig)
    assert answer == "1" and "button stop drives it (stop.out), and kept it at 1" in text, text
    assert "a scenario's set-control of stop's pressed changes it" in text, text
    text, answer = named(notes, "machine.mem32[0x3ff4403c]", r["gpio_in_reg"], rig)
    assert answer == "0x00000000", text
    assert "no register of the simulated Generic ESP32 module with ESP32 is modelled" in text, text
    assert len(notes) == 2, notes

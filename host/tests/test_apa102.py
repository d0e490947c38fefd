"""The apa102_strip part (docs/parts.md) on SPI: a DotStar driver written as the public
MicroPython ones are (no published one on the package index: host/tests/firmware/apa102_strip)
sets colours and brightness the strip's outputs show over time; frames split over writes
land; a stray byte where a frame starts is a counted fault; the report draws the colours."""

from pathlib import Path

import numpy as np
import pytest

from host.artefacts.folder import TraceData
from host.report import part_views
from host.tests.conftest import FIRMWARE, bench_app, results
from sim_plant import buses as B
from sim_plant.catalogue.assembly import assemble

STRIP = {"body": "bench", "parts": [{"kind": "apa102_strip", "name": "leds", "bus": "spi1", "count": 3}]}


def outputs(plant, what, n=3):
    return tuple(plant.output(f"leds.{what}{i}") for i in range(n))


@pytest.mark.hil
def test_a_dotstar_driver_sets_colours_and_brightness_the_strip_shows_over_time(make_rig):
    rig = make_rig(bench_app("apa102", STRIP), main_dir=FIRMWARE / "apa102_strip", allow_exit=True)
    seen = []
    for step in (0.05, 0.1, 0.1):
        rig.run_for(step)
        seen.append((outputs(rig.plant, "led"), outputs(rig.plant, "level")))
    rig.run_for(0.1)
    truth = rig.plant.truth()
    rig.stop()
    assert results(rig.console).get("done") == 1, rig.console
    assert seen[0] == ((0xFF0000, 0x00FF00, 0x0000FF), (31, 31, 31)), seen
    assert seen[1] == ((0x101010,) * 3, (4, 4, 4)), seen
    assert seen[2] == ((0x030201, 0x101010, 0x101010), (31, 4, 4)), "the start frame split over two writes"
    assert truth["leds_faults"] == 1 and truth["leds_frames"] == 7 and truth["leds_lit"] == 3


def spi(p, data):
    assert p.bus_transfer("spi1", B.SPI_XFER, 0, 0, bytes(data))[0] == B.OK


def test_an_end_frame_of_ones_past_the_last_led_leaves_the_strip_and_one_short_paints_the_next_led():
    p = assemble(STRIP)
    spi(p, [0] * 4 + [0xE5, 1, 2, 3] + [0xFF] * 8)  # one LED, then eight bytes of ones: LEDs 1 and 2
    p.advance_to(10)
    assert outputs(p, "led") == (0x030201, 0xFFFFFF, 0xFFFFFF) and outputs(p, "level") == (5, 31, 31)
    spi(p, [0] * 4 + [0xE1, 0, 0, 0] * 3 + [0xFF] * 4)  # three LEDs off, the end frame past the last
    p.advance_to(20)
    assert outputs(p, "led") == (0, 0, 0) and p.truth()["leds_lit"] == 0 and p.truth()["leds_faults"] == 0


def test_nothing_shows_before_a_start_frame_and_three_zero_bytes_inside_a_frame_are_not_one():
    p = assemble(STRIP)
    spi(p, [0xE7, 9, 9, 9])
    p.advance_to(10)
    assert outputs(p, "led") == (0, 0, 0), "no start frame yet"
    spi(p, [0] * 4 + [0xE7, 0, 0, 0, 0xE7, 0, 0, 5])
    p.advance_to(20)
    assert outputs(p, "led") == (0, 0x050000, 0) and outputs(p, "level") == (7, 7, 0)


def test_the_report_draws_each_leds_colour_and_not_its_brightness():
    plant = assemble(STRIP)
    header = {"app": "strip", "parts": plant.describe(), "initial": {}, "t_end_us": 1_000_000}
    events = [(10, "leds.led0", 0xFF0000), (10, "leds.level0", 31), (500_000, "leds.led1", 0x00FF00)]
    truth = {"t_us": np.asarray([0, 500_000])}
    panels = part_views.part_panels(TraceData(Path("."), header, events, truth, []))
    (strip,) = [p for p in panels if p.title.startswith("LED strips")]
    assert [line.label for line in strip.lines] == ["leds.led0", "leds.led1", "leds.led2"]
    assert list(strip.lines[0].values) == [0, 0xFF0000] and strip.lines[0].style == "colours"

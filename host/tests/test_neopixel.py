"""machine.bitstream and neopixel.NeoPixel in the loop (docs/shim.md, "Buses"): a firmware
written as MicroPython's docs show drives a ws2812_strip part; the LEDs' colours over
time are the strip's outputs (in the trace); the stream takes its time at the WS2812's
bit rate; a 400 kHz timing on this strip is counted as out of tolerance."""

import pytest

from host.tests.conftest import FIRMWARE, bench_app, results

pytestmark = pytest.mark.hil

STRIP = {"body": "bench", "parts": [{"kind": "ws2812_strip", "name": "leds", "count": 4}]}


def test_neopixel_writes_colours_the_strip_shows_over_time(make_rig):
    app = bench_app("neopixel", STRIP, wiring={"LED_DIN": "leds.din"}, pins={"LED_DIN": 13})
    rig = make_rig(app, main_dir=FIRMWARE / "neopixel_strip", allow_exit=True)
    seen = []
    for _ in range(4):
        rig.run_for(0.1)
        seen.append(tuple(rig.plant.output(f"leds.led{i}") for i in range(4)))
    truth = rig.plant.truth()
    strip = rig.plant.input_owner("leds.din")
    rig.stop()
    r = results(rig.console)
    assert r.get("done") == 1, rig.console
    assert seen[0] == (0xFF0000, 0x00FF00, 0x0000FF, 0), seen
    assert seen[1] == (0x101010,) * 4, seen
    assert seen[2] == (0xFFFFFF,) * 4, "the 400 kHz stream's every bit reads as a 1 on a WS2812"
    assert r["write_us"] == 120, "12 bytes at 1.25 us a bit"
    assert r["pixel1"] == (0, 255, 0) and r["len"] == 4
    assert r["encoding"] == "encoding"
    assert truth["leds_timing_faults"] == 1 and truth["leds_writes"] == 3
    assert "high_0 800 ns" in strip.timing_problem

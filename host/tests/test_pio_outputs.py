"""What PIO drives reaches the plant (docs/shim.md, "PIO"): a PIO PWM's pulses timed by
time_pulse_us through a wire, a PIO WS2812 strip showing what neopixel shows on another, a
PIO UART TX read by machine.UART through a UART wire. The programs are MicroPython's
examples/rp2 ones (host/tests/firmware/pio_outputs)."""

import pytest

from host.tests.conftest import FIRMWARE, bench_app, results

pytestmark = pytest.mark.hil

PLANT = {
    "body": "bench",
    "parts": [
        {"kind": "wire", "name": "w0"},
        {"kind": "uart_wire", "name": "u0"},
        {"kind": "ws2812_strip", "name": "pio_leds", "count": 4},
        {"kind": "ws2812_strip", "name": "np_leds", "count": 4},
    ],
}
PINS = {"PWM_OUT": 4, "PWM_IN": 5, "PIO_LEDS": 12, "NP_LEDS": 18, "PIO_TX": 0, "U0_UART": 0}
WIRING = {
    "PWM_OUT": "w0.in",
    "PWM_IN": "w0.out",
    "PIO_LEDS": "pio_leds.din",
    "NP_LEDS": "np_leds.din",
    "PIO_TX": "u0.line",
    "U0_UART": "u0.line",
}


@pytest.fixture(scope="module")
def outcome(request):
    from host.pytest_plugin import rig_from_keywords

    app = bench_app("pio_outputs", PLANT, board="rpi_pico_bench", wiring=WIRING, pins=PINS)
    rig = rig_from_keywords(app, main_dir=FIRMWARE / "pio_outputs")
    rig.start()
    try:
        rig.run_for(0.2)
        leds = {s: [rig.plant.output(f"{s}.led{i}") for i in range(4)] for s in ("pio_leds", "np_leds")}
        truth = rig.plant.truth()
        console = rig.console
    finally:
        rig.stop()
    return results(console), leds, truth, console


def test_pio_pwm_pulses_are_timed_by_time_pulse_us_within_one_pio_clock(outcome):
    r, _leds, _truth, console = outcome
    assert r.get("done") == 1, console
    # (the first high pulse timed is the one under way when the PWM's duty was put)
    assert all(abs(h - 62) <= 1 for h in r["pwm_high_us"][1:]), r["pwm_high_us"]  # 62 cycles at 1 MHz
    assert all(abs(lo - 144) <= 1 for lo in r["pwm_low_us"]), r["pwm_low_us"]  # 206 - 62


def test_a_pio_ws2812_strip_shows_what_neopixel_shows(outcome):
    _r, leds, truth, _console = outcome
    assert leds["np_leds"] == [0xFF0000, 0x00FF00, 0x0000FF, 0x101010]
    assert leds["pio_leds"] == leds["np_leds"]
    assert truth["pio_leds_writes"] >= 1 and truth["pio_leds_timing_faults"] == 0, truth


def test_a_pio_uart_tx_is_read_by_a_plant_uart(outcome):
    r, _leds, _truth, console = outcome
    assert r["uart"] == b"PIO says hi\n", console

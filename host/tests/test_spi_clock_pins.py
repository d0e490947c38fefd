"""Parts sharing one SPI controller's MOSI, each clocked on a pin of its own (a kit's
display and LEDs on SPI0: docs/wiring.md): a transfer reaches a chip only while its clock
pin (its ``sck`` input, wired) is in the SPI function at that instant, as IO_BANK0's FUNCSEL
says, however the firmware set it (host/tests/firmware/spi_clock_pins): the SPI
constructor, Pin.ALT with alt=1, a FUNCSEL write through mem32; a GPIO output, or another
function, clocks nothing. A chip whose clock input is not wired hears every transfer on
its bus."""

import pytest

from host.tests.conftest import FIRMWARE, bench_app, results

pytestmark = pytest.mark.hil

RP2040 = ("rp2", "Raspberry Pi Pico with RP2040")
STRIPS = [{"kind": "apa102_strip", "name": n, "bus": "spi0", "count": 1} for n in ("a", "b", "any")]
PLANT = {"body": "bench", "parts": STRIPS}
PINS = {"SCK_A": 2, "SCK_B": 6}
WIRING = {"SCK_A": "a.sck", "SCK_B": "b.sck"}  # (strip "any": its clock input wired to nothing)


def test_a_transfer_reaches_the_chips_whose_clock_pin_is_the_spis_at_that_instant(make_rig):
    app = bench_app("spi_clock_pins", PLANT, board="pins", identity=RP2040, wiring=WIRING, pins=PINS)
    rig = make_rig(app, main_dir=FIRMWARE / "spi_clock_pins", allow_exit=True)
    rig.run_for(0.05)
    truth = rig.truth()
    shown = {n: rig.plant.output(f"{n}.led0") for n in ("a", "b", "any")}
    rig.stop()
    r = results(rig.console)
    where = f"console:\n{rig.console}\nartefacts: {rig.artefacts}"
    assert r.get("done") == 1, f"the firmware did not finish; {where}"
    # frames 1..6: a saw 1, 3, 5; b saw 2, 3; the unwired strip every one
    assert truth["a_frames"] == 3 and shown["a"] == 5, (truth, shown, where)
    assert truth["b_frames"] == 2 and shown["b"] == 3, (truth, shown, where)
    assert truth["any_frames"] == 6 and shown["any"] == 6, (truth, shown, where)
    assert truth["a_faults"] == truth["b_faults"] == truth["any_faults"] == 0, truth
    assert r["funcsel"] == [5, 2], "FUNCSEL of GP2 (SIO) and GP6 (UART) as the firmware left them"

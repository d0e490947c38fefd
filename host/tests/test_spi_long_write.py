"""An SPI write longer than one link frame (a colour display's frame buffer: the Pico-Go's
ST7789 demos send 64,800 bytes in one ``spi.write``) goes out whole, in order, in the time
its bytes take at the baud rate, as ``mp_machine_spi_write`` clocks out any length on a
board; it raised ``ValueError: payload of 64815 bytes exceeds 4096`` from the link's codec."""

import pytest

from host.core.drivers import driver_folder
from host.tests.conftest import FIRMWARE, bench_app, results

pytestmark = pytest.mark.hil

PLANT = {"body": "bench", "parts": [{"kind": "ssd1306", "name": "panel", "bus": "spi1", "spi": True, "height": 32}]}


def test_an_spi_write_longer_than_a_frame_reaches_the_device_whole_and_in_order(make_rig):
    app = bench_app(
        "spi_long_write",
        PLANT,
        lib_dirs=(driver_folder("micropython-ssd1306"),),
        wiring={"OLED_DC": "panel.dc", "OLED_RES": "panel.res", "OLED_CS": "panel.cs"},
        pins={"OLED_DC": 4, "OLED_RES": 5, "OLED_CS": 15},
    )
    rig = make_rig(app, main_dir=FIRMWARE / "spi_long_write", allow_exit=True)
    rig.run_for(0.2)
    panel = next(p for p in getattr(rig.plant, "inner", rig.plant).parts if getattr(p, "label", "") == "panel")
    picture = panel.picture()
    rig.stop()
    r = results(rig.console)
    n = r["n"]
    assert n > 2 * 4096, rig.console
    data = [(i * 7 + i // 512) & 0xFF for i in range(n)]
    last = [data[max(i for i in range(a, n, 512))] for a in range(512)]  # each address's last byte
    expected = bytes(last[(y >> 3) * 128 + x] >> (y & 7) & 1 for y in range(32) for x in range(128))
    assert picture == expected, "the panel holds each address's last byte of the 9,000 written, in order"
    spent = n * 8 / (10 * 1024 * 1024) * 1e6  # (the driver sets its SPI to 10 MiHz before each write)
    assert spent <= r["us"] <= spent + 200, f"the write took {r['us']} us of virtual time, expected {spent:.0f} us"

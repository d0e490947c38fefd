"""Chip select as the silicon has it (docs/parts.md, docs/reliability.md "Chip select"):
active low, one selection from its fall to its rise however many transfers it spans; a
rig can tie a part's CS low (``cs = "low"``); ``check`` warns of an SPI part whose CS is
neither wired nor tied."""

import pytest

from host.core.drivers import driver_folder
from host.core.errors import ConfigError
from host.rig.config.rigfile import load_rig
from host.rig.scan.pincheck import check_pins
from host.tests.conftest import FIRMWARE, bench_app, results
from sim_plant import buses as B
from sim_plant.catalogue.assembly import assemble

PINS = {"OLED_DC": 4, "OLED_RES": 5, "CS_HOLD": 15, "DRIVER_CS": 16}


def vlsb_rows(buffer: list, width: int, height: int) -> bytes:
    return bytes(buffer[(y >> 3) * width + x] >> (y & 7) & 1 for y in range(height) for x in range(width))


def oled_plant(**options) -> dict:
    part = {"kind": "ssd1306", "name": "small", "bus": "spi1", "spi": True, "height": 32}
    return {"body": "bench", "parts": [{**part, **options}]}


def run_oled(make_rig, tmp_path, cs_pin: str | None, **options):
    wiring = {"OLED_DC": "small.dc", "OLED_RES": "small.res"}
    if cs_pin:
        wiring[cs_pin] = "small.cs"
    app = bench_app(
        "oled_cs_low", oled_plant(**options), lib_dirs=(driver_folder("micropython-ssd1306"),), wiring=wiring, pins=PINS
    )
    rig = make_rig(app, main_dir=FIRMWARE / "oled_cs_low", allow_exit=True, artefacts=tmp_path / (cs_pin or "tied"))
    rig.run_for(0.5)
    small = next(p for p in getattr(rig.plant, "inner", rig.plant).parts if getattr(p, "label", "") == "small")
    truth = rig.plant.truth()
    rig.stop()
    r = results(rig.console)
    assert r["same"] == 1, rig.console
    return small.display_frames()[2], truth, vlsb_rows(r["ref"], 128, 32)


@pytest.mark.hil
def test_an_ssd1306_whose_cs_is_held_low_or_tied_low_draws_what_it_draws_with_cs_toggled(make_rig, tmp_path):
    toggled, toggled_truth, expected = run_oled(make_rig, tmp_path, "DRIVER_CS")
    held, held_truth, _ = run_oled(make_rig, tmp_path, "CS_HOLD")
    tied, tied_truth, _ = run_oled(make_rig, tmp_path, None, cs="low")
    assert sum(expected) > 30
    assert toggled[-1][1] == expected, "with CS toggled the glass shows what framebuf drew"
    assert held[-1][1] == expected, "with CS held low by the firmware: the same picture"
    assert tied[-1][1] == expected, "with CS tied low by the rig: the same picture"
    pictures = [[p for _t, p in frames] for frames in (toggled, held, tied)]
    assert pictures[0] == pictures[1] == pictures[2], "the same pictures in the same order"
    assert toggled_truth["small_lit_px"] == held_truth["small_lit_px"] == tied_truth["small_lit_px"] == sum(expected)


def spi_plant(kind: str, **options):
    return assemble({"body": "bench", "parts": [{"kind": kind, "name": "chip", "bus": "spi1", "spi": True, **options}]})


def test_a_register_chip_takes_its_register_address_only_as_the_first_byte_after_cs_falls():
    plant = spi_plant("lsm6dsox")
    plant.set_input("chip.cs", 0)
    assert plant.bus_transfer("spi1", B.SPI_XFER, 0, 0, b"\x8f\x00")[2][1] == 0x6C  # WHO_AM_I
    # CS still low: the next transfer goes on reading from 0x10, its first byte no address
    assert plant.bus_transfer("spi1", B.SPI_XFER, 0, 0, b"\x8f\x00")[2] != b"\x00\x6c"
    plant.set_input("chip.cs", 1)
    plant.set_input("chip.cs", 0)
    assert plant.bus_transfer("spi1", B.SPI_XFER, 0, 0, b"\x8f\x00")[2][1] == 0x6C, "a new selection, a new address"


def test_a_register_chip_with_cs_tied_low_is_selected_from_power_on_with_no_cs_input():
    plant = spi_plant("lsm6dsox", cs="low")
    assert "chip.cs" not in plant.inputs
    assert plant.bus_transfer("spi1", B.SPI_XFER, 0, 0, b"\x8f\x00")[2][1] == 0x6C
    assert "chip.cs" in spi_plant("lsm6dsox").inputs


def test_cs_low_is_refused_on_an_i2c_part():
    with pytest.raises(Exception, match=r'cs: expected "pin" on I2C bus i2c0'):
        assemble({"body": "bench", "parts": [{"kind": "mpu6050", "name": "imu", "cs": "low"}]})


RIG = """
[firmware]
dir = "."

[board]
family = "esp32"

[board.pins]
OLED_DC = 4
OLED_RES = 5
CS_HOLD = 15
DRIVER_CS = 16

[plant]
body = "bench"

[[plant.parts]]
kind = "ssd1306"
name = "small"
bus = "spi1"
spi = true
height = 32
{tie}
[wiring]
OLED_DC = "small.dc"
OLED_RES = "small.res"
{cs}
"""


def rig_file(tmp_path, tie: str = "", cs: str = ""):
    (tmp_path / "main.py").write_text((FIRMWARE / "oled_cs_low" / "main.py").read_text())
    (tmp_path / "rig.toml").write_text(RIG.format(tie=tie, cs=cs))
    return load_rig(tmp_path / "rig.toml")


def cs_warnings(app) -> list:
    return [w for w in check_pins(app, app.make_plant()).warnings if "chip select" in w]


def test_check_warns_of_an_spi_part_whose_cs_is_neither_wired_nor_tied(tmp_path):
    (warning,) = cs_warnings(rig_file(tmp_path))
    assert "wires no pin to small.cs, the chip select of small on spi1" in warning
    assert 'cs = "low"' in warning


def test_check_is_quiet_of_a_cs_wired_or_tied_low_in_the_rig_file(tmp_path):
    assert cs_warnings(rig_file(tmp_path, cs='CS_HOLD = "small.cs"')) == []
    app = rig_file(tmp_path, tie='cs = "low"')
    assert cs_warnings(app) == []
    assert "small.cs" not in app.make_plant().inputs, "tied low: no cs input to wire"


def test_a_rig_that_wires_a_pin_to_a_cs_it_ties_low_is_refused_naming_both(tmp_path):
    with pytest.raises(
        ConfigError, match=r'\[wiring\] CS_HOLD: .*small.cs.* ties low \(cs = "low" in \[\[plant.parts\]\] small\)'
    ):
        rig_file(tmp_path, tie='cs = "low"', cs='CS_HOLD = "small.cs"')

"""1-Wire in the loop (docs/shim.md, "1-Wire"; docs/parts.md, ``ds18b20``): the port's
``_onewire`` primitives in virtual time at modonewire.c's slot timings, ``onewire`` and
``ds18x20`` importable as the ports freeze them, a DS18B20 part with its ROM, scratchpad,
CRCs and conversion time per resolution, and a clear error on a pin with no part."""

import pytest

from host.tests.conftest import results
from sim_plant.catalogue.ds18b20 import crc8, raw_temperature, rom_of

pytestmark = pytest.mark.hil

RIG = """
name = "ds18b20_bench"
[firmware]
entry = "main.py"
allow_exit = true
[board]
name = "{board}"
[plant]
body = "bench"
{parts}
[wiring]
"""
PART = """
[[plant.parts]]
kind = "ds18b20"
name = "probe"
bus = "onewire:{pin}"
temperature_c = {t}
serial = 0x0123456789AB
"""

# As the public DS18B20 examples are written (docs.micropython.org, esp32 quickref).
EXAMPLE = """
import time, machine, onewire, ds18x20
ds = ds18x20.DS18X20(onewire.OneWire(machine.Pin(PIN)))
roms = ds.scan()
print("R roms", [bytes(r) for r in roms])
print("R kinds", [type(r).__name__ for r in roms])
for rom in roms:
    ds.convert_temp()
    time.sleep_ms(750)
    print("R temp", ds.read_temp(rom))
"""

TIMING = """
import time, machine, onewire, ds18x20, _onewire
pin = machine.Pin(4)
ow = onewire.OneWire(pin)
ds = ds18x20.DS18X20(ow)
rom = ds.scan()[0]
print("R crc_rom", ow.crc8(rom))
t0 = time.ticks_us(); _onewire.reset(pin); t1 = time.ticks_us(); _onewire.readbyte(pin); t2 = time.ticks_us()
_onewire.writebit(pin, 1); t3 = time.ticks_us()
print("R slots", (time.ticks_diff(t1, t0), time.ticks_diff(t2, t1), time.ticks_diff(t3, t2)))
for bits in (9, 10, 11, 12):
    ds.write_scratch(rom, bytes((0x4B, 0x46, (bits - 9) << 5 | 0x1F)))
    ds.convert_temp()
    t0 = time.ticks_us()
    while not ow.readbit():
        time.sleep_us(500)
    print("R conv%d" % bits, (time.ticks_diff(time.ticks_us(), t0), ds.read_temp(rom)))
pad = ds.read_scratch(rom)
print("R pad", (bytes(pad), ow.crc8(pad)))
ds.convert_temp()
time.sleep_ms(10)
print("R early", ds.read_temp(rom))
"""

EMPTY = """
import machine, onewire, ds18x20
ow = onewire.OneWire(machine.Pin(4))
print("R reset", ow.reset())
print("R scan", ds18x20.DS18X20(ow).scan())
try:
    ds18x20.DS18X20(ow).convert_temp()
except onewire.OneWireError as e:
    print("R error", repr(str(e)))
"""


def _run(make_rig, tmp_path, firmware: str, parts: str, seconds: float = 5.0, board="esp32_devkitc", pin=4):
    (tmp_path / "main.py").write_text(firmware.replace("PIN", str(pin)))
    (tmp_path / "rig.toml").write_text(RIG.format(parts=parts.replace("{pin}", str(pin)), board=board))
    rig = make_rig(str(tmp_path))
    rig.run_for(seconds)
    return results(rig.console), rig.console


def test_the_rom_and_scratchpad_carry_the_datasheets_crc():
    rom = rom_of(0x0123456789AB)
    assert rom[0] == 0x28 and rom[1:7] == bytes.fromhex("AB8967452301") and crc8(rom) == 0
    # (the Maxim application note 27's worked example: 02 1C B8 01 00 00 00, CRC A2)
    assert crc8(bytes.fromhex("021CB801000000")) == 0xA2
    assert raw_temperature(22.5, 12) == 0x0168 and raw_temperature(-10.125, 12) == 0xFF5E
    assert raw_temperature(22.5625, 9) == 0x0168  # (9 bits: half degrees, the rest 0)


@pytest.mark.parametrize("board, pin", [("esp32_devkitc", 4), ("rpi_pico", 22)])
def test_a_public_ds18b20_example_reads_the_parts_temperature(make_rig, tmp_path, board, pin):
    r, console = _run(make_rig, tmp_path, EXAMPLE, PART.replace("{t}", "23.4375"), board=board, pin=pin)
    assert r.get("roms") == [rom_of(0x0123456789AB)] and r["kinds"] == ["bytearray"], console[-2000:]
    assert r["temp"] == 23.4375, console[-2000:]


def test_conversion_time_follows_the_resolution_and_the_scratchpad_crc_is_checked(make_rig, tmp_path):
    r, console = _run(make_rig, tmp_path, TIMING, PART.replace("{t}", "-10.1875"))
    assert r.get("crc_rom") == 0, console[-2000:]
    assert r["slots"] == (960, 560, 70)  # modonewire.c: 480 + 70 + 410; 8 x (6 + 9 + 55); 6 + 54 + 10
    # (the bits below the resolution read 0: two's complement, so a negative value rounds down)
    for bits, conv_us, temp in (
        (9, 93_750, -10.5),
        (10, 187_500, -10.25),
        (11, 375_000, -10.25),
        (12, 750_000, -10.1875),
    ):
        took, got = r["conv%d" % bits]
        assert conv_us <= took <= conv_us + 1_500, (bits, took)
        assert got == temp, (bits, got)
    pad, check = r["pad"]
    assert check == 0 and pad[4] == 0x7F and crc8(pad[:8]) == pad[8]
    assert r["early"] == -10.1875  # (10 ms into a conversion: the last one's value)


def test_a_pin_with_no_part_has_no_presence_and_says_what_the_bus_needs(make_rig, tmp_path):
    r, console = _run(make_rig, tmp_path, EMPTY, "", 2.0)
    assert r.get("reset") is False and r["scan"] == [], console[-2000:]
    assert "needs a ds18b20 part wired to that pin" in r["error"] and 'bus = "onewire:4"' in r["error"]


def test_check_takes_a_onewire_pin_as_the_parts_line_not_an_unwired_pin(tmp_path):
    from host.rig.config.rigfile import load_rig
    from host.rig.scan.pincheck import check_pins

    (tmp_path / "main.py").write_text(EXAMPLE.replace("PIN", "4"))
    part = PART.replace("{t}", "20").replace("{pin}", "4")
    (tmp_path / "rig.toml").write_text(RIG.format(parts=part, board="esp32_devkitc"))
    app = load_rig(tmp_path / "rig.toml")
    assert check_pins(app, app.make_plant()).warnings == []


class _Controls:
    def __init__(self, at_us, value):
        self.at_us, self.value = at_us, value

    def value_at(self, label, name, t_us, default):
        assert (label, name) == ("probe", "temperature")
        return self.value if t_us >= self.at_us else default


def test_a_scenarios_temperature_control_is_what_the_next_conversion_reads():
    from sim_plant.catalogue.ds18b20 import READ_BYTE, RESET, WRITE_BYTE, Ds18b20Chip

    chip = Ds18b20Chip("probe", "onewire:4", rom_of(1), 20.0, _Controls(1_000_000, 31.25))

    def op(t, code, value=None):
        chip.begin(t, False)
        chip.write(t, code)
        if value is not None:
            chip.write(t, value)
        return chip.read(t)

    def convert_and_read(t):
        op(t, RESET), op(t, WRITE_BYTE, 0xCC), op(t, WRITE_BYTE, 0x44)
        t += 800_000
        op(t, RESET), op(t, WRITE_BYTE, 0xCC), op(t, WRITE_BYTE, 0xBE)
        pad = bytes(op(t, READ_BYTE) for _ in range(9))
        assert crc8(pad) == 0
        return (pad[1] << 8 | pad[0]) / 16

    assert convert_and_read(0) == 20.0
    assert convert_and_read(2_000_000) == 31.25


def test_a_traced_onewire_slot_lasts_modonewires_time_and_reads_as_text():
    from host.link import frames as F
    from host.rig.hardware.bustrace import describe, transaction

    reset = transaction(0, "onewire:4", 1, F.BUS_XFER, 0x40, 1, b"\x00", F.BUS_OK, 1, b"\x01")
    assert (reset.duration_us, describe(reset)) == (960, "reset: presence (960 us)")
    write = transaction(0, "onewire:4", 1, F.BUS_XFER, 0x40, 0, b"\x02\xcc", F.BUS_OK, 2, b"")
    assert describe(write) == "write byte cc (560 us)"
    read = transaction(0, "onewire:4", 1, F.BUS_XFER, 0x40, 1, b"\x03", F.BUS_OK, 1, b"\x01")
    assert describe(read) == "read bit 01 (70 us)"
    empty = transaction(0, "onewire:4", 1, F.BUS_XFER, 0x40, 1, b"\x00", F.BUS_NACK_ADDRESS, 0, b"")
    assert describe(empty) == "reset (no device) (960 us)"

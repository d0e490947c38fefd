"""The vl53l0x part (sim_plant/catalogue/vl53l0x.py) played as the shim's BUS frames play
it: the identification registers, a single measurement ready after the timing budget
with the wall's range along the mount's ray, no target beyond max_m, back-to-back
measurements, the start-up handshakes, and the refusals."""

import pytest

from sim_plant import buses as B
from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError

MOTORS = [{"kind": "dc_motor", "name": f"motor_{s[0]}", "bridge": "tb6612", "drives": s} for s in ("left", "right")]


def plant(pose=(2.0, 1.0, 0.0), **options):
    tof = {"kind": "vl53l0x", "name": "tof", "bus": "i2c0", "mount": {"x_m": 0.05}, **options}
    return assemble({"body": "differential", "start_pose": list(pose), "parts": [*MOTORS, tof]})


def read(p, reg, n=1):
    status, _acks, got = p.bus_transfer("i2c0", B.XFER, 0x29, n, bytes((reg,)))
    assert status == B.OK
    return got


def write(p, reg, value):
    assert p.bus_transfer("i2c0", B.XFER, 0x29, 0, bytes((reg, value)))[0] == B.OK


def range_mm(p) -> int:
    return int.from_bytes(read(p, 0x1E, 2), "big")


def test_identification_registers_read_as_the_chips():
    p = plant()
    assert read(p, 0xC0, 3) == b"\xee\xaa\x10"
    assert read(p, 0x83)[0] != 0 and read(p, 0x92) == b"\x85"


def test_a_single_measurement_is_ready_after_the_budget_with_the_walls_range():
    p = plant()  # the room's wall at x = 3 m; the chip 5 cm ahead of the body's centre at x = 2 m
    write(p, 0x00, 0x01)
    assert read(p, 0x00) == b"\x00", "SYSRANGE_START's bit 0 clears once the measurement starts"
    p.advance_to(32_000)
    assert read(p, 0x13)[0] & 0x07 == 0, "not before the 33 ms budget"
    p.advance_to(33_000)
    assert read(p, 0x13)[0] & 0x07 == 0x04
    assert read(p, 0x14)[0] >> 3 == 11, "range status: valid"
    assert range_mm(p) == pytest.approx(950, rel=0.03)
    assert p.truth()["tof_range_m"] == pytest.approx(0.95)
    write(p, 0x0B, 0x01)
    assert read(p, 0x13)[0] & 0x07 == 0, "SYSTEM_INTERRUPT_CLEAR clears the ready flag"
    p.advance_to(200_000)
    assert p.truth()["tof_measurements"] == 1, "one measurement only"


def test_beyond_max_m_there_is_no_target():
    p = plant(pose=(2.0, 1.0, 3.14159))  # the far wall 2 m behind: beyond 1.2 m
    write(p, 0x00, 0x01)
    p.advance_to(40_000)
    assert range_mm(p) == 8190 and read(p, 0x14)[0] >> 3 == 4


def test_back_to_back_measurements_come_one_per_budget_until_stopped():
    p = plant(budget_us=50_000)
    write(p, 0x00, 0x02)
    p.advance_to(1_000_000)
    assert p.truth()["tof_measurements"] == 20
    write(p, 0x00, 0x00)
    p.advance_to(2_000_000)
    assert p.truth()["tof_measurements"] == 20


@pytest.mark.parametrize(
    "options, words",
    [
        ({"address": 0x78}, "reserved"),
        ({"bus": "spi1"}, "has no SPI"),
        ({"min_range_m": 2.0, "max_range_m": 1.0}, "min_range_m"),
    ],
)
def test_a_bad_address_bus_or_range_is_refused_by_name(options, words):
    with pytest.raises(PartsError, match=words):
        plant(**options)


def test_gpio1_is_asserted_while_a_range_is_ready_with_the_polarity_the_driver_sets():
    p = plant()
    assert p.output("tof.gpio1") == 0, "power-on: active high, nothing ready"
    write(p, 0x0A, 0x04)  # new sample ready
    write(p, 0x84, read(p, 0x84)[0] & ~0x10)  # active low, as the drivers set it
    assert [(c.name, c.value) for c in p.advance_to(1_000)] == [("tof.gpio1", 1)]
    write(p, 0x00, 0x01)
    changes = p.advance_to(40_000)
    assert [(c.t_us, c.value) for c in changes] == [(1_000 + 33_000, 0)], "asserted (low) at the range's end"
    write(p, 0x0B, 0x01)
    assert [(c.name, c.value) for c in p.advance_to(41_000)] == [("tof.gpio1", 1)]

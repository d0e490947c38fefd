"""The vl53l1x part (sim_plant/catalogue/vl53l1x.py) played as the shim's BUS frames play
it: 16-bit register addresses, the model id, the boot state after power-on and a software
reset, ranging started and stopped with the wall's range along the mount's ray, the
interrupt's status and pin with either polarity, no target beyond max_m, and the refusals."""

import pytest

from sim_plant import buses as B
from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError

MOTORS = [{"kind": "dc_motor", "name": f"motor_{s[0]}", "bridge": "tb6612", "drives": s} for s in ("left", "right")]


def plant(pose=(2.0, 1.0, 0.0), **options):
    tof = {"kind": "vl53l1x", "name": "tof", "bus": "i2c0", "mount": {"x_m": 0.05}, **options}
    return assemble({"body": "differential", "start_pose": list(pose), "parts": [*MOTORS, tof]})


def read(p, reg, n=1):
    status, _acks, got = p.bus_transfer("i2c0", B.XFER, 0x29, n, reg.to_bytes(2, "big"))
    assert status == B.OK
    return got


def write(p, reg, *values):
    assert p.bus_transfer("i2c0", B.XFER, 0x29, 0, reg.to_bytes(2, "big") + bytes(values))[0] == B.OK


def test_the_model_id_reads_at_its_16_bit_address_and_the_chip_boots_after_its_boot_time():
    p = plant()
    assert read(p, 0x010F, 2) == b"\xea\xcc"
    assert read(p, 0x0F) == b"\x00", "an 8-bit address is another register"
    assert read(p, 0x00E5) == b"\x00", "booting"
    p.advance_to(1_200)
    assert read(p, 0x00E5) == b"\x01"
    write(p, 0x0000, 0x00)  # SOFT_RESET held
    write(p, 0x0030, 0x11)
    p.advance_to(5_000)
    assert read(p, 0x00E5) == b"\x00" and read(p, 0x0030) == b"\x01", "in reset: the registers at power-on"
    write(p, 0x0000, 0x01)
    p.advance_to(5_000 + 1_199)
    assert read(p, 0x00E5) == b"\x00"
    p.advance_to(5_000 + 1_200)
    assert read(p, 0x00E5) == b"\x01"


def test_ranging_gives_the_walls_range_once_per_budget_with_the_interrupt_until_cleared():
    p = plant()  # the room's wall at x = 3 m; the chip 5 cm ahead of the body's centre at x = 2 m
    p.advance_to(2_000)
    write(p, 0x002D, *bytes(91))  # a default configuration block: plain memory
    write(p, 0x0087, 0x40)
    p.advance_to(2_000 + 99_999)
    assert read(p, 0x0031)[0] & 1 == 0 and p.output("tof.gpio1") == 0, "not before the 100 ms budget"
    p.advance_to(102_000)
    assert read(p, 0x0031)[0] & 1 == 1 and p.output("tof.gpio1") == 1
    assert read(p, 0x0089)[0] & 0x1F == 9, "range status: valid"
    assert int.from_bytes(read(p, 0x0096, 2), "big") == pytest.approx(950, rel=0.03)
    assert p.truth()["tof_range_m"] == pytest.approx(0.95)
    write(p, 0x0086, 0x01)
    assert read(p, 0x0031)[0] & 1 == 0, "SYSTEM__INTERRUPT_CLEAR"
    p.advance_to(1_002_000)
    assert p.truth()["tof_measurements"] == 10 and read(p, 0x008B) == b"\x0a"
    write(p, 0x0087, 0x00)
    p.advance_to(2_000_000)
    assert p.truth()["tof_measurements"] == 10, "stopped"


def test_an_active_low_interrupt_reads_zero_when_ready_and_one_shot_ranges_once():
    p = plant(budget_us=20_000)
    p.advance_to(2_000)
    write(p, 0x0030, 0x11)
    p.advance_to(3_000)
    assert read(p, 0x0031)[0] & 1 == 1 and p.output("tof.gpio1") == 1, "idle: high"
    write(p, 0x0087, 0x10)
    p.advance_to(500_000)
    assert read(p, 0x0031)[0] & 1 == 0 and p.output("tof.gpio1") == 0
    assert p.truth()["tof_measurements"] == 1


def test_beyond_max_m_there_is_no_target():
    p = plant(pose=(2.0, 1.0, 3.14159), max_range_m=1.5)  # the far wall 2 m behind
    write(p, 0x0087, 0x10)
    p.advance_to(200_000)
    assert read(p, 0x0089)[0] & 0x1F == 4 and read(p, 0x0096, 2) == b"\x00\x00"


def test_the_part_refuses_an_spi_bus_and_a_min_above_max():
    with pytest.raises(PartsError, match="I2C bus"):
        plant(bus="spi1")
    with pytest.raises(PartsError, match="min_range_m"):
        plant(min_range_m=0.5, max_range_m=0.2)

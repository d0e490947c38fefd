"""The ina219 part (sim_plant/catalogue/ina219.py) played as the shim's BUS frames play
it: power-on registers, calibration, the bus voltage from the battery part, the current
from the motors' load through the shunt, the PGA's range, CNVR, the reset bit."""

import pytest

from sim_plant import buses as B
from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError

MOTORS = [
    {"kind": "dc_motor", "name": "motor_l", "bridge": "tb6612", "drives": "left", "time_constant_ms": 0},
    {"kind": "dc_motor", "name": "motor_r", "bridge": "tb6612", "drives": "right", "time_constant_ms": 0},
    {"kind": "battery", "name": "batt", "full_v": 7.4},
]


def plant(**options):
    parts = [*MOTORS, {"kind": "ina219", "name": "power", "battery": "batt", **options}]
    return assemble({"body": "differential", "parts": parts})


def word(p, reg) -> int:
    status, _acks, got = p.bus_transfer("i2c0", B.XFER, 0x40, 2, bytes((reg,)))
    assert status == B.OK
    return got[0] << 8 | got[1]


def put(p, reg, value) -> None:
    assert p.bus_transfer("i2c0", B.XFER, 0x40, 0, bytes((reg, value >> 8, value & 0xFF)))[0] == B.OK


def signed(value: int) -> int:
    return value - 0x10000 if value & 0x8000 else value


def run(p, in1, pwm, until_us):
    for side in ("l", "r"):
        p.set_input(f"motor_{side}.in1", in1)
        p.set_input(f"motor_{side}.in2", 0)
        p.set_input(f"motor_{side}.pwm", pwm)
    p.advance_to(until_us)


def test_power_on_registers_and_the_bus_voltage_of_the_battery():
    p = plant()
    assert word(p, 0x00) == 0x399F and word(p, 0x05) == 0 and word(p, 0x04) == 0, "uncalibrated: no current"
    bus = word(p, 0x02)
    assert (bus >> 3) * 4e-3 == pytest.approx(7.4, abs=0.004)
    assert signed(word(p, 0x01)) == round(0.05 * 0.1 / 10e-6), "idle 50 mA through 0.1 ohm: 500 counts of 10 uV"


def test_the_current_follows_the_motors_load_through_the_calibration():
    p = plant()
    put(p, 0x05, 4096)  # current LSB 100 uA with a 0.1 ohm shunt (the datasheet's example)
    assert word(p, 0x05) == 4096
    assert signed(word(p, 0x04)) == 500, "50 mA idle"
    run(p, 1, 65535, 500_000)
    assert signed(word(p, 0x04)) * 1e-4 == pytest.approx(0.05 + 2 * 0.3, abs=0.002), "both motors at full speed"
    power = word(p, 0x03)
    assert power * 20 * 1e-4 == pytest.approx(0.65 * 7.4, rel=0.01), "power LSB = 20 x current LSB"


def test_the_pga_range_clips_the_shunt_and_sets_ovf_and_cnvr_clears_when_power_is_read():
    p = plant(motor_a=2.0)
    put(p, 0x00, 0x399F & ~0x1800)  # PGA /1: +-40 mV
    run(p, 1, 65535, 500_000)
    assert signed(word(p, 0x01)) == 4000 and word(p, 0x02) & 1, "4.05 A x 0.1 ohm beyond 40 mV"
    assert word(p, 0x02) & 2, "a conversion ready"
    word(p, 0x03)
    assert not word(p, 0x02) & 2, "CNVR cleared by reading the power register"
    put(p, 0x00, 0x8000)
    assert word(p, 0x00) == 0x399F


def test_an_spi_bus_is_refused():
    with pytest.raises(PartsError, match="expected an I2C bus"):
        plant(bus="spi1")


def test_a_battery_that_is_no_battery_part_is_refused():
    with pytest.raises(PartsError, match=r"\(power\) battery: no battery part named 'nope'"):
        plant(battery="nope")

"""Chips on a bus (sim_plant/buses.py, sim_plant/catalogue/imu.py, the lsm6dsox and mpu6050 parts),
played byte by byte as the shim's BUS frames play them: identity registers, auto-increment,
the gyro's truth + bias + noise + saturation, the accelerometer's gravity, the data-ready
line at the output data rate, SPI chip select, and the refusals at assembly."""

import math
import struct

import pytest

from sim_plant import buses as B
from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError


def plant(*parts, body="bench", **options):
    return assemble({"body": body, **options, "parts": list(parts)})


def imu(kind="lsm6dsox", name="imu", **options):
    return {"kind": kind, "name": name, "bus": "i2c0", **options}


def read(p, address, reg, n, bus="i2c0"):
    status, _acks, got = p.bus_transfer(bus, B.XFER, address, n, bytes((reg,)))
    assert status == B.OK
    return got


def write(p, address, reg, *values, bus="i2c0"):
    return p.bus_transfer(bus, B.XFER, address, 0, bytes((reg, *values)))


def test_each_chip_answers_its_identity_register_as_the_chip_does():
    p = plant(imu(), imu("mpu6050", "mpu"), imu("mpu6050", "mpu6886", address=0x69, who_am_i=0x19))
    assert read(p, 0x6A, 0x0F, 1) == b"\x6c"
    assert read(p, 0x68, 0x75, 1) == b"\x68"
    assert read(p, 0x69, 0x75, 1) == b"\x19"
    assert p.bus_transfer("i2c0", B.SCAN, 0, 0, b"")[2] == bytes((0x68, 0x69, 0x6A))


@pytest.mark.parametrize(("kind", "address"), [("lsm6dsox", 0x6A), ("lsm6dso", 0x6B)])
@pytest.mark.parametrize("member", [0x6C, 0x6A, 0x69])
def test_an_lsm6ds_part_answers_the_family_member_a_driver_expects_also_after_a_software_reset(kind, address, member):
    p = plant(imu(kind, who_am_i=member))
    assert read(p, address, 0x0F, 1) == bytes((member,))
    write(p, address, 0x12, 0x01)  # CTRL3_C SW_RESET: every register back to its reset value
    assert read(p, address, 0x0F, 1) == bytes((member,)), "WHO_AM_I after SW_RESET"


def test_a_missing_address_is_not_acknowledged_and_a_held_bus_is_stuck():
    p = plant(imu())
    assert p.bus_transfer("i2c0", B.XFER, 0x50, 1, b"\x00")[0] == B.NACK_ADDRESS
    assert p.bus_transfer("i2c1", B.XFER, 0x6A, 1, b"\x0f")[0] == B.NACK_ADDRESS  # another bus
    stuck = plant(imu(holds_bus=True))
    assert stuck.bus_transfer("i2c0", B.XFER, 0x6A, 1, b"\x0f")[0] == B.STUCK


def test_registers_auto_increment_unless_if_inc_is_cleared():
    p = plant(imu())
    write(p, 0x6A, 0x10, 0x40, 0x48)  # CTRL1_XL, CTRL2_G in one write
    assert read(p, 0x6A, 0x10, 2) == b"\x40\x48"
    write(p, 0x6A, 0x12, 0x00)  # CTRL3_C: IF_INC off
    assert read(p, 0x6A, 0x10, 2) == b"\x40\x40"
    write(p, 0x6A, 0x12, 0x01)  # SW_RESET: the registers at their reset values, the bit set for 50 us
    assert read(p, 0x6A, 0x10, 3) == b"\x00\x00\x05"
    p.advance_to(50)
    assert read(p, 0x6A, 0x10, 3) == b"\x00\x00\x04"


def spin(w_rad_s, **options):
    """A differential robot turning in place at about ``w_rad_s`` (its wheels' speeds set directly)."""
    p = plant(
        {"kind": "dc_motor", "name": "ml", "drives": "left", "time_constant_ms": 0},
        {"kind": "dc_motor", "name": "mr", "drives": "right", "time_constant_ms": 0},
        imu(**options),
        body="differential",
    )
    return p


def gyro_z_dps(p, t_us, fs_code=0):
    p.advance_to(t_us)
    write(p, 0x6A, 0x11, 0x40 | fs_code << 2)  # CTRL2_G: 104 Hz at the full scale
    p.advance_to(t_us + 20_000)
    raw = struct.unpack("<3h", read(p, 0x6A, 0x22, 6))
    return raw[2] * {0: 8.75, 1: 17.5, 2: 35.0, 3: 70.0}[fs_code] / 1000


def drive(p, duty):
    for name, sign in (("ml", -1), ("mr", 1)):
        p.set_input(f"{name}.in1", 1 if sign > 0 else 0)
        p.set_input(f"{name}.in2", 0 if sign > 0 else 1)
        p.set_input(f"{name}.pwm", duty)


def test_gyro_reads_the_true_turn_rate_plus_bias_and_saturates_at_the_full_scale():
    p = spin(0, gyro_bias_dps=[0, 0, 2.0], gyro_noise_dps=0.0)
    drive(p, 20_000)
    p.advance_to(1_000)
    true_dps = math.degrees(p.drive.body.w)
    assert 30 < true_dps < 250
    assert gyro_z_dps(p, 100_000) == pytest.approx(true_dps + 2.0, abs=0.01)
    drive(p, 65535)
    p.advance_to(200_000)
    fast_dps = math.degrees(p.drive.body.w)
    assert fast_dps > 290  # faster than the ±250 dps scale reads
    assert gyro_z_dps(p, 300_000) == pytest.approx(32767 * 8.75 / 1000, abs=0.01), "saturated"
    assert gyro_z_dps(p, 400_000, fs_code=1) == pytest.approx(fast_dps + 2.0, abs=0.02), "±500 dps reads it"


def test_gyro_noise_has_the_configured_spread_and_the_accelerometer_reads_gravity():
    p = plant(imu(gyro_noise_dps=0.5, accel_noise_m_s2=0.0))
    write(p, 0x6A, 0x10, 0x40, 0x40)  # both at 104 Hz, ±2 g, ±250 dps
    zs, gz = [], []
    for k in range(400):
        p.advance_to(k * 10_000 + 5_000)
        ax, ay, az = struct.unpack("<3h", read(p, 0x6A, 0x28, 6))
        zs.append(az * 0.061e-3 * 9.80665)
        gz.append(struct.unpack("<3h", read(p, 0x6A, 0x22, 6))[2] * 8.75e-3)
    assert sum(zs) / len(zs) == pytest.approx(9.80665, abs=0.002)
    mean = sum(gz) / len(gz)
    spread = math.sqrt(sum((g - mean) ** 2 for g in gz) / len(gz))
    assert abs(mean) < 0.1 and 0.42 < spread < 0.58, (mean, spread)


def test_data_ready_line_rises_at_each_output_data_rate_tick_and_falls_when_the_data_are_read():
    p = plant(imu("mpu6050", "mpu"))
    write(p, 0x68, 0x6B, 0x00)  # awake
    write(p, 0x68, 0x1A, 0x01, 0x00)  # DLPF on: 1 kHz ...
    write(p, 0x68, 0x19, 9)  # ... / (1 + 9): 100 Hz
    write(p, 0x68, 0x38, 0x01)  # DATA_RDY_EN
    changes = p.advance_to(35_000)
    assert [(c.t_us, c.value) for c in changes if c.name == "mpu.int"] == [(10_000, 1)]
    assert read(p, 0x68, 0x3A, 1) == b"\x01"  # INT_STATUS: read, it clears and the line falls
    changes = p.advance_to(45_000)
    assert [(c.t_us, c.value) for c in changes if c.name == "mpu.int"] == [(35_000, 0), (40_000, 1)]


def test_an_spi_device_answers_only_while_its_chip_select_is_low():
    p = plant(imu(bus="spi1", spi=True))
    assert p.bus_transfer("spi1", B.SPI_XFER, 0, 0, b"\x8f\x00")[2] == b"\xff\xff"  # not selected
    p.set_input("imu.cs", 0)
    assert p.bus_transfer("spi1", B.SPI_XFER, 0, 0, b"\x8f\x00")[2] == b"\x00\x6c"
    p.set_input("imu.cs", 1)


@pytest.mark.parametrize(
    "parts, words",
    [
        ([imu(address=0x05)], ["#1 (imu) address", "0x08 to 0x77", "got 0x05"]),
        ([imu(address=0x78)], ["#1 (imu) address", "got 0x78"]),
        ([imu(), imu("mpu6050", "mpu", address=0x6A)], ["#2 (mpu) address", "0x6a on bus i2c0", "#1 (imu)"]),
        ([imu(bus="spi1")], ["#1 (imu) spi", "expected true on bus spi1"]),
        ([imu(bus="i2c0", spi=True)], ["#1 (imu) spi"]),
        ([imu(bus="usb0")], ["#1 (imu) bus", "a bus name"]),
    ],
)
def test_a_bad_address_two_devices_at_one_address_or_a_bad_bus_are_refused_by_name(parts, words):
    with pytest.raises(PartsError) as e:
        plant(*parts)
    for word in words:
        assert word in str(e.value), str(e.value)

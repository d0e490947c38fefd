"""The lis3mdl part (sim_plant/catalogue/lis3mdl.py) played as the shim's BUS frames play
it: identity, power-down at reset, the field along the body's heading plus the hard-iron
offset at the full scale's sensitivity, data ready, a soft reset, the refusals."""

import math
import struct

import pytest

from sim_plant import buses as B
from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError


def plant(theta_rad=0.0, **options):
    part = {"kind": "lis3mdl", "name": "mag", "bus": "i2c0", "noise_ut": 0.0, **options}
    motors = [{"kind": "dc_motor", "name": f"motor_{s[0]}", "bridge": "tb6612", "drives": s} for s in ("left", "right")]
    return assemble({"body": "differential", "start_pose": [1.5, 1.0, theta_rad], "parts": [*motors, part]})


def read(p, reg, n):
    status, _acks, got = p.bus_transfer("i2c0", B.XFER, 0x1C, n, bytes((reg,)))
    assert status == B.OK
    return got


def write(p, reg, value):
    assert p.bus_transfer("i2c0", B.XFER, 0x1C, 0, bytes((reg, value)))[0] == B.OK


def field_ut(p, lsb_per_gauss=6842):
    return [v / lsb_per_gauss * 100 for v in struct.unpack("<hhh", read(p, 0x28, 6))]


def test_identity_and_power_down_until_continuous_mode():
    p = plant()
    assert read(p, 0x0F, 1) == b"\x3d"
    assert read(p, 0x22, 1) == b"\x03", "CTRL_REG3 resets to power-down"
    assert read(p, 0x27, 1) == b"\x00" and field_ut(p) == [0, 0, 0]


@pytest.mark.parametrize("theta_deg", [0, 30, 90, 200])
def test_the_field_turns_with_the_heading_plus_the_hard_iron_offset(theta_deg):
    p = plant(math.radians(theta_deg), hard_iron_ut=[5.0, -3.0, 1.0])
    write(p, 0x22, 0x00)  # continuous
    p.advance_to(200_000)
    assert read(p, 0x27, 1) == b"\x0f", "ZYXDA and each axis' XDA, YDA, ZDA"
    x, y, z = field_ut(p)
    assert read(p, 0x27, 1) == b"\x00", "read: no new sample until the next tick (10 Hz)"
    angle = math.radians(90 - theta_deg)
    assert x == pytest.approx(20 * math.cos(angle) + 5, abs=0.02)
    assert y == pytest.approx(20 * math.sin(angle) - 3, abs=0.02)
    assert z == pytest.approx(-44 + 1, abs=0.02)
    assert p.truth()["mag_heading_deg"] == pytest.approx((90 - theta_deg) % 360)


def test_the_full_scale_sets_the_sensitivity_and_saturates_and_soft_reset_restores():
    p = plant(hard_iron_ut=[500.0, 0.0, 0.0])
    write(p, 0x22, 0x00)
    p.advance_to(200_000)
    assert field_ut(p)[0] == pytest.approx(32767 / 6842 * 100), "500 uT saturates at +-4 gauss"
    write(p, 0x21, 0x60)  # +-16 gauss
    assert field_ut(p, 1711)[0] == pytest.approx(500, abs=0.1)
    write(p, 0x21, 0x04)  # SOFT_RST: set until the reset is done (50 us)
    assert read(p, 0x21, 1) == b"\x04"
    p.advance_to(200_050)
    assert read(p, 0x20, 3) == b"\x10\x00\x03", "CTRL_REG1..3 at their reset values: power-down again"


@pytest.mark.parametrize(
    "options, words",
    [({"address": 0x05}, "reserved"), ({"bus": "spi1"}, "has no SPI")],
)
def test_a_bad_address_or_bus_is_refused_by_name(options, words):
    with pytest.raises(PartsError, match=words):
        plant(**options)

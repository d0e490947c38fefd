"""The pca9685 part (sim_plant/catalogue/pca9685.py) played as the shim's BUS frames play
it: power-on registers, auto-increment only with AI, PRE_SCALE written only asleep, the
datasheet's frequency, a channel's pulse passed on to a servo and to a motor bridge, and
the refusals at assembly."""

import pytest

from sim_plant import buses as B
from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError

SERVO = {"kind": "servo", "name": "pan", "min_pulse_us": 1000, "max_pulse_us": 2000, "slew_deg_per_s": 600}


def plant(*parts):
    return assemble({"body": "bench", "parts": list(parts)})


def pca(**options):
    return {"kind": "pca9685", "name": "pwm", "bus": "i2c0", "drives": ["pan.pwm"], **options}


def read(p, reg, n):
    status, _acks, got = p.bus_transfer("i2c0", B.XFER, 0x40, n, bytes((reg,)))
    assert status == B.OK
    return got


def write(p, reg, *values):
    assert p.bus_transfer("i2c0", B.XFER, 0x40, 0, bytes((reg, *values)))[0] == B.OK


def test_power_on_registers_and_auto_increment_only_with_ai():
    p = plant(SERVO, pca())
    assert read(p, 0x00, 1) == b"\x11"  # MODE1: SLEEP, ALLCALL
    assert read(p, 0xFE, 1) == b"\x1e"  # PRE_SCALE: 200 Hz
    write(p, 0x06, 1, 2, 3, 4)  # AI off: four writes to LED0_ON_L
    assert read(p, 0x06, 4) == b"\x04\x04\x04\x04"
    write(p, 0x00, 0x21)  # AI on
    write(p, 0x06, 1, 2, 3, 4)
    assert read(p, 0x06, 4) == b"\x01\x02\x03\x04"


def test_prescale_is_written_only_asleep_and_sets_the_datasheet_frequency():
    p = plant(SERVO, pca())
    write(p, 0x00, 0x01)  # awake
    write(p, 0xFE, 121)
    assert read(p, 0xFE, 1) == b"\x1e", "PRE_SCALE is ignored while the oscillator runs"
    write(p, 0x00, 0x11)
    write(p, 0xFE, 121)
    assert read(p, 0xFE, 1) == bytes((121,))
    assert p.truth()["pwm_freq_hz"] == pytest.approx(25e6 / 4096 / 122)


def pulse(p, on, off):
    write(p, 0x06, on & 0xFF, on >> 8, off & 0xFF, off >> 8)


def test_a_channel_drives_its_servo_to_the_pulse_width_it_makes():
    p = plant(SERVO, pca())
    write(p, 0x00, 0x31)  # asleep, AI
    write(p, 0xFE, 121)  # 50 Hz: a count is 20 ms / 4096
    write(p, 0x00, 0x21)  # awake
    pulse(p, 0, 307)  # 1.5 ms: the middle
    p.advance_to(1_000_000)
    assert p.truth()["pwm_ch0_pulse_us"] == pytest.approx(1499, abs=1)
    assert p.truth()["pan_angle_deg"] == pytest.approx(90, abs=0.5)
    pulse(p, 100, 100 + 389)  # 1.9 ms from a later start: the same width
    p.advance_to(2_000_000)
    assert p.truth()["pan_angle_deg"] == pytest.approx(162, abs=1)
    write(p, 0x00, 0x31)  # asleep: no pulses, the horn stays
    p.advance_to(3_000_000)
    assert p.truth()["pan_angle_deg"] == pytest.approx(162, abs=1)
    assert p.truth()["pwm_ch0_pulse_us"] == 0


def test_channels_drive_a_motor_bridge_pwm_and_direction_inputs():
    p = assemble(
        {
            "body": "differential",
            "parts": [
                {"kind": "dc_motor", "name": "motor_l", "bridge": "tb6612", "drives": "left"},
                {"kind": "dc_motor", "name": "motor_r", "bridge": "tb6612", "drives": "right"},
                pca(drives=["motor_l.pwm", "motor_l.in1", "motor_l.in2", "motor_r.pwm", "motor_r.in1", "motor_r.in2"]),
            ],
        }
    )
    write(p, 0x00, 0x21)
    for ch, (on, off) in enumerate([(0, 4095), (0x1000, 0), (0, 0x1000), (0, 4095), (0x1000, 0), (0, 0x1000)]):
        write(p, 0x06 + 4 * ch, on & 0xFF, on >> 8, off & 0xFF, off >> 8)
    p.advance_to(1_000_000)
    left, right = p.truth()["wheel_rad_s"]
    assert left > 5 and right > 5, "full duty, in1 high, in2 low: both wheels forward"
    assert abs(p.truth()["w_rad_s"]) < 0.01
    write(p, 0x06 + 4 * 3, 0, 0, 0, 0x10)  # right PWM full off
    p.advance_to(2_000_000)
    assert p.truth()["wheel_rad_s"][1] < 0.5


@pytest.mark.parametrize(
    "options, words",
    [
        ({"drives": ["nope.pwm"]}, r"\[\[plant.parts\]\] #2 \(pwm\) drives: expected inputs of the plant.s parts"),
        ({"drives": ["pan.pwm", "pan.pwm"]}, "pan.pwm twice"),
        ({"address": 0x7F}, "reserved"),
        ({"bus": "spi1"}, "the PCA9685 has no SPI"),
    ],
)
def test_a_bad_channel_target_or_address_is_refused_by_name(options, words):
    with pytest.raises(PartsError, match=words):
        plant(SERVO, pca(**options))

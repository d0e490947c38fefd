"""The servo part and the ackermann body: a pulse sets the horn's angle at the servo's
slew rate; a car's rear motor and steering servo drive it round the arc a bicycle model
gives (radius = wheelbase / tan(steer)); a car without its rear motor, or a continuous
servo that steers, is refused by name."""

import math

import pytest

from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError

PERIOD_US = 20_000


def duty(pulse_us: float) -> int:
    return round(pulse_us / PERIOD_US * 65535)


def car(**servo):
    return assemble(
        {
            "body": "ackermann",
            "room_w_m": 20.0,
            "room_h_m": 20.0,
            "start_pose": [10.0, 10.0, 0.0],
            "parts": [
                {"kind": "dc_motor", "name": "drive", "drives": "rear", "time_constant_ms": 0, "deadband_duty": 0},
                {"kind": "servo", "name": "steer", "steers": True, **servo},
            ],
        }
    )


def test_a_pulse_turns_the_horn_at_its_slew_rate_to_the_angle_it_asks():
    plant = assemble({"body": "bench", "parts": [{"kind": "servo", "name": "pan", "slew_deg_per_s": 300}]})
    assert plant.truth()["pan_angle_deg"] == 90, "a positional servo starts centred"
    plant.set_input("pan.pwm", duty(2500))  # 180 degrees
    plant.advance_to(150_000)
    assert plant.truth()["pan_angle_deg"] == pytest.approx(90 + 300 * 0.15, abs=1.6), "on its way at 300 deg/s"
    plant.advance_to(400_000)
    assert plant.truth()["pan_angle_deg"] == pytest.approx(180)
    assert plant.truth()["pan_pulse_us"] == pytest.approx(2500, abs=0.5)


def test_a_car_steered_left_drives_the_bicycle_models_circle():
    plant = car(slew_deg_per_s=100_000)
    plant.set_input("drive.in1", 1)
    plant.set_input("drive.pwm", 65535)
    plant.set_input("steer.pwm", duty(500 + 110 / 180 * 2000))  # servo 110: 20 degrees left
    plant.advance_to(500_000)
    truth = plant.truth()
    assert truth["steer_deg"] == pytest.approx(20, abs=0.1)
    v = truth["v_m_s"]
    assert v == pytest.approx(0.4), "the body's v_max_m_s at full duty"
    assert truth["w_rad_s"] == pytest.approx(v * math.tan(math.radians(truth["steer_deg"])) / 0.16)
    assert truth["theta_rad"] == pytest.approx(truth["w_rad_s"] * 0.495), "turning left from the first 5 ms step"


def test_the_front_wheels_stop_at_max_steer_deg():
    plant = car(slew_deg_per_s=100_000)
    plant.set_input("steer.pwm", duty(500))  # servo 0: 90 degrees right of centre
    plant.advance_to(50_000)
    assert plant.truth()["steer_deg"] == pytest.approx(-30)


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ({"body": "ackermann", "parts": [{"kind": "servo", "name": "s", "steers": True}]}, "drives 'rear', got none"),
        (
            {"body": "differential", "parts": [{"kind": "dc_motor", "name": "m", "drives": "rear"}]},
            "drives left or right, not rear|needs a dc_motor",
        ),
        (
            {"body": "bench", "parts": [{"kind": "servo", "name": "s", "steers": True, "type": "continuous"}]},
            r"#1 \(s\) steers: a steering servo is a positional one",
        ),
        ({"body": "bench", "parts": [{"kind": "servo", "name": "s", "min_pulse_us": 3000}]}, "min_pulse_us: expected"),
    ],
)
def test_a_car_or_servo_that_cannot_be_built_is_refused_by_name(table, message):
    with pytest.raises(PartsError, match=message):
        assemble(table).reset(0)

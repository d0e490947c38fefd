"""Part servo: a positional SG90 turns to the pulse's angle at its slew rate, a
continuous one turns at the pulse's speed; a ranger on it looks along its horn."""

import math

import pytest

from sim_plant.catalogue.assembly import PartsError, assemble

MOTORS = [
    {"kind": "dc_motor", "name": "motor_l", "drives": "left"},
    {"kind": "dc_motor", "name": "motor_r", "drives": "right"},
]


def robot(*parts, **body):
    return assemble({"body": "differential", **body, "parts": [*MOTORS, *parts]})


def duty(pulse_ms):
    return round(pulse_ms / 20 * 65535)


def test_a_positional_servo_reaches_the_pulses_angle_at_its_slew_rate():
    plant = robot({"kind": "servo", "name": "pan", "slew_deg_per_s": 500})
    assert "pan.pwm" in plant.inputs and plant.truth()["pan_angle_deg"] == 90.0
    plant.set_input("pan.pwm", duty(2.5))  # 180 degrees: 90 to go, 180 ms
    plant.advance_to(90_000)
    assert plant.truth()["pan_angle_deg"] == pytest.approx(135.0, abs=0.1)
    plant.advance_to(200_000)
    assert plant.truth()["pan_angle_deg"] == pytest.approx(180.0, abs=0.1) and plant.truth()["pan_target_deg"] == 180.0


def test_a_continuous_servo_turns_at_the_pulses_speed_and_stands_still_at_1_5_ms():
    plant = robot({"kind": "servo", "name": "wheel", "type": "continuous", "rpm": 60})
    plant.set_input("wheel.pwm", duty(2.5))  # full speed on
    plant.advance_to(500_000)
    assert plant.truth()["wheel_angle_deg"] == pytest.approx(180.0, abs=0.5)
    plant.set_input("wheel.pwm", duty(1.5))
    plant.advance_to(1_000_000)
    assert plant.truth()["wheel_angle_deg"] == pytest.approx(180.0, abs=0.5)
    plant.set_input("wheel.pwm", duty(1.0))  # half speed back
    plant.advance_to(2_000_000)
    assert plant.truth()["wheel_angle_deg"] == pytest.approx(0.0, abs=1.0)


def test_an_hcsr04_on_the_servo_looks_along_its_horn():
    """A wall 1 m to the left of the sensor, 2.6 m ahead: turned to 180 deg (90 left) the
    ranger sees the wall at 1 m; straight ahead it sees the far one."""
    servo = {"kind": "servo", "name": "pan", "mount": {"x_m": 0.1}}
    sonar = {"kind": "hcsr04", "name": "sonar", "mount": {"x_m": 0.1}, "on_servo": "pan", "noise_sd_m": 0}
    plant = robot(servo, sonar, room_w_m=3.0, room_h_m=2.0, start_pose=[0.3, 1.0, 0.0])

    def ping(t_us):
        plant.advance_to(t_us)
        plant.set_input("sonar.trig", 1)
        plant.advance_to(t_us + 10)
        plant.set_input("sonar.trig", 0)
        edges = [c for c in plant.advance_to(t_us + 40_000) if c.name == "sonar.echo"]
        return (edges[1].t_us - edges[0].t_us) / 5831

    assert ping(10_000) == pytest.approx(3.0 - 0.4, abs=0.01)
    plant.set_input("pan.pwm", duty(2.5))
    assert ping(400_000) == pytest.approx(1.0, abs=0.01)
    assert plant.truth()["sonar_ping_angle_deg"] == pytest.approx(180.0)


def test_a_ranger_on_a_servo_not_listed_before_it_is_refused_by_name():
    sonar = {"kind": "hcsr04", "name": "sonar", "on_servo": "pan"}
    with pytest.raises(PartsError, match=r"#3 \(sonar\) on_servo: no servo part named 'pan'"):
        robot(sonar, {"kind": "servo", "name": "pan"})
    with pytest.raises(PartsError, match="min_pulse_us: expected less than max_pulse_us"):
        robot({"kind": "servo", "name": "pan", "min_pulse_us": 2500, "max_pulse_us": 500})


def test_the_servo_declares_its_signal_and_its_angle_view():
    from sim_plant.catalogue.servo import Servo

    assert [s.suffix for s in Servo.SIGNALS] == ["pwm"] and Servo.VIEWS[0].plot == "angle"
    assert math.isclose(Servo.defaults()["slew_deg_per_s"], 600) and Servo.defaults()["start_deg"] is None

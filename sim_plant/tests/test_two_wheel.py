"""The two-wheel robot a rig file assembles from options."""

import pytest

from sim_plant.hcsr04 import US_PER_CM
from sim_plant.two_wheel import TwoWheelRobot


def ping(plant, width_us):
    t0 = plant.t_us
    plant.set_input("sonar.trig", 1)
    plant.advance_to(t0 + width_us)
    plant.set_input("sonar.trig", 0)
    return [c for c in plant.advance_to(t0 + 60_000) if c.name == "sonar.echo"]


def test_hcsr04_answers_a_5us_trigger_by_default_and_not_when_held_to_the_datasheet():
    lenient = TwoWheelRobot(start_pose=(1.0, 1.0, 0.0), ranger_noise_sd_m=0.0)
    lenient.reset(1)
    lenient.advance_to(1_000)
    rise, fall = ping(lenient, 5)
    range_m = 3.0 - 1.0 - 0.08  # to the far wall, from the front of the body
    assert abs((fall.t_us - rise.t_us) - range_m * 100 * US_PER_CM) < 2
    strict = TwoWheelRobot(start_pose=(1.0, 1.0, 0.0), hcsr04_trigger_min_us=10)
    strict.reset(1)
    strict.advance_to(1_000)
    assert ping(strict, 5) == [] and len(ping(strict, 10)) == 2


def test_buttons_read_1_released_and_0_while_pressed_at_the_scripted_times():
    plant = TwoWheelRobot(buttons=["start", "stop"], presses=[["start", 0.5, 0.6]])
    plant.reset(0)
    assert plant.output("button.start") == 1 and plant.output("button.stop") == 1
    changes = [c for c in plant.advance_to(1_000_000) if c.name.startswith("button")]
    assert [(c.t_us, c.name, c.value) for c in changes] == [(500_000, "button.start", 0), (600_000, "button.start", 1)]


def test_a_bouncing_button_chatters_at_press_and_release():
    plant = TwoWheelRobot(buttons=["start"], presses=[["start", 0.5, 0.6]], button_bounce_us=2_000)
    plant.reset(0)
    levels = [(c.t_us, c.value) for c in plant.advance_to(1_000_000) if c.name == "button.start"]
    assert levels == [(500_000, 0), (500_500, 1), (501_000, 0), (600_000, 1), (600_500, 0), (601_000, 1)]


def test_floor_sensors_read_the_tape_while_over_it_within_one_check():
    """Crossing a 19 mm tape at 0.4 m/s: on from 0.9905 m to 1.0095 m, checked every 1 ms."""
    plant = TwoWheelRobot(line_sensors=[[0.06, -0.01], [0.06, 0.01]], tape=[[1.0, 0.2], [1.0, 1.8]])
    plant.reset(0)
    assert plant.output("floor_0.adc") == plant.output("floor_1.adc") == 6_000
    for side in "lr":
        plant.set_input(f"motor_{side}.in1", 1)
        plant.set_input(f"motor_{side}.pwm", 65535)
    changes = [(c.t_us, c.name, c.value) for c in plant.advance_to(3_000_000) if c.name.startswith("floor")]
    t_on, t_off = (0.9905 - 0.46) / 0.4 * 1e6, (1.0095 - 0.46) / 0.4 * 1e6
    assert [c[2] for c in changes] == [58_000, 58_000, 6_000, 6_000]
    assert 0 <= changes[0][0] - t_on < 1_000 and 0 <= changes[2][0] - t_off < 1_000, changes


@pytest.mark.parametrize("placed", [False, True])
def test_a_box_placed_in_the_way_at_a_time_is_met(placed):
    plant = TwoWheelRobot(placements=[[1.0, 1.2, 1.0, 0.2, 1.0]] if placed else [])
    plant.reset(0)
    for side in "lr":
        plant.set_input(f"motor_{side}.in1", 1)
        plant.set_input(f"motor_{side}.pwm", 65535)
    plant.advance_to(3_000_000)
    contacts = plant.truth()["contacts"]
    if placed:  # the front (x 0.48 + 0.4 t) meets the box's face at 1.1 m: t = 1.55 s
        assert contacts and abs(contacts[0][0] - 1_550_000) < 5_000, contacts
    else:
        assert contacts == [] and plant.truth()["x_m"] > 1.5


def test_tb6612_standby_low_keeps_both_motors_off():
    plant = TwoWheelRobot(standby=True)
    plant.reset(0)
    for side in "lr":
        plant.set_input(f"motor_{side}.in1", 1)
        plant.set_input(f"motor_{side}.pwm", 65535)
    plant.advance_to(500_000)
    assert plant.truth()["x_m"] == pytest.approx(0.4)
    plant.set_input("motor.stby", 1)
    plant.advance_to(1_000_000)
    assert plant.truth()["x_m"] == pytest.approx(0.4 + 0.4 * 0.5, abs=1e-6)


@pytest.mark.parametrize(
    ("options", "says"),
    [
        ({"bridge": "l293"}, "bridge: expected one of tb6612, l298n, drv8833, dir_pwm, got 'l293'"),
        ({"standby": True, "bridge": "l298n"}, "standby: only the tb6612 has a STBY pin"),
        ({"room_w_m": -2.0}, "room_w_m: expected a room wider than the robot"),
        ({"start_pose": (5.0, 1.0, 0.0)}, "start_pose: [5.0, 1.0, 0.0] puts the robot outside the room"),
        ({"presses": [["go", 1.0, 2.0]]}, "presses: no button 'go'"),
    ],
)
def test_bad_options_are_refused_by_name(options, says):
    with pytest.raises(ValueError) as e:
        TwoWheelRobot(**options)
    assert says in str(e.value)


@pytest.mark.parametrize("world", ["canyon", "duct", "multi_branch_duct", "vacuum_room", "pool"])
def test_the_two_wheel_robot_runs_in_each_of_our_worlds(world):
    plant = TwoWheelRobot(world=world)
    plant.reset(0)
    assert plant.truth()["contacts"] == [], f"{world}: the default start pose touches a wall"
    for side in "lr":
        plant.set_input(f"motor_{side}.in1", 1)
        plant.set_input(f"motor_{side}.pwm", 30000)
    plant.advance_to(1_000_000)
    assert plant.truth()["distance_m"] > 0.1


def test_motor_rpm_through_the_gearbox_sets_the_rim_speed():
    plant = TwoWheelRobot(motor_rpm=6000, gear_ratio=50, wheel_radius_m=0.03)
    assert plant.v_max_m_s == pytest.approx(6000 / 50 * 2 * 3.141592653589793 * 0.03 / 60)

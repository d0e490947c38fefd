"""A hobby two-wheel robot as a rig file describes it, part by part: what the retired
``two_wheel`` kind offered by options (a lenient HC-SR04, buttons, line sensors over
tape, boxes placed at a time, the TB6612's standby, our worlds, a motor's rpm)."""

import pytest

from sim_plant.catalogue.assembly import PartsError, assemble
from sim_plant.physics.hcsr04 import US_PER_CM

MOTORS = [
    {"kind": "dc_motor", "name": "motor_l", "drives": "left", "time_constant_ms": 0},
    {"kind": "dc_motor", "name": "motor_r", "drives": "right", "time_constant_ms": 0},
]


def robot(*parts, **body):
    plant = assemble({"body": "differential", **body, "parts": [*MOTORS, *parts]})
    plant.reset(0)
    return plant


def forward(plant, duty_u16=65535):
    for side in "lr":
        plant.set_input(f"motor_{side}.in1", 1)
        plant.set_input(f"motor_{side}.pwm", duty_u16)


def ping(plant, width_us):
    t0 = plant.t_us
    plant.set_input("sonar.trig", 1)
    plant.advance_to(t0 + width_us)
    plant.set_input("sonar.trig", 0)
    return [c for c in plant.advance_to(t0 + 60_000) if c.name == "sonar.echo"]


def test_hcsr04_answers_a_5us_trigger_by_default_and_not_when_held_to_the_datasheet():
    sonar = {"kind": "hcsr04", "name": "sonar", "mount": {"x_m": 0.08}, "noise_sd_m": 0.0}
    lenient = robot(sonar, start_pose=[1.0, 1.0, 0.0])
    lenient.advance_to(1_000)
    rise, fall = ping(lenient, 5)
    range_m = 3.0 - 1.0 - 0.08  # to the far wall, from the front of the body
    assert abs((fall.t_us - rise.t_us) - range_m * 100 * US_PER_CM) < 2
    strict = robot({**sonar, "trigger_min_us": 10}, start_pose=[1.0, 1.0, 0.0])
    strict.advance_to(1_000)
    assert ping(strict, 5) == [] and len(ping(strict, 10)) == 2


def test_a_bouncing_button_chatters_at_press_and_release():
    plant = robot({"kind": "button", "name": "start", "presses": [[0.5, 0.6]], "bounce_us": 2_000})
    assert plant.output("start.out") == 1
    levels = [(c.t_us, c.value) for c in plant.advance_to(1_000_000) if c.name == "start.out"]
    assert levels == [(500_000, 0), (500_500, 1), (501_000, 0), (600_000, 1), (600_500, 0), (601_000, 1)]


def test_floor_sensors_read_the_tape_while_over_it_within_one_check():
    """Crossing a 19 mm tape at 0.4 m/s: on from 0.9905 m to 1.0095 m, checked every 1 ms."""
    floor = {"kind": "line_sensor", "name": "floor", "offsets_m": [[0.06, -0.01], [0.06, 0.01]]}
    plant = robot(floor, tape=[[1.0, 0.2], [1.0, 1.8]])
    assert plant.output("floor.0") == plant.output("floor.1") == 6_000
    forward(plant)
    changes = [(c.t_us, c.name, c.value) for c in plant.advance_to(3_000_000) if c.name.startswith("floor")]
    t_on, t_off = (0.9905 - 0.46) / 0.4 * 1e6, (1.0095 - 0.46) / 0.4 * 1e6
    assert [c[2] for c in changes] == [58_000, 58_000, 6_000, 6_000]
    assert 0 <= changes[0][0] - t_on < 1_000 and 0 <= changes[2][0] - t_off < 1_000, changes


@pytest.mark.parametrize("placed", [False, True])
def test_a_box_placed_in_the_way_at_a_time_is_met(placed):
    box = {"kind": "placement", "name": "door", "t_s": 1.0, "box": [1.2, 1.0, 0.2, 1.0]}
    plant = robot(box) if placed else robot()
    forward(plant)
    plant.advance_to(3_000_000)
    contacts = plant.truth()["contacts"]
    if placed:  # the front (x 0.48 + 0.4 t) meets the box's face at 1.1 m: t = 1.55 s
        assert contacts and abs(contacts[0][0] - 1_550_000) < 5_000, contacts
        assert plant.truth()["door_placed"]
    else:
        assert contacts == [] and plant.truth()["x_m"] > 1.5


def test_tb6612_standby_low_keeps_both_motors_off():
    plant = robot({"kind": "standby", "name": "motor"})
    forward(plant)
    plant.advance_to(500_000)
    assert plant.truth()["x_m"] == pytest.approx(0.4)
    plant.set_input("motor.stby", 1)
    plant.advance_to(1_000_000)
    assert plant.truth()["x_m"] == pytest.approx(0.4 + 0.4 * 0.5, abs=1e-6)


@pytest.mark.parametrize(
    ("table", "says"),
    [
        ({"parts": [{"kind": "dc_motor", "name": "m", "bridge": "l293"}]}, "#3 (m) bridge: expected one of tb6612"),
        ({"room_w_m": -2.0}, "[plant] room_w_m: expected a number of metres from 0.1 to 100"),
        ({"start_pose": [5.0, 1.0, 0.0]}, "start_pose: [5.0, 1.0, 0.0] puts the robot outside the room"),
        (
            {"parts": [{"kind": "button", "name": "go", "presses": [[2.0, 1.0]]}]},
            "#3 (go) presses: go pressed at 2.0 s, released at 1.0 s",
        ),
        ({"parts": [{"kind": "standby", "name": "a"}, {"kind": "standby", "name": "b"}]}, "standby pin already"),
    ],
)
def test_bad_options_are_refused_by_name(table, says):
    parts = table.pop("parts", [])
    with pytest.raises(PartsError) as e:
        robot(*parts, **table)
    assert says in str(e.value)


@pytest.mark.parametrize("world", ["canyon", "duct", "multi_branch_duct", "vacuum_room", "pool"])
def test_the_differential_body_runs_in_each_of_our_worlds(world):
    plant = robot({"kind": "bumper", "name": "bumper"}, world=world)
    assert plant.truth()["contacts"] == [], f"{world}: the default start pose touches a wall"
    forward(plant, 30000)
    plant.advance_to(1_000_000)
    assert plant.truth()["distance_m"] > 0.1


def test_motor_rpm_through_the_gearbox_sets_the_rim_speed():
    motors = [{**m, "rpm": 6000, "gear_ratio": 50, "deadband_duty": 0} for m in MOTORS]
    plant = assemble({"body": "differential", "wheel_radius_m": 0.03, "parts": motors})
    forward(plant)
    plant.advance_to(1_000_000)
    assert plant.truth()["v_m_s"] == pytest.approx(6000 / 50 * 2 * 3.141592653589793 * 0.03 / 60)

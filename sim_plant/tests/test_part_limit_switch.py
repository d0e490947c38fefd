"""The limit switch: closed only when its own point of the body meets a wall."""

from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError


def _robot(*parts, start_pose):
    motors = [
        {"kind": "dc_motor", "name": f"motor_{s}", "drives": side, "time_constant_ms": 0}
        for s, side in (("l", "left"), ("r", "right"))
    ]
    return assemble({"body": "differential", "start_pose": start_pose, "parts": [*motors, *parts]})


def _back_up(plant):
    for side in "lr":
        plant.set_input(f"motor_{side}.in1", 0)
        plant.set_input(f"motor_{side}.in2", 1)
        plant.set_input(f"motor_{side}.pwm", 65535)


def test_a_rear_limit_switch_closes_at_the_wall_behind_and_a_side_one_does_not():
    rear = {"kind": "limit_switch", "name": "home", "mount": {"heading_deg": 180}, "bounce_us": 0}
    side = {"kind": "limit_switch", "name": "side", "mount": {"heading_deg": 90}, "bounce_us": 0}
    plant = _robot(rear, side, start_pose=[0.3, 1.0, 0.0])
    assert (plant.output("home.out"), plant.output("side.out")) == (1, 1), "active low: open reads 1"
    _back_up(plant)
    changes = [c for c in plant.advance_to(2_000_000) if c.name in ("home.out", "side.out")]
    assert [(c.name, c.value) for c in changes] == [("home.out", 0)], changes
    assert plant.truth()["home.out_pressed"] and not plant.truth()["side.out_pressed"]


def test_a_limit_switch_lever_reach_out_of_bounds_is_refused_by_name():
    try:
        _robot({"kind": "limit_switch", "name": "home", "half_arc_deg": 90}, start_pose=[1.0, 1.0, 0.0])
    except PartsError as e:
        assert "(home) half_arc_deg: expected" in str(e), e
    else:
        raise AssertionError("a 180-degree lever was accepted")

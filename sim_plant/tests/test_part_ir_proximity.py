"""The ir_proximity part: its level falls when the body comes within threshold_m of a wall
along the sensor's axis, and rises when it backs away."""

from sim_plant.catalogue.assembly import assemble

MOTORS = [
    {"kind": "dc_motor", "name": f"motor_{s}", "drives": side, "time_constant_ms": 0, "deadband_duty": 0.0}
    for s, side in (("l", "left"), ("r", "right"))
]


def test_the_level_falls_within_the_threshold_of_the_wall_ahead_and_not_for_one_behind():
    front = {"kind": "ir_proximity", "name": "ir_f", "threshold_m": 0.1, "mount": {"x_m": 0.05}}
    back = {"kind": "ir_proximity", "name": "ir_b", "threshold_m": 0.1, "mount": {"x_m": -0.05, "heading_deg": 180}}
    plant = assemble(
        {
            "body": "differential",
            "room_w_m": 3.0,
            "room_h_m": 2.0,
            "start_pose": [2.7, 1.0, 0.0],  # the east wall 0.25 m from the front sensor
            "parts": [*MOTORS, front, back],
        }
    )
    assert plant.output("ir_f.out") == 1 and plant.output("ir_b.out") == 1
    for m in ("l", "r"):
        plant.set_input(f"motor_{m}.in1", 1)
        plant.set_input(f"motor_{m}.in2", 0)
        plant.set_input(f"motor_{m}.pwm", 20_000)
    t, falls = 0, []
    while not falls and t < 3_000_000:
        t += 1_000
        falls = [c for c in plant.advance_to(t) if c.name == "ir_f.out"]
    assert falls and falls[0].value == 0, "low once the wall is near"
    truth = plant.truth()
    assert truth["ir_f_near"] and not truth["ir_b_near"], truth
    assert 0.1 - 0.002 < truth["ir_f_range_m"] <= 0.1, f"it fell at the threshold (a look's travel): {truth}"

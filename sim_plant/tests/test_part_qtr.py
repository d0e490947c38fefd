"""The qtr part (RC-decay reflectance sensors): a channel driven high reads 1, let go it
reads 1 for its discharge time, set by the floor under it and the emitter, then 0."""

import pytest

from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError
from sim_plant.catalogue.qtr import RELEASED
from sim_plant.plant import ReleasedAt

TAPE = [[1.0, 0.2], [1.0, 1.8]]  # a line across the floor at x = 1 m, 19 mm wide
MOTORS = [
    {"kind": "dc_motor", "name": f"motor_{s}", "drives": side, "time_constant_ms": 0}
    for s, side in (("l", "left"), ("r", "right"))
]


def plant_with(**options):
    # channel 0 on the tape (x = 1.0 m), channel 1 on the floor beside it (x = 1.03 m)
    qtr = {"kind": "qtr", "name": "line", "offsets_m": [[0.0, 0.0], [0.03, 0.0]], **options}
    plant = assemble({"body": "differential", "start_pose": [1.0, 1.0, 0.0], "tape": TAPE, "parts": [*MOTORS, qtr]})
    if options.get("emitter", "high") == "high":
        plant.set_input("line.emitter", 1)  # (the emitters lit)
    return plant


def read_us(plant, channel: int, t_us: int, charge_us=10, window_us=20_000, part="line") -> tuple[int, list]:
    """Drive the channel high ``charge_us`` at ``t_us``, let it go; (µs until it reads 0
    within ``window_us``, its changes). The plant is then at the window's end."""
    line = f"{part}.{channel}"
    plant.advance_to(t_us)
    plant.set_input(line, 1)
    changes = [(c.t_us - t_us, c.value) for c in plant.advance_to(t_us) if c.name == line]
    plant.advance_to(t_us + charge_us)
    plant.set_input(line, RELEASED)
    released = t_us + charge_us
    fall = [c for c in plant.advance_to(released + window_us) if c.name == line]
    changes += [(c.t_us - t_us, c.value) for c in fall]
    return (fall[0].t_us - released if fall else None), changes


def test_a_channel_reads_high_while_driven_and_for_its_discharge_time_after_release():
    plant = plant_with()
    assert plant.output("line.0") == 0, "uncharged, it reads low"
    black, changes = read_us(plant, 0, 1_000)
    assert changes == [(0, 1), (10 + 800, 0)], "high at the drive; low 800 us after the release"
    white, _ = read_us(plant, 1, 200_000)
    assert (black, white) == (800, 150)
    assert plant.truth()["line_on_tape"] == [True, False]
    assert plant.truth()["line_discharge_us"] == [800, 150]


def test_the_emitter_off_reads_as_no_light_and_the_emitter_line_follows_its_option():
    plant = plant_with(unlit_us=4_000)
    plant.set_input("line.emitter", 0)
    assert read_us(plant, 1, 1_000)[0] == 4_000, "emitters off: ambient light only"
    plant.set_input("line.emitter", 1)
    assert read_us(plant, 1, 200_000)[0] == 150
    plant.set_input("line.emitter", RELEASED)  # (the 3pi+'s bump emitters' GP23 made an input)
    assert read_us(plant, 1, 400_000)[0] == 4_000, "the control line let go: emitters off"
    low = plant_with(emitter="low")
    low.set_input("line.emitter", 1)
    assert read_us(low, 0, 1_000)[0] == 5_000, "active low: driven high is off"
    low.set_input("line.emitter", 0)
    assert read_us(low, 0, 200_000)[0] == 800, "active low: driven low is on"
    low.set_input("line.emitter", RELEASED)
    assert read_us(low, 0, 400_000)[0] == 5_000, "active low, let go: off"
    always = plant_with(emitter="none")
    assert "line.emitter" not in always.inputs
    assert read_us(always, 0, 1_000)[0] == 800


def test_a_release_given_ahead_of_its_instant_discharges_from_that_instant():
    """A PIO program's ``pindirs`` change, seen by the host's look-ahead before its cycle:
    driven high and let go 32.375 us later, both given at the same instant (the charge
    counted up to the release); the fall comes the discharge time after the release."""
    plant = plant_with()
    plant.advance_to(1_000)
    plant.set_input("line.1", 1)
    plant.set_input("line.1", ReleasedAt(1_032.375))
    changes = [(c.t_us, c.value) for c in plant.advance_to(3_000) if c.name == "line.1"]
    assert changes == [(1_000, 1), (1_182, 0)], f"expected high at 1000 us, low at 1032.375 + 150, got {changes}"
    plant.set_input("line.0", 1)
    plant.set_input("line.0", ReleasedAt(3_005))  # (5 us of the 10 a full charge takes: half)
    changes = [(c.t_us, c.value) for c in plant.advance_to(5_000) if c.name == "line.0"]
    assert changes == [(3_000, 1), (3_405, 0)], f"expected half of 800 us after 3005 us, got {changes}"


def test_a_short_charge_discharges_in_proportion_and_a_drive_low_empties_it():
    plant = plant_with()
    assert read_us(plant, 0, 1_000, charge_us=5)[0] == 400, "half the charge: half the time"
    assert read_us(plant, 0, 100_000, charge_us=50)[0] == 800, "a longer drive charges it no more"
    plant.advance_to(200_000)
    plant.set_input("line.0", 1)
    changes = plant.advance_to(200_020)
    plant.set_input("line.0", 0)
    changes = [(c.t_us, c.value) for c in changes + plant.advance_to(200_020) if c.name == "line.0"]
    assert changes == [(200_000, 1), (200_020, 0)]
    plant.set_input("line.0", RELEASED)
    assert [c for c in plant.advance_to(300_000) if c.name == "line.0"] == [], "nothing held: stays low"


def test_the_reading_follows_the_floor_as_the_robot_drives_across_the_tape():
    qtr = {"kind": "qtr", "name": "line", "emitter": "none", "mount": {"x_m": 0.05}}
    plant = assemble({"body": "differential", "start_pose": [0.8, 1.0, 0.0], "tape": TAPE, "parts": [*MOTORS, qtr]})
    for side in "lr":
        plant.set_input(f"motor_{side}.in1", 1)
        plant.set_input(f"motor_{side}.in2", 0)
        plant.set_input(f"motor_{side}.pwm", 65535)
    readings = []
    for k in range(200):
        t = 5_000 * k + 1_000
        us, _ = read_us(plant, 0, t, window_us=2_000)
        x = plant.truth()["x_m"] + 0.05
        readings.append((round(x, 4), us, plant.truth()["line_on_tape"][0]))
    assert {us for _, us, _ in readings} == {150, 800}, "the robot crossed the tape"
    for x, us, on in readings:  # (the channel moves a few mm during a 1 ms read: allow the edge)
        if abs(abs(x - 1.0) - 0.0095) > 0.003:
            assert on == (abs(x - 1.0) < 0.0095), (x, on)
            assert us == (800 if on else 150), (x, us)


def test_times_out_of_order_are_refused_by_name():
    with pytest.raises(PartsError, match=r"\(line\).*white_us < black_us <= unlit_us"):
        plant_with(white_us=900)


def test_a_bump_channel_reads_black_while_the_wall_presses_its_flap_and_white_before():
    """flaps_deg: each channel looks at a bumper flap over an arc of the body's edge, not the
    floor (the 3pi+'s bump sensors): driven into the east wall 10 degrees to the right of
    square on, the contact is left of the heading: the left flap's channel reads black_us."""
    bump = {"kind": "qtr", "name": "bump", "offsets_m": [[0.0, 0.0]] * 2, "flaps_deg": [[35, 35], [-35, 35]]}
    body = {"body": "differential", "room_w_m": 3.0, "room_h_m": 2.0, "start_pose": [2.8, 1.0, -0.17]}
    plant = assemble({**body, "tape": TAPE, "parts": [*MOTORS, {**bump, "white_us": 300, "black_us": 700}]})
    plant.set_input("bump.emitter", 1)
    assert [read_us(plant, i, 1_000 + 30_000 * i, part="bump")[0] for i in (0, 1)] == [300, 300], "not touching"
    for side in "lr":
        plant.set_input(f"motor_{side}.in1", 1)
        plant.set_input(f"motor_{side}.in2", 0)
        plant.set_input(f"motor_{side}.pwm", 65535)
    plant.advance_to(2_000_000)  # (0.4 m/s for 2 s: against the wall 0.15 m away)
    assert plant.truth()["contacts"], f"expected the body against the east wall: {plant.truth()}"
    t = 2_000_000
    assert [read_us(plant, i, t + 30_000 * i, part="bump")[0] for i in (0, 1)] == [700, 300], "the left flap pressed"
    assert plant.truth()["bump_on_tape"] == [True, False]


def test_flaps_need_an_arc_for_each_channel():
    with pytest.raises(PartsError, match=r"flaps_deg: expected an arc for each of the 2 channels"):
        plant_with(flaps_deg=[[35, 35]])

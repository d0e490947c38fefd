"""The SunFounder Pico-4WD car (host/kits/sunfounder_pico_4wd, docs/kits.md) run with
firmware in the style of SunFounder's library (hil_tests/firmware/kits/sunfounder_pico_4wd/
car4wd.py: its imports, habits and quirks, not a copy): what the library does that the
harness once got wrong, each held to the plant's ground truth in virtual time.

- ``time_pulse_us(echo, Pin.on)``: the level is any object, true or not, as on a board
  (``extmod/machine_pulse.c``, ``mp_obj_is_true(args[1])``); it waited for a level equal to
  the function and timed out after 1 s (-2: "-0.034 cm").
- 24 WS2812 LEDs put to a PIO state machine: a frame of black (or white) comes in bursts of
  one kind of bit; each burst was counted as a timing fault (its other bit's times 0 ns),
  and each burst as a write.
- Four motors, two a side: the rig file's second ``dc_motor`` on a side was refused."""

import shutil
from pathlib import Path

import pytest

from host.kits import kit

pytestmark = pytest.mark.hil
LIBRARY = Path(__file__).parent / "firmware" / "kits" / "sunfounder_pico_4wd" / "car4wd.py"


def car(make_rig, tmp_path, main: str, **plant):
    """The kit's rig, car4wd.py and ``main`` in a folder of its own; ``plant``: options of
    the rig's [plant] table changed."""
    text = (kit("sunfounder_pico_4wd").folder / "rig.toml").read_text()
    for key, value in plant.items():
        text = text.replace("[plant]\n", f"[plant]\n{key} = {value}\n", 1)
    (tmp_path / "rig.toml").write_text(text)
    shutil.copy(LIBRARY, tmp_path / "car4wd.py")
    (tmp_path / "main.py").write_text(main)
    return make_rig(str(tmp_path / "rig.toml"), allow_exit=True)


def test_the_sonar_timed_with_pin_on_as_its_level_ranges_the_wall(make_rig, tmp_path):
    rig = car(
        make_rig,
        tmp_path,
        "import time, car4wd\nfor _ in range(3):\n"
        "    t0 = time.ticks_us()\n    d = car4wd.sonar.distance()\n"
        "    print('sonar', d, time.ticks_diff(time.ticks_us(), t0))\n    time.sleep_ms(100)\n",
    )
    for _ in range(3):
        cm, took_us = (float(v) for v in rig.expect(r"sonar (\S+) (\S+)\n").groups())
        truth = rig.truth()
        where = f"console:\n{rig.console}\nartefacts: {rig.artefacts}"
        true_cm = truth["sonar_ping_range_m"] * 100 if truth["sonar_ping_range_m"] else None
        # (the library's 340 m/s against the plant's 343: 0.9 % short)
        assert true_cm and abs(cm - true_cm * 340 / 343) < 1.0, f"read {cm} cm, the wall at {true_cm} cm; {where}"
        assert took_us < 20_000, f"the read took {took_us} us: expected the echo's 14 ms round trip; {where}"


def test_pio_leds_frames_of_white_and_of_black_are_in_tolerance_and_counted_once(make_rig, tmp_path):
    rig = car(
        make_rig,
        tmp_path,
        "import time, car4wd\ncar4wd.all_lights([255, 255, 255])\ntime.sleep_ms(20)\n"
        "car4wd.all_lights([0, 0, 0])\ntime.sleep_ms(20)\n"
        "car4wd.lights[0] = [255, 255, 255]\ncar4wd.lights.show()\ntime.sleep_ms(20)\nprint('shown')\n",
    )
    rig.expect("shown\n")
    truth = rig.truth()
    shown = [rig.plant.output(f"lights.led{i}") for i in range(24)]
    strip = rig.plant.input_owner("lights.din")
    assert shown == [0xFFFFFF] + [0] * 23, [hex(c) for c in shown]
    assert truth["lights_timing_faults"] == 0, f"{truth['lights_timing_faults']} faults: {strip.timing_problem}"
    writes = truth["lights_writes"]
    assert writes == 3, f"three frames written (white, black, one white), {writes} counted"


def test_four_motors_two_a_side_drive_spin_and_count_as_the_plant_moves(make_rig, tmp_path):
    rig = car(
        make_rig,
        tmp_path,
        "import time, car4wd\n"
        "car4wd.drive(50, 50, 50, 50)\ntime.sleep_ms(1000)\n"
        "print('forward', car4wd.slots.speed, car4wd.slots.total[0], car4wd.slots.total[1])\n"
        "car4wd.drive(50, 50, 0, 0)\ntime.sleep_ms(1000)\nprint('front')\n"
        "car4wd.drive(-50, 50, -50, 50)\ntime.sleep_ms(500)\nprint('left')\n"
        "car4wd.drive(0, 0, 0, 0)\ntime.sleep_ms(300)\nprint('stopped')\n",
        v_max_m_s=0.4,
    )
    start = rig.truth()
    speed_cm_s, left, right = (float(v) for v in rig.expect(r"forward (\S+) (\S+) (\S+)\n").groups())
    forward = rig.truth()
    where = f"console:\n{rig.console}\nartefacts: {rig.artefacts}"
    assert forward["x_m"] - start["x_m"] > 0.2 and abs(forward["y_m"] - start["y_m"]) < 1e-3, (forward, where)
    assert abs(forward["theta_rad"]) < 1e-3, (forward, where)
    slot_cm = 2 * 3.14159 * 3.3 / 20
    assert abs(speed_cm_s - forward["v_m_s"] * 100) <= 5 * slot_cm, f"{speed_cm_s} cm/s, the body {forward}; {where}"
    for n, edges in ((left, forward["speed_l_edges"]), (right, forward["speed_r_edges"])):
        assert abs(n - edges // 2) <= 1, f"{n} slots counted by the 200 ms Timer, the disk's {edges} edges; {where}"
    rig.expect("front\n")
    front = rig.truth()
    # (the rear motors braked, the front ones at 60 %: each side at their mean, 30 %)
    assert 0 < front["v_m_s"] < forward["v_m_s"] * 0.6, (front["v_m_s"], forward["v_m_s"], where)
    rig.expect("left\n")
    spun = rig.truth()
    assert spun["theta_rad"] - front["theta_rad"] > 0.5, f"'left' turns anticlockwise: {front} then {spun}; {where}"
    assert abs(spun["x_m"] - front["x_m"]) < 0.01, (front, spun, where)
    rig.expect("stopped\n")
    assert all(abs(w) < 0.05 for w in rig.truth()["wheel_rad_s"]), f"braked 300 ms: {rig.truth()}; {where}"

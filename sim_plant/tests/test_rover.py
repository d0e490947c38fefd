"""The rover, built from its rig file's body and parts: its encoders, sonar ADC and
bumper as a board sees them."""

import math
from pathlib import Path

import pytest

from sim_plant.catalogue.assembly import assemble_file
from sim_plant.sonars import MAXBOTIX_V_PER_M as SONAR_V_PER_M

RIG = Path(__file__).resolve().parents[2] / "firmware" / "apps" / "rover" / "rig.toml"
WHEEL_RADIUS_M, V_MAX_M_S, BODY_RADIUS_M = 0.033, 0.5, 0.17


def rover_plant(parts=None, **options):
    """The rover of its rig file, with body options (and part options by name) changed."""
    return assemble_file(RIG, parts, **options)


def test_the_rig_file_says_what_the_rover_is():
    body = rover_plant().body.options
    assert (body["wheel_radius_m"], body["v_max_m_s"], body["body_radius_m"]) == (
        WHEEL_RADIUS_M,
        V_MAX_M_S,
        BODY_RADIUS_M,
    )


def drive(plant, duty_l, duty_r, forward=True):
    for side, duty in (("l", duty_l), ("r", duty_r)):
        plant.set_input(f"motor_{side}.in1", 1 if forward else 0)
        plant.set_input(f"motor_{side}.in2", 0 if forward else 1)
        plant.set_input(f"motor_{side}.pwm", duty)


def test_one_wheel_revolution_gives_80_quadrature_edges_with_a_leading():
    plant = rover_plant(room_w_m=100)
    drive(plant, 65535, 65535)
    rev_s = 2 * math.pi * WHEEL_RADIUS_M / V_MAX_M_S
    changes = plant.advance_to(round(rev_s * 1e6) + 1)
    left = [c for c in changes if c.name.startswith("enc_l")]
    assert len(left) == 80
    assert [c.name for c in left[:4]] == ["enc_l.a", "enc_l.b", "enc_l.a", "enc_l.b"]
    assert [c.value for c in left[:2]] == [1, 1], "forward: A rises before B"
    assert all(a.t_us <= b.t_us for a, b in zip(left, left[1:]))


def test_reverse_makes_b_lead_and_stepping_matches_one_call():
    a, b = rover_plant(room_w_m=100), rover_plant(room_w_m=100)
    for plant in (a, b):
        drive(plant, 40000, 30000, forward=False)
    whole = [c for c in a.advance_to(300_000) if c.name != "sonar.adc"]
    stepped = []
    while b.t_us < 300_000:
        stepped += [c for c in b.advance_to(min(b.next_change_us(), 300_000)) if c.name != "sonar.adc"]
    first_left = next(c for c in whole if c.name.startswith("enc_l"))
    assert (first_left.name, first_left.value) == ("enc_l.b", 1), "reverse: B rises before A"
    assert [(c.t_us, c.name, c.value) for c in whole] == [(c.t_us, c.name, c.value) for c in stepped]


def test_dead_band_duty_does_not_move_the_wheel():
    plant = rover_plant()
    drive(plant, int(0.05 * 65535), int(0.05 * 65535))
    changes = plant.advance_to(1_000_000)
    assert [c for c in changes if c.name.startswith("enc")] == []
    assert plant.truth()["distance_m"] == 0.0


def test_sonar_gives_a_new_adc_sample_every_500ms_from_the_range_ahead():
    plant = rover_plant({"sonar": {"noise_sd_m": 0.0}}, room_w_m=5.0, start_pose=[1.0, 2.0, 0.0])
    samples = [c for c in plant.advance_to(2_100_000) if c.name == "sonar.adc"]
    assert [c.t_us for c in samples] == [20_000, 520_000, 1_020_000, 1_520_000, 2_020_000]
    range_m = 5.0 - 1.0 - BODY_RADIUS_M
    counts = round(range_m * SONAR_V_PER_M / 3.3 * 4095)
    assert samples[0].value == (counts << 4) | (counts >> 8)


def test_bumper_closes_at_the_wall_and_is_recorded_in_ground_truth():
    plant = rover_plant(room_w_m=3.0, start_pose=[2.0, 2.0, 0.0])
    drive(plant, 30000, 30000)
    changes = plant.advance_to(10_000_000)
    bumps = [c for c in changes if c.name == "bumper.out"]
    assert bumps and bumps[0].value == 0
    truth = plant.truth()
    assert truth["bumper.out_pressed"] and truth["contacts"][0][0] == bumps[0].t_us
    assert math.isclose(truth["x_m"], 3.0 - BODY_RADIUS_M)


def test_same_seed_same_sonar_noise():
    runs = []
    for _ in range(2):
        plant = rover_plant()
        plant.reset(42)
        runs.append([c.value for c in plant.advance_to(5_000_000) if c.name == "sonar.adc"])
    other = rover_plant()
    other.reset(43)
    assert runs[0] == runs[1]
    assert runs[0] != [c.value for c in other.advance_to(5_000_000) if c.name == "sonar.adc"]


def test_snapshot_and_restore_replay_the_same_future():
    plant = rover_plant()
    drive(plant, 30000, 20000)
    plant.advance_to(700_000)
    snap = plant.snapshot()
    first = plant.advance_to(3_000_000)
    truth = plant.truth()
    plant.restore(snap)
    assert plant.advance_to(3_000_000) == first and plant.truth() == truth


def test_a_snapshot_brings_the_generator_back_as_its_state_dict_would():
    """The generator is saved as raw bytes (``engine._RawGenerator``): after draws of every
    width (a buffered 32-bit half included) a restore gives the state a snapshot of
    ``bit_generator.state`` gave, and the same draws after."""
    import numpy as np

    from sim_plant.engine import _raw_generator

    plant = rover_plant()
    plant.rng.integers(0, 2**32, dtype=np.uint32)  # (a half left buffered)
    state = plant.rng.bit_generator.state
    snap = plant.snapshot()
    assert plant._raw_rng is not None, "expected the PCG64 generator saved raw"
    draws = [plant.rng.random(), int(plant.rng.integers(0, 2**32, dtype=np.uint32)), plant.rng.normal()]
    plant.restore(snap)
    assert plant.rng.bit_generator.state == state
    again = [plant.rng.random(), int(plant.rng.integers(0, 2**32, dtype=np.uint32)), plant.rng.normal()]
    assert again == draws, f"expected the same draws after a restore: {draws}, got {again}"
    assert _raw_generator(np.random.Generator(np.random.MT19937(1))) is None  # (another generator: its dict)


def test_coverage_sampled_at_bends_matches_sampling_every_change_of_motion():
    """A board trims its wheel duties every 50 ms; the recorder samples those changes
    only where the path bends or turns back. The swept cells match a recorder that
    samples every change, over straight runs, a straight reversal in open floor, arcs
    and turns on the spot."""
    import random

    import numpy as np

    import sim_plant.physics.coverage as coverage
    from sim_plant.physics.coverage import CoverageRecorder

    def swept(bend_rad):
        old = coverage.BEND_RAD
        coverage.BEND_RAD = bend_rad
        try:
            plant = rover_plant(room_w_m=4.0, room_h_m=4.0, start_pose=[0.5, 0.5, 0.3])
            plant.reset(2)
            rnd = random.Random(5)
            base = [(30000, 30000), (-30000, -30000), (30000, 45000), (25000, 25000), (40000, 0)]
            t = 0
            for step in range(500):  # 25 s: 50 ms control steps, segments of 1.25 s
                left, right = base[(step // 25) % len(base)]
                for side, duty in (("l", left), ("r", right)):
                    duty += rnd.randrange(-800, 800) if duty else 0
                    plant.set_input(f"motor_{side}.in1", 1 if duty > 0 else 0)
                    plant.set_input(f"motor_{side}.in2", 1 if duty < 0 else 0)
                    plant.set_input(f"motor_{side}.pwm", abs(duty))
                t += 50_000
                plant.advance_to(t)
            plant.truth()
            grid = plant.part(CoverageRecorder).grid
            return grid.covered.copy(), len(plant.truth()["contacts"])
        finally:
            coverage.BEND_RAD = old

    every, contacts = swept(-1.0)  # every change of motion is a sample
    assert contacts, "the path should also slide along a wall"
    bends, _ = swept(coverage.BEND_RAD)
    assert every.sum() > 80, "the robot should sweep a good part of the room"
    differ = int(np.logical_xor(every, bends).sum())
    assert differ == 0, f"{differ} of {int(every.sum())} swept cells differ"


@pytest.mark.parametrize("reverse_at_us", [1_090_000, 1_150_000, 1_190_000])
def test_coverage_reaches_the_point_where_the_robot_turned_back(reverse_at_us):
    """Straight ahead, then straight back in open floor: the turning point is sampled
    (the heading does not change there), as a path sampled every millisecond shows."""
    from sim_plant.physics.coverage import CoverageRecorder

    def swept(dense):
        plant = rover_plant(start_pose=[1.0, 2.0, 0.0])
        grid = plant.part(CoverageRecorder).grid
        t = 0

        def drive(duty, until_us):
            nonlocal t
            for side in "lr":
                plant.set_input(f"motor_{side}.in1", 1 if duty > 0 else 0)
                plant.set_input(f"motor_{side}.in2", 1 if duty < 0 else 0)
                plant.set_input(f"motor_{side}.pwm", abs(duty))
            while t < until_us:
                t = min(t + 1_000, until_us) if dense else until_us
                plant.advance_to(t)
                if dense:
                    grid.add_point(*plant.pose_at(t)[:2])

        drive(65535, reverse_at_us)
        drive(-65535, reverse_at_us + 1_000_000)
        drive(0, reverse_at_us + 1_100_000)
        grid.flush()
        return grid.covered.copy()

    reference, got = swept(dense=True), swept(dense=False)
    missed = int((reference & ~got).sum())
    assert missed == 0, f"{missed} cells swept on the way out are not marked"

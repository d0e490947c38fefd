"""Seed 002's duct robot: amplitude sonars on an 8-bit ADC, slotted-disk encoders, spin slip,
LMD18200 bridges, and the duct worlds."""

import math

import pytest

from sim_plant.duct import BODY_CIRCLES
from sim_plant.physics.amplitude_sonar import AmplitudeChannel, AmplitudeSonarArray
from sim_plant.physics.tether import TetherSnag
from sim_plant.tests.rigs import duct_robot
from sim_plant.world import World, one_right_branch_duct

DEG = math.pi / 180


def counts8(u16):
    assert u16 % 257 == 0, "an 8-bit reading scaled to 16 bits by read_u16"
    return u16 // 257


def array(**options):
    return AmplitudeSonarArray([AmplitudeChannel("s.adc", (0.0, 0.0, 0.0))], noise_v=0.0, corner_spike_p=0.0, **options)


class _Plant:
    """Just what AmplitudeSonarArray.fire asks of a plant: a pose, a world, a generator."""

    def __init__(self, world, pose):
        import numpy as np

        self.world, self.pose, self.rng = world, pose, np.random.default_rng(0)

    def pose_at(self, t_us):
        return self.pose


def reading(sonar, world, pose, t_us=25_000):
    out = []
    sonar.fire(t_us, _Plant(world, pose), out)
    return counts8(sonar.channels[0].value)


WALL = World([(1.0, -5.0, 1.0, 5.0)], name="one wall at x = 1 m")


def test_reading_rises_as_the_range_shrinks_and_saturates_at_30_mm():
    """Seed 002 App. C: "as the distance to the objects gets smaller, the ADC reading gets
    bigger"; "The minimum range of the sonars was 30mm"; "the 8 bit ADC was implemented"."""
    ranges = (0.6, 0.3, 0.15, 0.08, 0.03, 0.02)
    values = [reading(array(discharge_tau_ms=0), WALL, (1.0 - r, 0.0, 6 * DEG)) for r in ranges]
    assert values == sorted(values) and len(set(values)) == len(values) - 1
    assert values[-2] == values[-1] == 255
    assert values[0] == round(5.0 * 0.03 / 0.6 / 5.0 * 255)


def test_return_is_strongest_at_5_to_8_degrees_and_absent_at_35():
    """Seed 002 App. C.4.2: "At about 35° the return signal can be considered as absent and
    between 5° and 8° the signal was at its maximum"."""
    sonar_at = {a: reading(array(discharge_tau_ms=0), WALL, (0.8, 0.0, a * DEG)) for a in (0, 3, 6, 8, 15, 25, 34, 36)}
    assert sonar_at[6] == sonar_at[8] == max(sonar_at.values())
    assert sonar_at[0] < sonar_at[6] and sonar_at[15] < sonar_at[8] and sonar_at[25] < sonar_at[15]
    assert sonar_at[36] == 0


def test_an_opening_makes_the_reading_slope_down_as_the_peak_detector_discharges():
    """Seed 002 App. C.4.3: "the sonar circuitry stored the distance as a charge there is a
    finite discharging time. When the branch was detected, the value was effectively zero, but
    the finite discharging time created the slope seen"."""
    quiet = {f"sonar_{s}.{o}": 0.0 for s in "flr" for o in ("noise_sd_v", "corner_spike_p")}
    plant = duct_robot(start_pose=(1.2, 0.2, 0.0), **quiet)
    for side in "lr":
        plant.set_input(f"motor_{side}.dir", 1)
        plant.set_input(f"motor_{side}.pwm", 30_000)
    trace = []
    while plant.t_us < 3_000_000:
        plant.advance_to(plant.t_us + 25_000)
        trace.append((plant.truth()["x_m"], counts8(plant.output("sonar_r.adc"))))
    before = [v for x, v in trace if 1.25 < x < 1.45]
    assert before and min(before) == max(before) > 50, "a steady wall before the branch at x = 1.5 m"
    opening = next(i for i, (x, _) in enumerate(trace) if x > 1.5 + 0.10)  # sonar 0.10 m behind the axle
    slope = [v for _, v in trace[opening : opening + 12]]
    assert slope == sorted(slope, reverse=True)
    assert slope[1] > 0.5 * before[0], "one update later the reading is still high"
    assert slope[-1] < 0.2 * before[0], "and it has decayed within 0.3 s (tau = 150 ms)"
    assert slope[1] / slope[2] == pytest.approx(math.exp(0.025 / 0.150), rel=0.05)


def test_corners_in_the_beam_can_spike_the_reading():
    """Seed 002 §5.6: "drastic increase on the left sonar reading at reading 106 was
    attributed to the reflection caused by the corner as the robot turned"."""
    corner = World([(0.0, 0.5, 2.0, 0.5), (2.0, 0.5, 2.0, -1.0)], name="an inside corner")
    pose = (1.75, 0.25, 45 * DEG)  # looking straight into the corner, walls at 45 degrees
    quiet = reading(array(discharge_tau_ms=0), corner, pose)
    spiky = AmplitudeSonarArray(
        [AmplitudeChannel("s.adc", (0.0, 0.0, 0.0))], noise_v=0.0, corner_spike_p=1.0, discharge_tau_ms=0
    )
    assert quiet == 0 and reading(spiky, corner, pose) == round(5.0 * 0.03 / math.hypot(0.25, 0.25) / 5.0 * 255)


def test_slotted_disks_on_the_motor_shaft_count_slots_times_gear_ratio_per_wheel_turn():
    """Seed 002 §3.3.3: "A slotted encoder disk, mounted on the motor shaft"; one channel,
    an edge each way per slot."""
    disks = {f"enc_{s}.{o}": v for s in "lr" for o, v in (("lines_per_rev", 8), ("gear_ratio", 6.0))}
    plant = duct_robot(World([(-50, -1, 50, -1), (-50, 1, 50, 1)]), start_pose=(0, 0, 0), **disks)
    for side in "lr":
        plant.set_input(f"motor_{side}.dir", 1)
        plant.set_input(f"motor_{side}.pwm", 65535)
    turn_us = round(2 * math.pi * plant.body.options["wheel_radius_m"] / plant.body.options["v_max_m_s"] * 1e6)
    changes = [c for c in plant.advance_to(turn_us) if c.name == "enc_l.out"]
    assert len(changes) == 2 * 8 * 6
    assert [c.value for c in changes[:4]] == [1, 0, 1, 0]


def test_slotted_disks_cannot_tell_direction():
    """Seeds 002/003: single-channel encoders: backwards looks like forwards."""
    seqs = []
    for direction in (1, 0):
        plant = duct_robot(World([(-50, -1, 50, -1), (-50, 1, 50, 1)]), start_pose=(0, 0, 0))
        for side in "lr":
            plant.set_input(f"motor_{side}.dir", direction)
            plant.set_input(f"motor_{side}.pwm", 40_000)
        seqs.append([(c.name, c.value) for c in plant.advance_to(1_000_000) if c.name.startswith("enc")])
    assert seqs[0] == seqs[1] and len(seqs[0]) > 20


def test_spins_slip_the_backward_wheel_without_counts():
    """Seed 002 §5.7: "During the spin, the right wheel was pushed back by the left wheel, not
    producing any rotation of the wheel encoder": a right spin (left +, right -) turns the
    body by the commanded amount while the right encoder sees only (1 - spin_slip) of it."""
    plant = duct_robot(World([(-50, -5, 50, -5)]), start_pose=(0, 0, 0), spin_slip=0.3)
    plant.set_input("motor_l.dir", 1)
    plant.set_input("motor_r.dir", 0)
    for side in "lr":
        plant.set_input(f"motor_{side}.pwm", 30_000)
    changes = plant.advance_to(2_000_000)
    left = sum(c.name == "enc_l.out" for c in changes)
    right = sum(c.name == "enc_r.out" for c in changes)
    assert right == pytest.approx(0.7 * left, abs=2)
    w = plant.truth()["wheel_rad_s"][0]
    turned = -2 * w * plant.body.options["wheel_radius_m"] / 0.18 * 2.0
    assert plant.truth()["theta_rad"] == pytest.approx(math.remainder(turned, 2 * math.pi), abs=1e-9)


def test_lmd18200_dir_sets_the_direction_and_pwm_the_magnitude():
    """Seed 002 §3.3.3: LMD18200 H-bridges, "a PWM signal of 12V"; DIR + PWM (sign/magnitude)."""
    plant = duct_robot(start_pose=(1.0, 0.2, 0.0))
    assert set(plant.inputs) == {"motor_l.dir", "motor_l.pwm", "motor_r.dir", "motor_r.pwm", "link.uart"}
    plant.set_input("motor_l.pwm", 30_000)
    plant.set_input("motor_r.pwm", 30_000)
    plant.advance_to(500_000)
    assert plant.truth()["x_m"] < 1.0, "DIR low drives backwards"
    plant.set_input("motor_l.dir", 1)
    plant.set_input("motor_r.dir", 1)
    x = plant.truth()["x_m"]
    plant.advance_to(1_000_000)
    assert plant.truth()["x_m"] > x


def test_one_right_branch_duct_is_open_to_the_right_at_the_branch():
    """Seed 002 §5.5-5.8: a duct with one right branch (both side walls seen, then the right
    one disappears at the branch)."""
    world = one_right_branch_duct()
    assert world.ray(1.0, 0.2, -math.pi / 2)[0] == pytest.approx(0.2)
    assert world.ray(1.7, 0.2, -math.pi / 2)[0] == pytest.approx(0.2 + 1.2)
    assert world.ray(1.7, 0.2, math.pi / 2)[0] == pytest.approx(0.2)
    assert world.ray(0.5, 0.2, 0.0)[0] == pytest.approx(2.5)
    assert world.contains(1.7, -1.0) and not world.contains(1.2, -0.5)


def test_touching_a_duct_wall_is_recorded_though_the_robot_has_no_bumper():
    """Seed 002 §6: the real robot had no bump sensors; contacts are ground truth only."""
    plant = duct_robot(start_pose=(1.0, 0.2, 0.3))
    assert not any(name.startswith("bumper") for name in plant.outputs)
    for side in "lr":
        plant.set_input(f"motor_{side}.dir", 1)
        plant.set_input(f"motor_{side}.pwm", 30_000)
    plant.advance_to(3_000_000)
    contacts = plant.truth()["contacts"]
    assert contacts and contacts[0].part == "body"
    x, y, th = plant.pose_at(plant.t_us)
    for ox, _oy, r in BODY_CIRCLES:
        assert y + math.sin(th) * ox + r <= 0.4 + 1e-9, "held at the wall, not through it"


def _spin_twice(plant, seed, waste=0):
    """Reset, draw ``waste`` numbers from the plant's generator (as other parts would), then
    spin, stop, spin again; the snags that came."""
    plant.reset(seed)
    plant.rng.random(waste)
    for t_us, (left, right, pwm) in ((0, (1, 0, 30_000)), (400_000, (1, 1, 0)), (800_000, (1, 0, 30_000))):
        plant.advance_to(t_us)
        plant.set_input("motor_l.dir", left)
        plant.set_input("motor_r.dir", right)
        for side in "lr":
            plant.set_input(f"motor_{side}.pwm", pwm)
    plant.advance_to(1_200_000)
    snag = plant.part(TetherSnag)
    return snag.spins, snag.events


def test_a_snag_can_be_kept_to_chosen_spins():
    plant = duct_robot("bench_duct", start_pose=(2.0, 0.2, 0.0), **{"tether.snag_p": 1.0, "tether.spins": [1]})
    spins, events = _spin_twice(plant, 3)
    assert spins == 2 and [e[0] for e in events] == [950_000], f"expected one snag, 150 ms into spin 2: {events}"


def test_whether_and_how_a_spin_snags_depends_on_the_seed_alone():
    """The draws are taken at reset: how much the rest of the plant draws from the shared
    generator afterwards (a drive or firmware change would shift it) changes nothing."""
    plant = duct_robot("bench_duct", start_pose=(2.0, 0.2, 0.0), **{"tether.snag_p": 0.5})
    runs = {seed: _spin_twice(plant, seed) for seed in range(8)}
    assert any(events for _n, events in runs.values()) and not all(events for _n, events in runs.values())
    for seed, (spins, events) in runs.items():
        assert _spin_twice(plant, seed, waste=1000) == (spins, events), f"seed {seed}: snags moved with other draws"

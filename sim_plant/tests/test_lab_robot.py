"""Seed 004's dead-reckoning lab robot, built from its rig files (a differential body over
catalogue parts): quadrature encoders (Table 1), DRV8833 two-PWM bridges, the odometry the
encoders support, wheel slip, missed edges, the sonars' RX line, the program jumper, and
its worlds."""

import math
from pathlib import Path

import pytest

from sim_plant.catalogue.assembly import assemble_file
from sim_plant.physics.encoder import QuadratureEncoder, SlottedDiskEncoder
from sim_plant.world import CANYON_END_M, canyon_centre_m

APP = Path(__file__).resolve().parents[2] / "firmware" / "apps" / "lab_robot"
RIG, CANYON_RIG = APP / "rig.toml", APP / "rig-canyon.toml"
WHEEL_RADIUS_M = 0.035  # the rig file's body: the seed's numbers are checked against these
TRACK_M = 0.20


def open_floor(parts=None, **options):
    """The lab robot (rig.toml) in a 100 x 100 m room, at its middle facing +x: ``parts``
    (a part's name -> options) and body ``options`` over the rig file's."""
    return assemble_file(RIG, parts, room_w_m=100.0, room_h_m=100.0, start_pose=[50.0, 50.0, 0.0], **options)


def both(prefix: str, **options) -> dict:
    """The same options for both wheels' parts (``enc_l`` and ``enc_r`` for ``enc``)."""
    return {f"{prefix}_{side}": dict(options) for side in "lr"}


def test_the_rig_files_body_is_the_seeds_robot():
    """The figures the checks below use are the rig files' (r = 35 mm, w = 0.2 m, 80
    counts a wheel turn)."""
    for rig in (RIG, CANYON_RIG):
        plant = assemble_file(rig)
        assert plant.body.options["wheel_radius_m"] == WHEEL_RADIUS_M
        assert plant.body.options["track_m"] == TRACK_M
        counts = {p.name: p.metres_per_edge(plant.body.options) for p in plant.catalogue_parts if p.kind == "encoder"}
        assert counts == pytest.approx({"enc_l": 2 * math.pi * 0.035 / 80, "enc_r": 2 * math.pi * 0.035 / 80})


def drive(plant, left: float, right: float):
    """Signed duty per wheel through the DRV8833 inputs (IN1 PWM forwards, IN2 backwards)."""
    for side, duty in (("l", left), ("r", right)):
        plant.set_input(f"motor_{side}.in1", round(max(duty, 0) * 65535))
        plant.set_input(f"motor_{side}.in2", round(max(-duty, 0) * 65535))


class Table1Decoder:
    """Seed 004 §1.2: a phase change to the next phase (0 -> 1 -> 2 -> 3 -> 0) counts +1, to
    the previous one -1; a jump of two phases is an error."""

    PHASE = {(0, 0): 0, (1, 0): 1, (1, 1): 2, (0, 1): 3}

    def __init__(self, a=0, b=0):
        self.levels = {"a": a, "b": b}
        self.phase = self.PHASE[(a, b)]
        self.count = self.errors = 0
        self.last = 1
        self.phases = [self.phase]

    def edge(self, channel, level):
        self.levels[channel] = level
        phase = self.PHASE[(self.levels["a"], self.levels["b"])]
        step = (phase - self.phase) % 4
        self.count += {1: 1, 3: -1}.get(step, 0)
        self.errors += step == 2
        self.phase = phase
        self.phases.append(phase)


class InstantDecoder(Table1Decoder):
    """A decoder that reads the channels once per instant, as a board's IRQ handler does
    when it runs after every edge of that instant has come."""

    def __init__(self):
        super().__init__()
        self.t_us = None

    def change(self, t_us, channel, level):
        if t_us != self.t_us:
            self.flush()
            self.t_us = t_us
        self.levels[channel] = level

    def flush(self):
        phase = self.PHASE[(self.levels["a"], self.levels["b"])]
        step = (phase - self.phase) % 4
        if step == 2:
            self.errors += 1
            self.count += 2 * self.last
        elif step:
            self.last = {1: 1, 3: -1}[step]
            self.count += self.last
        self.phase = phase


def decode(changes, side="l"):
    dec = Table1Decoder()
    for c in changes:
        if c.name.startswith(f"enc_{side}."):
            dec.edge(c.name[-1], c.value)
    return dec


def test_forward_runs_through_the_phases_of_table_1_and_backward_runs_them_back():
    """Seed 004 Table 1: phases AB = 00, 10, 11, 01; increasing phase one way, decreasing
    the other, one channel changing per edge."""
    forward, backward = open_floor(), open_floor()
    drive(forward, 0.5, 0.5)
    drive(backward, -0.5, -0.5)
    fwd = decode(forward.advance_to(500_000))
    bwd = decode(backward.advance_to(500_000))
    assert fwd.phases[:9] == [0, 1, 2, 3, 0, 1, 2, 3, 0]
    assert bwd.phases[:9] == [0, 3, 2, 1, 0, 3, 2, 1, 0]
    assert fwd.errors == bwd.errors == 0 and fwd.count == -bwd.count > 0


def test_decoded_counts_give_the_wheel_travel_to_one_count():
    """Seed 004 eq. 4: S = R mu sum(+-1), mu = 2 pi / counts per wheel revolution
    (4 x lines x gear ratio); with the odometry equations (Eq. 1) the decoded counts give the
    distance and heading (error-less encoders, no slip)."""
    plant = open_floor(both("enc", lines_per_rev=10, gear_ratio=2.0))
    drive(plant, 0.6, 0.3)
    changes = plant.advance_to(3_000_000)
    mu = 2 * math.pi / (4 * 10 * 2.0)
    s_l = decode(changes, "l").count * WHEEL_RADIUS_M * mu
    s_r = decode(changes, "r").count * WHEEL_RADIUS_M * mu
    w_l, w_r = plant.truth()["wheel_rad_s"]
    assert s_l == pytest.approx(w_l * 3.0 * WHEEL_RADIUS_M, abs=WHEEL_RADIUS_M * mu)
    assert s_r == pytest.approx(w_r * 3.0 * WHEEL_RADIUS_M, abs=WHEEL_RADIUS_M * mu)
    assert (s_r - s_l) / TRACK_M == pytest.approx(plant.truth()["theta_rad"], abs=2 * mu * 0.035 / 0.2)


def test_a_mirrored_encoder_runs_its_phases_backwards():
    """Polarity -1: an encoder mounted the other way round (B leads A going forwards)."""
    plant = open_floor({"enc_r": {"polarity": -1}})
    drive(plant, 0.5, 0.5)
    changes = plant.advance_to(500_000)
    assert decode(changes, "l").count > 0 > decode(changes, "r").count


def test_drv8833_two_pwm_truth_table():
    """DRV8833: (PWM, low) forwards at the duty, (high, PWM) forwards at 1 - duty, (low, PWM)
    backwards, (high, high) brake."""
    speeds = {}
    for label, (in1, in2) in {
        "fast": (40_000, 0),
        "slow": (65535, 40_000),
        "back": (0, 40_000),
        "brake": (65535, 65535),
        "coast": (0, 0),
    }.items():
        plant = open_floor()
        for side in "lr":
            plant.set_input(f"motor_{side}.in1", in1)
            plant.set_input(f"motor_{side}.in2", in2)
        speeds[label] = plant.truth()["wheel_rad_s"][0]
    duty = lambda d: (d - 0.05) / 0.95 * 0.5 / 0.035  # noqa: E731  (dead band 5 %, 0.5 m/s, r = 35 mm)
    assert speeds["fast"] == pytest.approx(duty(40_000 / 65535))
    assert speeds["slow"] == pytest.approx(duty(1 - 40_000 / 65535))
    assert speeds["back"] == pytest.approx(-speeds["fast"])
    assert speeds["brake"] == speeds["coast"] == 0.0


def test_lines_and_gear_ratio_set_the_counts_per_wheel_turn():
    """Counts per wheel revolution = edges per line x lines x gear ratio."""
    assert QuadratureEncoder(("a", "b"), wheel=0, lines_per_rev=12, gear_ratio=30).edges_per_wheel_rev == 1440
    assert SlottedDiskEncoder(("s",), wheel=0, lines_per_rev=20).edges_per_wheel_rev == 40
    with pytest.raises(ValueError, match="polarity"):
        QuadratureEncoder(("a", "b"), wheel=0, lines_per_rev=12, polarity=0)


def test_square_path_sides_are_exact_arcs():
    """Seed 004 Fig. 8: a 2 m square of straight sides and turns on the spot; the plant moves
    on exact arcs, so four quarter turns and four sides close the square."""
    plant = assemble_file(RIG, both("motor", deadband_duty=0.0), room_w_m=6.0, room_h_m=6.0, start_pose=[2.0, 2.0, 0.0])
    corners = []
    for _ in range(4):
        drive(plant, 0.5, 0.5)
        plant.advance_to(plant.t_us + round(2.0 / plant.truth()["v_m_s"] * 1e6))
        corners.append(plant.pose_at(plant.t_us)[:2])
        drive(plant, -0.5, 0.5)
        plant.advance_to(plant.t_us + round(math.pi / 2 / plant.truth()["w_rad_s"] * 1e6))
    x, y, th = plant.pose_at(plant.t_us)
    assert corners[0] == pytest.approx((4.0, 2.0), abs=1e-6)
    assert corners[1] == pytest.approx((4.0, 4.0), abs=1e-5)
    assert (x, y) == pytest.approx((2.0, 2.0), abs=1e-5)
    assert math.remainder(th, 2 * math.pi) == pytest.approx(0.0, abs=1e-5)


def test_canyon_world_has_walls_on_both_sides_and_an_open_end():
    """Seed 004 §2.4 (Fig. 10): the S-curve "canyon"; wall following stops where no wall is
    seen. The robot starts 0.4 m off the left wall (the one it follows), 0.8 m off the right."""
    plant = assemble_file(CANYON_RIG)
    x, y, th = plant.pose_at(0)
    left = plant.world.ray(x, y, th + math.pi / 2)[0]
    right = plant.world.ray(x, y, th - math.pi / 2)[0]
    assert left == pytest.approx(0.4, abs=1e-9) and right == pytest.approx(0.8, abs=1e-9)
    for x_m in (1.0, 5.0, 7.5, 10.0, 15.0):  # 1.2 m wide all along its centre line
        y_m = canyon_centre_m(x_m)
        assert plant.world.clearance(x_m, y_m)[0] == pytest.approx(0.6, abs=0.01)
    assert math.isinf(plant.world.ray(CANYON_END_M + 0.1, canyon_centre_m(CANYON_END_M), math.pi / 2)[0])
    assert math.isinf(plant.world.ray(CANYON_END_M - 1.0, canyon_centre_m(CANYON_END_M), 0.0)[0])


def test_canyon_cannot_be_driven_straight_through():
    """The S shifts the corridor 1.2 m sideways: a robot that keeps its start heading hits
    a wall, so getting through it takes wall following."""
    plant = assemble_file(CANYON_RIG)
    x, y, th = plant.pose_at(0)
    hit_m = plant.world.ray(x, y, th)[0]
    assert hit_m < CANYON_END_M - x


def test_canyon_bends_are_gentle_s_curve():
    """Left bend, then right bend, at most 11.3 degrees off the x axis (slope 2 x 1.2 / 12)."""
    xs = [i * 0.05 for i in range(round(CANYON_END_M / 0.05) + 1)]
    slopes = [(canyon_centre_m(b) - canyon_centre_m(a)) / 0.05 for a, b in zip(xs, xs[1:])]
    assert max(slopes) == pytest.approx(0.2, abs=1e-3) and min(slopes) >= 0.0
    assert canyon_centre_m(0.0) == 0.0 and canyon_centre_m(CANYON_END_M) == pytest.approx(1.2)


def test_missed_edges_come_two_at_once_and_the_decoder_counts_each_as_an_error():
    """The encoders' missed_edge_p: now and then two edges of one encoder fall at the same instant; a
    Table 1 decoder that reads both channels after the instant sees a two-phase jump, once
    per missed edge, and the plant counts them in its truth."""
    plant = open_floor(both("enc", missed_edge_p=0.02))
    plant.reset(3)
    drive(plant, 0.6, -0.4)
    changes = plant.advance_to(4_000_000)
    drive(plant, -0.5, 0.5)
    changes += plant.advance_to(6_000_000)
    truth = plant.truth()
    for side in "lr":
        dec = InstantDecoder()
        for c in changes:
            if c.name.startswith(f"enc_{side}."):
                dec.change(c.t_us, c.name[-1], c.value)
        dec.flush()
        assert truth[f"enc_{side}_missed"] > 5
        assert dec.errors == truth[f"enc_{side}_missed"], side
        assert dec.count == truth[f"enc_{side}_edges"], side


def test_no_missed_edges_by_default():
    plant = open_floor()
    drive(plant, 1.0, 1.0)
    changes = plant.advance_to(2_000_000)
    times = {}
    for c in changes:
        side = c.name[4]
        assert times.get(side) != c.t_us, "two edges of one encoder at one instant"
        times[side] = c.t_us
    assert "enc_l_missed" not in plant.truth()


def test_wheel_slip_moves_the_counts_off_the_floor_travel_and_is_seeded():
    """The body's wheel_slip_sd: each wheel's encoder sees its floor travel times (1 + s), s redrawn
    every slip period; the same seed gives the same counts."""

    def run(seed):
        plant = open_floor(wheel_slip_sd=0.05, slip_period_us=100_000)
        plant.reset(seed)
        drive(plant, 0.5, 0.5)
        plant.advance_to(5_000_000)
        truth = plant.truth()
        return truth["enc_l_edges"], truth["enc_r_edges"], truth["distance_m"], truth["wheel_slip"]

    (n_l, n_r, dist_m, slip), again, other = run(1), run(1), run(2)
    assert (n_l, n_r, dist_m, slip) == again and (n_l, n_r) != other[:2]
    per_edge_m = 2 * math.pi * 0.035 / 80
    assert n_l != n_r and abs(slip[0]) > 0
    assert n_l * per_edge_m == pytest.approx(dist_m, rel=0.05)  # 50 draws of 5 %: about 0.7 %


def test_sonars_range_on_the_rx_line_and_read_the_walls():
    """Triggered rangers (ranger_trigger "sonar"): nothing until the board raises RX; then
    the front, left and left-front sonars each give one reading 49 ms later, of the ranges
    to the walls along their axes."""
    plant = assemble_file(RIG, {f"sonar_{s}": {"noise_sd_m": 0.0} for s in ("f", "l", "lf")})
    assert plant.advance_to(500_000) == []
    plant.set_input("sonar.rx", 1)
    plant.set_input("sonar.rx", 0)
    changes = plant.advance_to(600_000)
    assert sorted((c.t_us, c.name) for c in changes) == [
        (549_000, "sonar_f.adc"),
        (549_000, "sonar_l.adc"),
        (549_000, "sonar_lf.adc"),
    ]
    truth = plant.truth()
    assert truth["sonar_f_range_m"] == pytest.approx(3.0 - 0.14)
    assert truth["sonar_l_range_m"] == pytest.approx(3.0 - 0.14)
    assert truth["sonar_lf_range_m"] == pytest.approx(3.0 * math.sqrt(2) - 0.14)
    volts = {c.name: c.value / 65535 * 3.3 for c in changes}
    assert volts["sonar_f.adc"] / (3.3 / 512 / 0.0254) == pytest.approx(2.86, abs=0.003)
    assert plant.sample_period_us("sonar_l.adc") is None


def test_program_jumper_reads_low_when_fitted():
    assert assemble_file(RIG).output("jumper.out") == 1
    assert assemble_file(CANYON_RIG).output("jumper.out") == 0


def test_missed_edges_leave_the_counts_on_the_wheel_travel():
    """An edge that comes early moves no disk: after speed changes and reversals the count
    is where a plant without missed edges has it (the next edge comes when it would have;
    turning back, the early edge is taken back)."""
    counts = []
    for p in (0.0, 0.1):
        plant = open_floor(both("enc", missed_edge_p=p))
        plant.reset(5)
        for i in range(60):  # a new duty every 37 ms, now and then backwards
            duty = 0.3 + 0.5 * ((i * 7) % 10) / 10
            drive(plant, duty if i % 9 else -duty, -duty if i % 7 else duty)
            plant.advance_to((i + 1) * 37_000)
        counts.append((plant.truth()["enc_l_edges"], plant.truth()["enc_r_edges"]))
        if p:
            assert min(plant.truth()["enc_l_missed"], plant.truth()["enc_r_missed"]) > 10
    assert counts[0] == counts[1]

"""H-bridges, DC motors, the differential drive's exact arcs, contacts and bumpers."""

import math

import pytest

from sim_plant.contacts import MIN_STEP_US, RECHECK_US, Bumper, ContactMonitor, _release_s
from sim_plant.drivetrain import DiffDriveTrain
from sim_plant.engine import RobotPlant
from sim_plant.motors import DcMotor, DirPinsPwmBridge, DirPwmBridge, GangedBridges, TwoPwmBridge
from sim_plant.physics.encoder import QuadratureEncoder
from sim_plant.world import box, rectangle, room

FULL = 65535


class Bot(RobotPlant):
    """A small test robot: TB6612 with standby, quadrature encoders, a disc body with a
    front bumper, motor options and world given."""

    def __init__(self, world=None, start=(2.0, 2.0, 0.0), bounce_us=0, monitor=ContactMonitor, **motor):
        self.world = world or rectangle(10.0, 10.0)
        self.start = start
        self.bounce_us = bounce_us
        self.monitor = monitor
        self.motor = {"max_wheel_rad_s": 20.0, **motor}
        super().__init__()

    def _build(self):
        gains = self.motor.pop("gains", (1.0, 1.0))
        self.drive = DiffDriveTrain(
            bridges=(DirPinsPwmBridge("motor_l"), DirPinsPwmBridge("motor_r")),
            motors=tuple(DcMotor(gain=g, **self.motor) for g in gains),
            wheel_radius_m=0.03,
            track_m=0.2,
            start_pose=self.start,
            standby="motor.stby",
        )
        self.motor["gains"] = gains
        self.encoders = [
            QuadratureEncoder(("enc_l.a", "enc_l.b"), wheel=0, lines_per_rev=25),
            QuadratureEncoder(("enc_r.a", "enc_r.b"), wheel=1, lines_per_rev=25),
        ]
        self.parts = [self.monitor([(0.0, 0.0, 0.15)], [Bumper("bumper", bounce_us=self.bounce_us)])]


def go(plant, left, right, stby=1):
    plant.set_input("motor.stby", stby)
    for side, duty in (("l", left), ("r", right)):
        plant.set_input(f"motor_{side}.in1", 1 if duty > 0 else 0)
        plant.set_input(f"motor_{side}.in2", 1 if duty < 0 else 0)
        plant.set_input(f"motor_{side}.pwm", round(abs(duty) * FULL))


def test_tb6612_truth_table_with_standby():
    """TB6612FNG: IN1/IN2 = 1/0 forward, 0/1 reverse, 1/1 short brake, 0/0 stop; STBY low
    turns both channels off (and it is low until the board raises it)."""
    b = DirPinsPwmBridge("m")
    b.set_pin("pwm", FULL // 2)
    for (in1, in2), expect in {
        (1, 0): (0.5, False),
        (0, 1): (-0.5, False),
        (1, 1): (0.0, True),
        (0, 0): (0.0, False),
    }.items():
        b.set_pin("in1", in1)
        b.set_pin("in2", in2)
        duty, brake = b.effective()
        assert (round(duty, 3), brake) == expect
    plant = Bot()
    go(plant, 0.8, 0.8, stby=0)
    assert plant.truth()["wheel_rad_s"] == (0.0, 0.0)
    plant.set_input("motor.stby", 1)
    assert plant.truth()["wheel_rad_s"][0] > 0


def test_lmd18200_and_drv8833_effective_duty():
    lmd = DirPwmBridge("m", brake_pin=True)
    lmd.set_pin("pwm", FULL)
    assert lmd.effective() == (-1.0, False)
    lmd.set_pin("dir", 1)
    assert lmd.effective() == (1.0, False)
    lmd.set_pin("brake", 1)
    assert lmd.effective() == (0.0, True)
    drv = TwoPwmBridge("m")
    drv.set_pin("in1", FULL)
    drv.set_pin("in2", FULL // 4)
    assert drv.effective()[0] == pytest.approx(0.75, abs=1e-4)


def test_two_motors_on_a_side_drive_it_at_the_mean_of_their_duties():
    """A four-wheel car's side (SunFounder's Pico-4WD: each motor's inputs held high, one
    pulsed low): the side at the mean effective duty, braked only when both brake."""
    front, rear = TwoPwmBridge("front"), TwoPwmBridge("rear")
    side = GangedBridges([front, rear])
    assert set(side.pins) == {"front.in1", "front.in2", "rear.in1", "rear.in2"}
    for name in side.pins:
        side.set_pin(name, FULL)
    assert side.effective() == (0.0, True), "all four inputs high: both braked"
    side.set_pin("front.in2", FULL - 39321)  # 60 % low on in2: +0.6 (slow decay)
    assert side.effective()[0] == pytest.approx(0.3, abs=1e-4) and not side.effective()[1]
    side.set_pin("rear.in2", FULL - 39321)
    assert side.effective()[0] == pytest.approx(0.6, abs=1e-4)
    side.standby = True
    assert front.standby and rear.standby


def test_dc_motor_dead_band_saturation_and_gain():
    """A dead band (minimum duty that moves the wheel), linear rise, saturation, gain."""
    m = DcMotor(max_wheel_rad_s=10.0, deadband_duty=0.2, saturation_duty=0.8, gain=0.9)
    assert m.steady_rad_s(0.2) == 0.0 and m.steady_rad_s(-0.1) == 0.0
    assert m.steady_rad_s(0.5) == pytest.approx(4.5)
    assert m.steady_rad_s(-0.8) == m.steady_rad_s(-1.0) == pytest.approx(-9.0)
    with pytest.raises(ValueError, match="deadband"):
        DcMotor(max_wheel_rad_s=1.0, deadband_duty=0.9, saturation_duty=0.5)


def test_motor_lag_reaches_63_percent_after_one_time_constant():
    plant = Bot(time_constant_ms=100.0)
    go(plant, 1.0, 1.0)
    assert plant.truth()["wheel_rad_s"] == (0.0, 0.0)
    plant.advance_to(100_000)
    assert plant.truth()["wheel_rad_s"][0] == pytest.approx(20.0 * (1 - math.exp(-1)), rel=1e-6)
    plant.advance_to(2_000_000)
    assert plant.truth()["wheel_rad_s"][0] == 20.0
    assert plant.next_change_us() - plant.t_us < 100_000, "the encoders still tick"


def test_spin_and_circle_follow_exact_arcs():
    """Constant wheel speeds: the pose is the closed-form arc whatever the event times."""
    plant = Bot(world=rectangle(20.0, 20.0), start=(10.0, 10.0, 0.0))
    go(plant, 0.5, 1.0)
    changes = plant.advance_to(7_300_000)
    assert len(changes) > 500
    w_l, w_r = plant.truth()["wheel_rad_s"]
    v, w = 0.03 * (w_l + w_r) / 2, 0.03 * (w_r - w_l) / 0.2
    t = 7.3
    x = 10.0 + v / w * math.sin(w * t)
    y = 10.0 + v / w * (1 - math.cos(w * t))
    truth = plant.truth()
    assert (truth["x_m"], truth["y_m"]) == pytest.approx((x, y), abs=1e-9)
    assert truth["theta_rad"] == pytest.approx(math.remainder(w * t, 2 * math.pi), abs=1e-12)


def test_encoder_edges_fall_at_exact_microseconds():
    """Disk half way between two edges at rest; at constant speed edge k comes at
    ceil((k - 0.5) / rate) us."""
    plant = Bot()
    go(plant, 0.6, 0.6)
    w = plant.truth()["wheel_rad_s"][0]
    rate = w * 100 / (2 * math.pi) * 1e-6  # 100 counts per wheel turn
    times = [c.t_us for c in plant.advance_to(1_000_000) if c.name.startswith("enc_l")]
    assert times == [math.ceil((k - 0.5) / rate) for k in range(1, len(times) + 1)]


def test_walls_stop_the_body_and_it_slides_along_them():
    plant = Bot(world=rectangle(5.0, 5.0), start=(3.0, 4.5, math.radians(30)))
    go(plant, 0.5, 0.5)
    plant.advance_to(8_000_000)
    truth = plant.truth()
    assert truth["y_m"] == pytest.approx(5.0 - 0.15, abs=1e-9)
    assert truth["x_m"] == pytest.approx(5.0 - 0.15, abs=1e-9), "slid along the wall into the corner"
    assert len(truth["contacts"]) == 2 and truth["contacts"][0].part == "bumper"
    assert truth["bumper_pressed"]


def test_convex_obstacles_stop_the_robot():
    plant = Bot(world=room(6.0, 4.0, [box(4.0, 2.0, 0.5, 0.5)]), start=(1.0, 2.0, 0.0))
    go(plant, 0.5, 0.5)
    changes = plant.advance_to(10_000_000)
    assert [c.value for c in changes if c.name == "bumper"] == [0]
    assert plant.truth()["x_m"] == pytest.approx(4.0 - 0.25 - 0.15, abs=1e-9)


def test_bumper_bounces_then_settles_pressed():
    plant = Bot(world=rectangle(3.0, 5.0), start=(1.0, 2.5, 0.0), bounce_us=2_000)
    plant.reset(9)
    go(plant, 0.5, 0.5)
    changes = [c for c in plant.advance_to(10_000_000) if c.name == "bumper"]
    assert len(changes) >= 3 and len(changes) % 2 == 1 and changes[-1].value == 0
    assert [c.value for c in changes] == [0, 1] * (len(changes) // 2) + [0]
    assert changes[-1].t_us - changes[0].t_us <= 2_000
    assert len(plant.truth()["contacts"]) == 1


def test_bumper_releases_when_the_robot_backs_off():
    plant = Bot(world=rectangle(3.0, 5.0), start=(1.0, 2.5, 0.0))
    go(plant, 0.5, 0.5)
    plant.advance_to(8_000_000)
    go(plant, -0.5, -0.5)
    changes = [c for c in plant.advance_to(9_000_000) if c.name == "bumper"]
    assert [c.value for c in changes] == [1]
    assert changes[0].t_us - 8_000_000 <= 5_000 + 1
    assert not plant.truth()["touching"]


class DenseMonitor(ContactMonitor):
    """Reference: checks every millisecond while the body moves, planning nothing."""

    def _next_check_us(self, t_us, plant):
        planned = super()._next_check_us(t_us, plant)
        return t_us + MIN_STEP_US if self._rate_m_s > 0.0 else planned


def _normal_speed(nx, ny, rx, ry, v, w, th, t):
    """n . (velocity of the circle's centre) at time t on the free arc."""
    co, si = math.cos(w * t), math.sin(w * t)
    ox, oy = co * rx - si * ry, si * rx + co * ry
    return nx * (v * math.cos(th + w * t) - w * oy) + ny * (v * math.sin(th + w * t) + w * ox)


@pytest.mark.parametrize("seed", range(40))
def test_release_time_is_when_the_free_motion_turns_away_from_the_wall(seed):
    """_release_s against a dense scan of the centre's free velocity: it points into the
    wall until the computed time and away from it just after."""
    import random

    rnd = random.Random(seed)
    a = rnd.uniform(-math.pi, math.pi)
    nx, ny = math.cos(a), math.sin(a)
    rx, ry = (0.0, 0.0) if seed % 3 == 0 else (rnd.uniform(-0.3, 0.3), rnd.uniform(-0.3, 0.3))
    v, w, th = rnd.uniform(-0.5, 0.5), rnd.choice((0.0, rnd.uniform(-2.0, 2.0))), rnd.uniform(-math.pi, math.pi)
    got = _release_s(nx, ny, rx, ry, v, w, th, recheck_s=0.005)
    if w == 0.0 and _normal_speed(nx, ny, rx, ry, v, w, th, 0.0) <= 0.0:
        assert got == math.inf, "straight into the wall: the touch holds"
        return
    if _normal_speed(nx, ny, rx, ry, v, w, th, 0.0) >= 0.0:
        assert got == 0.005, "moving off the wall: look again after the recheck period"
        return
    assert 0.0 < got <= math.pi / abs(w) + 1e-9
    steps = 2000
    worst = max(_normal_speed(nx, ny, rx, ry, v, w, th, got * k / steps) for k in range(steps))
    assert worst <= 1e-9, f"the free motion turned away from the wall before {got:.6f} s ({worst:.3g} m/s)"
    after = _normal_speed(nx, ny, rx, ry, v, w, th, got * 1.01)
    assert after > 0.0, f"expected the free motion off the wall just after {got:.6f} s, got {after:.3g} m/s"


def _bumper_run(monitor, world, start, moves):
    plant = Bot(world=world, start=start, monitor=monitor)
    changes = []
    for left, right, until_us in moves:
        go(plant, left, right)
        changes += [(c.t_us, c.value) for c in plant.advance_to(until_us) if c.name == "bumper"]
    truth = plant.truth()
    return changes, [(c.t_us, c.part) for c in truth["contacts"]], (truth["x_m"], truth["y_m"], truth["theta_rad"])


def test_a_disc_spinning_against_a_wall_stays_on_it():
    assert _release_s(0.0, -1.0, 0.0, 0.0, 0.0, 1.5, 0.3, recheck_s=0.005) == math.inf


@pytest.mark.parametrize(
    "case",
    [
        "spin against a wall",
        "curve into a wall and slide",
        "slide off a box's end",
        "curve away from a wall",
        "square into a corner",
    ],
)
def test_planned_contact_checks_see_what_checks_every_millisecond_see(case):
    """The monitor plans its checks from the gaps, the touches and the speeds; a monitor
    that checks every millisecond is the reference. Same presses and releases (a release
    seen within RECHECK_US + 1 ms of the reference's), same contacts, same final pose."""
    world, start, moves = {
        "spin against a wall": (
            rectangle(5.0, 5.0),
            (2.5, 4.85, math.pi / 2),
            [(0.5, 0.5, 300_000), (0.4, -0.4, 3_000_000)],
        ),
        "curve into a wall and slide": (rectangle(5.0, 5.0), (1.0, 4.7, math.radians(20)), [(0.5, 0.55, 6_000_000)]),
        "slide off a box's end": (
            room(6.0, 6.0, [box(3.0, 3.0, 1.0, 0.4)]),
            (1.0, 2.3, math.radians(12)),
            [(0.5, 0.5, 8_000_000)],
        ),
        "curve away from a wall": (
            rectangle(5.0, 5.0),
            (2.0, 4.7, math.radians(60)),
            [(0.5, 0.5, 1_500_000), (0.6, 0.3, 4_000_000)],
        ),
        "square into a corner": (rectangle(3.0, 3.0), (1.5, 1.5, math.radians(45)), [(0.6, 0.6, 6_000_000)]),
    }[case]
    ref_changes, ref_contacts, ref_pose = _bumper_run(DenseMonitor, world, start, moves)
    changes, contacts, pose = _bumper_run(ContactMonitor, world, start, moves)
    assert ref_contacts, f"{case}: the scenario should touch a wall"
    assert [v for _, v in changes] == [v for _, v in ref_changes], (
        f"{case}: bumper levels {changes} differ from the reference's {ref_changes}"
    )
    for (t, _), (t_ref, _) in zip(changes, ref_changes):
        assert t_ref - MIN_STEP_US <= t <= t_ref + RECHECK_US + MIN_STEP_US, (
            f"{case}: bumper change at {t} us, reference {t_ref} us"
        )
    assert [p for _, p in contacts] == [p for _, p in ref_contacts]
    for (t, _), (t_ref, _) in zip(contacts, ref_contacts):
        assert abs(t - t_ref) <= MIN_STEP_US, f"{case}: contact at {t} us, reference {t_ref} us"
    assert pose == pytest.approx(ref_pose, abs=1e-3)

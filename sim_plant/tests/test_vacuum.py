"""Seed 003's vacuum robot, built from its rig file's body and parts: HC-SR04
trigger/echo on an SG90 servo, slotted-disk IR encoders, an L298N-style bridge with a
wide dead band."""

import math
from pathlib import Path

import pytest

from sim_plant.catalogue.assembly import assemble_file
from sim_plant.physics.hcsr04 import START_DELAY_US, TIMEOUT_US, HcSr04, echo_width_us
from sim_plant.world import World, box, polygon_segments, room

RIG = Path(__file__).resolve().parents[2] / "firmware" / "apps" / "vacuum" / "rig.toml"


def vacuum_plant(world="vacuum_room", start_pose=None, sonar_noise_sd_m=None, motor_gains=None, **body):
    """The vacuum robot of its rig file, in one of the body's worlds or in ``world``, a
    World of the test's own (then starting at ``start_pose``)."""
    parts = {}
    if sonar_noise_sd_m is not None:
        parts["sonar"] = {"noise_sd_m": sonar_noise_sd_m}
    for side, gain in zip(("motor_l", "motor_r"), motor_gains or ()):
        parts[side] = {"gain": gain}
    if not isinstance(world, World):
        pose = {} if start_pose is None else {"start_pose": list(start_pose)}
        return assemble_file(RIG, parts, world=world, **pose, **body)
    plant = assemble_file(RIG, parts, world="room", **body)
    plant.body.world_and_pose = lambda rng: (world, tuple(start_pose))  # a world no rig file names
    plant.reset(0)
    return plant


SENSOR_X_M = 0.10  # the HC-SR04 sits 10 cm ahead of the axle
SERVO_DUTY_90 = round(1.5 / 20 * 65535)


def ping(plant, width_us=10):
    """Raise TRIG for ``width_us``; return (rise, fall) of ECHO, or None if it stays low."""
    plant.set_input("sonar.trig", 1)
    plant.advance_to(plant.t_us + width_us)
    t_trig = plant.t_us
    plant.set_input("sonar.trig", 0)
    echo = [c for c in plant.advance_to(plant.t_us + 60_000) if c.name == "sonar.echo"]
    if not echo:
        return None
    assert [c.value for c in echo] == [1, 0]
    assert echo[0].t_us == t_trig + START_DELAY_US
    return echo[0].t_us, echo[1].t_us


def facing_wall(range_m, **options):
    """A robot whose sonar is ``range_m`` from a wall straight ahead (nothing else near)."""
    x = 1.0
    world = room(x + SENSOR_X_M + range_m, 20.0)
    return vacuum_plant(world=world, start_pose=(x, 10.0, 0.0), sonar_noise_sd_m=0.0, **options)


@pytest.mark.parametrize("range_cm, width_us", [(10, 583), (100, 5831), (400, 23324)])
def test_echo_lasts_58_31_us_per_cm(range_cm, width_us):
    """Seed 003 §3.3: D = T C / 2 with C = 343 m/s: 10 cm -> 583 us, 1 m -> 5831 us,
    4 m -> 23324 us of ECHO high."""
    rise, fall = ping(facing_wall(range_cm / 100))
    assert fall - rise == width_us == echo_width_us(range_cm / 100)


def test_nothing_within_4_m_times_out_after_38_ms():
    """Seed 003 §3.3: "Echo pulse will timeout after 38ms of no object detected"; "Max Range 4m"."""
    rise, fall = ping(facing_wall(4.2))
    assert fall - rise == TIMEOUT_US == 38_000


def test_nearer_than_4_cm_reads_4_cm():
    """Seed 003 §3.3: "Min Range 4cm"."""
    rise, fall = ping(facing_wall(0.02))
    assert fall - rise == echo_width_us(0.04) == 233


def test_the_cone_is_15_degrees():
    """Seed 003 §3.3: "Measuring Angle 15 degree": a post 7 deg off the axis echoes, one at
    9 deg does not (the wall 3.5 m behind it does)."""
    for angle_deg, expect_m in ((7.0, 1.0), (9.0, 3.5)):
        a = math.radians(angle_deg)
        sx, sy = 1.0 + SENSOR_X_M, 10.0
        post = box(sx + 1.0 * math.cos(a) + 0.02, sy + 1.0 * math.sin(a), 0.04, 0.04)
        world = room(sx + 3.5, 20.0, [post])
        plant = vacuum_plant(world=world, start_pose=(1.0, 10.0, 0.0), sonar_noise_sd_m=0.0)
        rise, fall = ping(plant)
        assert (fall - rise) / 5831 == pytest.approx(expect_m, abs=0.03), angle_deg


def test_a_trigger_shorter_than_10us_or_during_an_echo_is_ignored():
    """Seed 003 §3.3: "Trigger Input Signal 10us TTL pulse"; the module measures one echo at a time."""
    plant = facing_wall(1.0)
    assert ping(plant, width_us=5) is None
    plant.set_input("sonar.trig", 1)
    plant.advance_to(plant.t_us + 10)
    plant.set_input("sonar.trig", 0)
    plant.advance_to(plant.t_us + 1_000)  # echo is high now
    plant.set_input("sonar.trig", 1)
    plant.advance_to(plant.t_us + 10)
    plant.set_input("sonar.trig", 0)
    echo = [c for c in plant.advance_to(plant.t_us + 100_000) if c.name == "sonar.echo"]
    assert [c.value for c in echo] == [0], "only the first ping's falling edge"


def test_servo_turns_60_degrees_in_0_12_s_and_a_ping_sees_along_its_current_angle():
    """Seed 003 §3.3: "SG90, takes 0.12 sec / 60 degrees"; the scan angles 10..170 deg
    (10 -> 45 deg takes 70 ms)."""
    plant = facing_wall(2.0)
    plant.set_input("servo.pwm", SERVO_DUTY_90)
    to_150 = round(2.1667 / 20 * 65535)  # 150 deg: 0.5 ms + 150/180 * 2 ms
    plant.set_input("servo.pwm", to_150)
    plant.advance_to(plant.t_us + 60_000)
    assert plant.truth()["servo_angle_deg"] == pytest.approx(120.0, abs=0.1)
    plant.advance_to(plant.t_us + 60_000)
    assert plant.truth()["servo_angle_deg"] == pytest.approx(150.0, abs=0.1)
    plant.set_input("servo.pwm", round(0.6111 / 20 * 65535))  # 10 deg
    plant.advance_to(plant.t_us + 279_000)
    assert plant.truth()["servo_angle_deg"] > 10.0
    plant.advance_to(plant.t_us + 1_500)
    assert plant.truth()["servo_angle_deg"] == pytest.approx(10.0, abs=0.1)
    plant.set_input("servo.pwm", round(1.0 / 20 * 65535))  # 45 deg
    plant.advance_to(plant.t_us + 70_000)
    assert plant.truth()["servo_angle_deg"] == pytest.approx(45.0, abs=0.1)
    plant.set_input("servo.pwm", SERVO_DUTY_90)
    plant.advance_to(plant.t_us + 45_000)  # half way: 67.5 deg
    ping(plant)
    assert plant.truth()["sonar_ping_angle_deg"] == pytest.approx(67.5, abs=0.1)


def test_low_duty_does_not_move_the_robot():
    """Seed 003 §5.2: "At low speed the motor was not able to supply the required torque to
    move the robot" (a 25 % dead band here)."""
    plant = facing_wall(2.0)
    for side in "lr":
        plant.set_input(f"motor_{side}.in1", 1)
        plant.set_input(f"motor_{side}.pwm", int(0.24 * 65535))
    changes = plant.advance_to(1_000_000)
    assert not [c for c in changes if c.name.startswith("enc")] and plant.truth()["distance_m"] == 0.0
    for side in "lr":
        plant.set_input(f"motor_{side}.pwm", int(0.6 * 65535))
    changes = plant.advance_to(2_000_000)
    assert sum(c.name == "enc_l.out" for c in changes) == pytest.approx(
        plant.truth()["distance_m"] / (math.pi * 0.065) * 20 * 2, abs=1
    )


def test_unequal_wheels_veer_towards_the_weaker_one():
    """Seed 003 §7.2: "Error in estimate of ... wheel diameters" causes "a uniform veer in one
    direction": a per-wheel gain mismatch at equal duty curves the path."""
    plant = vacuum_plant(world=room(20.0, 20.0), start_pose=(2.0, 10.0, 0.0), motor_gains=(1.0, 0.95))
    for side in "lr":
        plant.set_input(f"motor_{side}.in1", 1)
        plant.set_input(f"motor_{side}.pwm", 50_000)
    plant.advance_to(5_000_000)
    truth = plant.truth()
    assert truth["theta_rad"] < -0.1 and truth["y_m"] < 10.0 - 0.05


def test_a_ping_at_4_m_takes_at_most_23_7_ms_so_42_a_second():
    """Seed 003 §3.3: T_max = 13 us + 0.2 ms + 23.4 ms = 23.7 ms; "In one second the
    ultrasonic sensor can measure a minimum of 1/23.7ms = 42 measurements"."""
    plant = facing_wall(4.0)
    plant.set_input("sonar.trig", 1)
    plant.advance_to(plant.t_us + 10)
    t_trig = plant.t_us
    plant.set_input("sonar.trig", 0)
    echo = [c for c in plant.advance_to(plant.t_us + 60_000) if c.name == "sonar.echo"]
    t_done = echo[-1].t_us - t_trig
    assert t_done <= 23_700 and 1e6 / t_done >= 42


def servo_duty(angle_deg):
    """duty_u16 of an SG90 pulse for angle_deg: 0.5 ms + angle / 180 * 2 ms of 20 ms."""
    return round((0.5 + angle_deg / 180 * 2.0) / 20 * 65535)


def test_a_35_degree_step_takes_70_ms_and_45_degrees_90_ms():
    """Seed 003 notes §2.1: at 0.12 s / 60 deg, 10 -> 45 deg takes 70 ms, 45 -> 90 deg 90 ms,
    and a whole 10 -> 170 deg pass 320 ms."""
    plant = facing_wall(2.0)
    servo = plant.part(HcSr04).servo
    plant.set_input("servo.pwm", servo_duty(10))
    plant.advance_to(plant.t_us + 400_000)
    for target, travel_us in ((45, 70_000), (90, 90_000), (135, 90_000), (170, 70_000)):
        start = plant.t_us
        plant.set_input("servo.pwm", servo_duty(target))
        assert servo.settle_us() - start == pytest.approx(travel_us, abs=100), target  # duty_u16 steps: 0.03 deg
        plant.advance_to(start + travel_us - 1_000)
        assert plant.truth()["servo_angle_deg"] < target - 0.4, "still turning 1 ms before"
        plant.advance_to(start + travel_us + 100)
        assert plant.truth()["servo_angle_deg"] == pytest.approx(target, abs=0.03)
    plant.set_input("servo.pwm", servo_duty(10))
    assert servo.settle_us() - plant.t_us == pytest.approx(320_000, abs=100), "the fly-back"


def test_a_ping_before_the_servo_settles_sees_along_the_angle_it_has_reached():
    """A wall 1 m to the sensor's left, nothing ahead within 4 m. Settled at 90 deg (ahead)
    the ping times out; at 170 deg (80 deg left, the cone 72.5..87.5 deg) it sees the wall
    at 1 / sin(87.5 deg) = 1.001 m. Triggered 40 ms into the 90 -> 170 deg turn the horn
    is at 110 deg (cone 12.5..27.5 deg left): the wall at 1 / sin(27.5 deg) = 2.166 m, a
    reading of neither angle."""
    plant = vacuum_plant(world=room(20.0, 11.0), start_pose=(2.0, 10.0, 0.0), sonar_noise_sd_m=0.0)
    plant.set_input("servo.pwm", servo_duty(90))
    plant.advance_to(200_000)
    rise, fall = ping(plant)
    assert fall - rise == TIMEOUT_US, "ahead: nothing within 4 m"
    plant.set_input("servo.pwm", servo_duty(170))
    plant.advance_to(plant.t_us + 40_000 - 10)
    rise, fall = ping(plant)
    assert plant.truth()["sonar_ping_angle_deg"] == pytest.approx(110.0, abs=0.01)
    assert (fall - rise) / 5831 == pytest.approx(1.0 / math.sin(math.radians(27.5)), abs=0.002)
    plant.advance_to(plant.t_us + 200_000)
    rise, fall = ping(plant)
    assert plant.truth()["sonar_ping_angle_deg"] == pytest.approx(170.0, abs=0.01)
    assert (fall - rise) / 5831 == pytest.approx(1.0 / math.sin(math.radians(87.5)), abs=0.002)


def ring_around(cx, cy, radius_m, sides=72):
    """A room whose walls are all radius_m from (cx, cy) (a polygon's inscribed circle)."""
    r = radius_m / math.cos(math.pi / sides)
    return World(
        polygon_segments(
            [
                (cx + r * math.cos(2 * math.pi * (k + 0.5) / sides), cy + r * math.sin(2 * math.pi * (k + 0.5) / sides))
                for k in range(sides)
            ]
        )
    )


def ping_now(plant):
    """Trigger for 10 us and return when ECHO falls (the board's time_pulse_us)."""
    plant.set_input("sonar.trig", 1)
    plant.advance_to(plant.t_us + 10)
    plant.set_input("sonar.trig", 0)
    for level in (1, 0):
        (change,) = plant.advance_to(plant.t_us + 60_000, limit=1)
        assert change.name == "sonar.echo" and change.value == level


@pytest.mark.parametrize("wall_m, sweep_ms", [(3.999, 437.7), (4.5, 511.1)])
def test_a_sweep_at_the_heads_own_pace_takes_about_438_ms_with_echoes_and_510_without(wall_m, sweep_ms):
    """Seed 003 notes §2.1: 320 ms of travel and five pings, 5 x 23.7 ms = 438.5 ms when the
    echoes come from 4 m, 5 x 38 ms = 510 ms when every ping times out. Each ping starts
    the moment the servo arrives, the next step the moment its echo ends; a ping here is
    10 us of TRIG, 213 us to the burst and the echo (23.3 ms from 4 m, 38 ms timeout)."""
    sx, sy = 10.0 + SENSOR_X_M, 10.0
    plant = vacuum_plant(world=ring_around(sx, sy, wall_m), start_pose=(10.0, 10.0, 0.0), sonar_noise_sd_m=0.0)
    servo = plant.part(HcSr04).servo
    plant.set_input("servo.pwm", servo_duty(10))
    plant.advance_to(400_000)
    t0 = plant.t_us
    for target in (45, 90, 135, 170, None):
        ping_now(plant)
        if target is not None:
            plant.set_input("servo.pwm", servo_duty(target))
            plant.advance_to(servo.settle_us())
    assert (plant.t_us - t0) / 1000 == pytest.approx(sweep_ms, abs=0.1)


def test_the_furnished_room_is_drawn_from_the_seed_with_a_piece_across_every_leg():
    """sim_plant.furniture: the same seed gives the same room, another seed another; every
    piece keeps 0.5 m from the walls, the other pieces and the route's points, and the
    straight line of every leg runs through (or within 0.15 m of) a piece."""
    from sim_plant.furniture import DEFAULT_ROUTE

    def pieces(seed):
        plant = vacuum_plant(world="furnished")
        plant.reset(seed)
        segs = plant.world.segments()[4:]  # after the room's four walls
        return segs, plant

    assert pieces(3)[0] == pieces(3)[0] and pieces(3)[0] != pieces(4)[0]
    for seed in range(1, 21):
        segs, plant = pieces(seed)
        walls = plant.world
        truth = plant.truth()
        assert (truth["x_m"], truth["y_m"], truth["theta_rad"]) == (*DEFAULT_ROUTE[0], 0.0)
        for x, y in DEFAULT_ROUTE:
            assert walls.clearance(x, y)[0] >= 0.5 - 1e-9, (seed, x, y)
        for (ax, ay), (bx, by) in zip(DEFAULT_ROUTE, DEFAULT_ROUTE[1:]):
            n = 200
            nearest = min(walls.clearance(ax + (bx - ax) * k / n, ay + (by - ay) * k / n)[0] for k in range(n + 1))
            assert nearest < 0.15 + 1e-9, (seed, (ax, ay), (bx, by), nearest)
        polygons = split_polygons(segs)
        assert len(polygons) >= 3, f"seed {seed}: expected a piece per leg at least, got {len(polygons)}"
        for i, poly in enumerate(polygons):
            for x, y in poly:
                assert min(x, y, 5.0 - x, 4.0 - y) >= 0.5 - 1e-9, (seed, x, y)
                for other in polygons[:i] + polygons[i + 1 :]:
                    assert World(polygon_segments(other)).clearance(x, y)[0] >= 0.5 - 1e-9, (seed, x, y)


def split_polygons(segments):
    """The pieces' corner lists from their wall segments (each piece's walls are a closed chain)."""
    polygons, current = [], []
    for ax, ay, bx, by in segments:
        current.append((ax, ay))
        if math.isclose(bx, current[0][0], abs_tol=1e-9) and math.isclose(by, current[0][1], abs_tol=1e-9):
            polygons.append(current)
            current = []
    return polygons


def test_an_unknown_world_is_refused_with_the_known_ones():
    with pytest.raises(ValueError, match="world: expected one of room, furnished, .*vacuum_room"):
        vacuum_plant(world="kitchen")
    assert vacuum_plant(world="room", room_w_m=8.0, room_h_m=6.0).world.bounds == (0.0, 0.0, 8.0, 6.0)

"""The WEDA B400 pool cleaner's tracks, bumpers and reversals (seeds 000/001)."""

import math
import statistics

import pytest

from sim_plant.tests.rigs import pool_cleaner

DEG = math.pi / 180

# seed 000, Table 7.2: heading change (deg) after stopping one track for t ms, 5 trials each
TABLE_7_2 = {
    "L": {
        300: [1.66, 1.54, 1.80, 1.20, 1.80],
        400: [1.70, 2.50, 2.35, 1.80, 1.80],
        500: [3.20, 2.65, 2.70, 3.00, 3.00],
        600: [3.12, 3.67, 4.44, 4.33, 4.71],
        700: [5.55, 4.97, 6.11, 6.25, 5.12],
    },
    "R": {
        300: [1.78, 1.51, 1.78, 1.23, 1.77],
        400: [2.47, 1.78, 2.20, 2.47, 1.78],
        500: [2.75, 3.02, 2.75, 3.02, 3.02],
        600: [3.71, 5.48, 4.39, 4.67, 4.39],
        700: [4.94, 6.59, 6.03, 5.49, 6.03],
    },
}


def eq_7_1(t_ms):
    return 8.17e-6 * t_ms**2 + 0.0022 * t_ms


def quiet_pool(**options):
    """A pool cleaner mid-pool, with the sonar on its ADC option (fewer events)."""
    options.setdefault("start_pose", (8.0, 4.0, 0.0))
    return pool_cleaner("rig-adc.toml", **options)


def stop(plant, side, duration_us):
    """Stop one track for ``duration_us`` from now; the pose at the start and at the end."""
    t0 = plant.t_us
    before = plant.truth()
    plant.set_input(f"track_{side}.stop", 1)
    plant.advance_to(t0 + duration_us)
    after = plant.truth()
    plant.set_input(f"track_{side}.stop", 0)
    return before, after


@pytest.mark.parametrize("t_ms, theta_deg", [(300, 1.395), (500, 3.143), (700, 5.543)])
def test_stopping_the_left_track_turns_by_eq_7_1(t_ms, theta_deg):
    """Seed 000 §7.2, eq. 7.1: theta(300) = 1.395 deg, theta(500) = 3.143, theta(700) = 5.543."""
    plant = quiet_pool(steer_scatter_rel=0.0)
    plant.advance_to(1_000_000)
    before, after = stop(plant, "l", t_ms * 1000)
    plant.advance_to(plant.t_us + 1_000_000)  # running straight again: no further turn
    assert after["theta_rad"] / DEG - before["theta_rad"] / DEG == pytest.approx(theta_deg, abs=5e-4)
    assert plant.truth()["theta_rad"] / DEG == pytest.approx(after["theta_rad"] / DEG, abs=1e-9)


def test_right_stops_turn_the_other_way_by_the_same_law():
    """Seed 000 Table 7.2: left and right stops give the same angles (mirror image)."""
    plant = quiet_pool(steer_scatter_rel=0.0)
    before, after = stop(plant, "r", 500_000)
    assert after["theta_rad"] / DEG - before["theta_rad"] / DEG == pytest.approx(-eq_7_1(500), abs=1e-6)


def test_a_long_stop_ends_as_a_pivot_about_the_stopped_track():
    """The law's turn rate grows until it meets the kinematic pivot rate v/W (seed 000
    eq. 4.16, W = 0.4 m, v = 0.3 m/s: 0.75 rad/s), after about 2.5 s."""
    plant = quiet_pool(steer_scatter_rel=0.0)
    plant.set_input("track_l.stop", 1)
    plant.advance_to(3_000_000)
    th1 = plant.truth()["theta_rad"]
    plant.advance_to(3_400_000)
    th2 = plant.truth()["theta_rad"]
    assert (th2 - th1) / 0.4 == pytest.approx(0.3 / 0.4, rel=1e-6)
    assert th1 == pytest.approx(eq_7_1(2495.4) * DEG + 0.75 * (3.0 - 2.4954), rel=1e-3)


def test_ideal_pivot_of_12_degrees_moves_the_centre_0_0416_by_0_0044_m():
    """Seed 000 eq. 4.6/4.7 (seed 001 eq. 17/18) with W = 0.4 m and 12 deg: dx = 0.0416 m,
    dy = 0.0044 m ("less than 0.04m and 0.005m")."""
    plant = quiet_pool(steering="ideal")
    plant.advance_to(500_000)
    t_12deg_us = round(12 * DEG / (0.3 / 0.4) * 1e6)
    before, after = stop(plant, "l", t_12deg_us)
    dth = after["theta_rad"] - before["theta_rad"]
    dx, dy = after["x_m"] - before["x_m"], after["y_m"] - before["y_m"]
    assert dth == pytest.approx(12 * DEG, abs=1e-6)
    assert dx == pytest.approx(0.4 * math.sin(dth) / 2, abs=1e-9)
    assert dy == pytest.approx(0.4 * (1 - math.cos(dth)) / 2, abs=1e-9)
    assert round(dx, 4) == 0.0416 and round(dy, 4) == 0.0044


def _stop_trials(seeds, t_ms, side="l"):
    angles = []
    for seed in seeds:
        plant = quiet_pool()
        plant.reset(seed)
        before, after = stop(plant, side, t_ms * 1000)
        angles.append(abs(after["theta_rad"] / DEG - before["theta_rad"] / DEG))
    return angles


def test_steering_scatter_matches_table_7_2():
    """Seed 000 Table 7.2: 50 stops scatter about eq. 7.1 with a residual sd of 0.45 deg and
    a relative sd of 0.13 within each stop time; the simulated stops do the same, and five
    simulated trials average inside the table's range at 300, 500 and 700 ms."""
    table_resid = [v - eq_7_1(t) for side in TABLE_7_2.values() for t, vs in side.items() for v in vs]
    table_sd = statistics.pstdev(table_resid)
    sim_resid, sim_rel_var = [], []
    for t_ms in (300, 400, 500, 600, 700):
        angles = _stop_trials(range(40), t_ms)
        sim_resid += [a - eq_7_1(t_ms) for a in angles]
        sim_rel_var.append(statistics.variance(angles) / statistics.mean(angles) ** 2)
    assert table_sd == pytest.approx(0.45, abs=0.01)
    assert statistics.pstdev(sim_resid) == pytest.approx(table_sd, abs=0.1)
    assert math.sqrt(statistics.mean(sim_rel_var)) == pytest.approx(0.13, abs=0.03)
    for t_ms in (300, 500, 700):
        table = TABLE_7_2["L"][t_ms] + TABLE_7_2["R"][t_ms]
        five = statistics.mean(_stop_trials(range(100, 105), t_ms))
        assert min(table) <= five <= max(table), (t_ms, five, table)


def test_front_bumper_closes_at_the_end_wall_and_the_machine_reverses_after_a_pause():
    """Seed 001 §2: "Upon activation of a bumper the drive motors are reversed"; seed 000:
    bumper1 is the forward one. The pause and float take reversal_pause_ms."""
    plant = quiet_pool(start_pose=(23.0, 4.0, 0.0), kick_sd_rad=0.0, kick_mean_rad=0.0)
    changes = []
    while plant.t_us < 12_000_000:
        changes += plant.advance_to(plant.t_us + 50_000)
    bumps = [c for c in changes if c.name == "bumper_front.out"]
    assert [c.value for c in bumps] == [0, 1], "pressed (active low) once, then released"
    t_hit = bumps[0].t_us
    assert t_hit == pytest.approx((25.0 - 0.45 - 23.0) / 0.3 * 1e6, abs=2_000)
    assert bumps[1].t_us - t_hit == pytest.approx(1_000_000, abs=10_000), "released as it leaves after the pause"
    truth = plant.truth()
    assert truth["direction"] == -1 and truth["reversals"] == 1
    assert truth["contacts"][0].part == "bumper_front.out"
    assert truth["x_m"] == pytest.approx(24.55 - 0.3 * (12.0 - t_hit / 1e6 - 1.0), abs=1e-3)


def test_reversal_heading_kick_follows_table_5_1():
    """Seed 000 §5.4 / Table 5.1: after a reversal the heading is N(-1.74e-2 rad, 3.48e-2)
    (the pump revolves anticlockwise); 3.48e-2 is taken as the standard deviation."""
    plant = pool_cleaner("rig-adc.toml", pool_length_m=2.0, start_pose=(1.0, 4.0, 0.0), reversal_pause_ms=200)
    plant.reset(5)
    while len(plant.truth()["reversal_kicks_rad"]) < 120:
        plant.advance_to(plant.t_us + 1_000_000)
        plant.drive.body.rebase(plant.t_us, (*plant.pose_at(plant.t_us)[:2], 0.0))  # keep it square to the walls
    kicks = plant.truth()["reversal_kicks_rad"]
    assert statistics.mean(kicks) == pytest.approx(-0.0174, abs=3 * 0.0348 / math.sqrt(len(kicks)))
    assert statistics.stdev(kicks) == pytest.approx(0.0348, rel=0.2)


def test_stopping_the_left_track_bends_the_path_to_the_robot_left_in_both_directions():
    """Seed 000 §4.2: the heading's sign flips for -x runs, the lateral effect does not:
    stopping the left track moves the robot towards its left side (+y here) either way,
    compared with the same machine that does not stop."""
    options = {"start_pose": (22.0, 4.0, 0.0), "steer_scatter_rel": 0.0, "kick_sd_rad": 0.0, "kick_mean_rad": 0.0}
    for direction, t_us in ((1, 1_000_000), (-1, 13_000_000)):
        steered, straight = quiet_pool(**options), quiet_pool(**options)
        for plant in (steered, straight):
            plant.advance_to(t_us)
            assert plant.truth()["direction"] == direction
        before, after = stop(steered, "l", 500_000)
        for plant in (steered, straight):
            plant.advance_to(t_us + 2_000_000)
        turn = after["theta_rad"] - before["theta_rad"]
        assert turn == pytest.approx(direction * eq_7_1(500) * DEG, abs=1e-9)
        assert steered.truth()["y_m"] - straight.truth()["y_m"] > 0.005, direction


def test_a_straight_run_cleans_a_strip_as_wide_as_the_machine():
    """Coverage ground truth: 10 m along the pool sweeps a 0.48 m strip (seed 001: 48 cm wide)."""
    plant = quiet_pool(start_pose=(1.0, 4.0, 0.0), coverage_cell_m=0.05)
    plant.advance_to(int(10.0 / 0.3 * 1e6))
    strip_m2 = 0.48 * 10.0 + math.pi * 0.24**2
    assert plant.truth()["coverage_fraction"] * 25 * 8 == pytest.approx(strip_m2, rel=0.06)


def test_the_b400_has_no_encoders_and_its_inputs_are_the_track_stop_bits():
    """Seed 000 §1.3.3: "there is not a feedback on the motion of the trucks"."""
    plant = pool_cleaner()
    assert set(plant.inputs) == {"track_l.stop", "track_r.stop", "sonar.select"}
    assert set(plant.outputs) == {"bumper_front.out", "bumper_rear.out", "sonar.uart"}
    assert not any(name.startswith("enc") for name in plant.outputs)


def test_a_sonar_sample_every_0_15_m_and_about_50_per_8_m_lane():
    """Seed 001 §5: "data are collected every 500 ms" at 0.3 m/s, Delta s = 0.15 m; seed 000
    §7.3.1: along the 8 m side "the control software stores about 50 samples during each
    passage"."""
    plant = pool_cleaner(
        "rig-adc.toml",
        pool_length_m=8.0,
        pool_width_m=25.0,
        start_pose=(0.46, 12.0, 0.0),
        kick_sd_rad=0.0,
        kick_mean_rad=0.0,
    )
    samples = []  # (direction, reversing) at each sonar sample, one backward lane
    while plant.truth()["reversals"] < 2:
        for c in plant.advance_to(plant.t_us + 100_000):
            if c.name == "sonar_l.adc":
                samples.append((plant.truth()["direction"], plant.truth()["reversing"]))
    lane = [s for s in samples if s == (-1, False)]
    assert 45 <= len(lane) <= 55
    plant = quiet_pool(start_pose=(1.0, 4.0, 0.0))
    plant.advance_to(100_000)
    x0 = plant.truth()["x_m"]
    plant.advance_to(600_000)
    assert plant.truth()["x_m"] - x0 == pytest.approx(0.15, abs=1e-12)


def test_carrying_the_machine_moves_it_without_sweeping_the_floor_between():
    """The operator sets the machine down elsewhere (seed 000 §6.3); the coverage grid
    gets no swath along the way and the machine drives on from the new place."""
    from sim_plant.physics.coverage import CoverageRecorder

    plant = pool_cleaner(start_pose=(5.0, 1.0, 0.0))
    plant.reset(3)
    plant.advance_to(1_000_000)
    plant.carry_to((5.0, 4.0, 0.0))
    plant.advance_to(2_000_000)
    truth = plant.truth()
    assert truth["x_m"] == pytest.approx(5.3, abs=1e-6) and truth["y_m"] == pytest.approx(4.0, abs=1e-9)
    grid = plant.part(CoverageRecorder).grid
    assert grid.fraction_in(4.0, 6.0, 2.0, 3.0) == 0.0, "no swath between the two places"
    assert grid.fraction_in(5.0, 5.3, 3.8, 4.2) == 1.0
    assert grid.fraction_in(5.05, 5.25, 0.8, 1.2) == 1.0


def test_the_rig_files_bumpers_are_the_seeds_and_the_corner_start_is_seed_000s():
    """Both rig files (NMEA and ADC) put the seed's end bumpers (60 deg either side of
    square on) on the machine, which starts in the corner: the front bumper 1 cm off the
    end wall, its right side 2 cm off the side wall (seed 000 §7.3.3)."""
    from sim_plant.pool import BODY_LENGTH_M, BODY_WIDTH_M, BUMPER_HALF_ARC_DEG

    for rig in ("rig.toml", "rig-adc.toml"):
        plant = pool_cleaner(rig)
        bumpers = [p for p in plant.catalogue_parts if p.kind == "bumper"]
        assert [b.options["half_arc_deg"] for b in bumpers] == [BUMPER_HALF_ARC_DEG] * 2, rig
        assert [b.mount[2] for b in bumpers] == [0.0, 180.0], rig
        x, y, theta = plant.pose_at(0)
        assert (x + BODY_LENGTH_M / 2, y - BODY_WIDTH_M / 2, theta) == pytest.approx((25.0 - 0.01, 0.02, 0.0)), rig

"""The floors `make bench` prints beside issue 30's targets: the arithmetic on given
numbers (no wall clock), and the verdict beside each target."""

import math

from host.bench import (
    compute_us_total,
    encoder_floor_line,
    floor_rtf,
    floor_text,
    imu_floor,
    lockstep_floor_line,
    ratio_floor_text,
)


def test_a_lockstep_floor_is_its_exchanges_at_the_raw_round_trip_plus_the_firmware_compute():
    # 100 exchanges a simulated s at 50 us = 5 ms, + 5 ms of compute: 10 ms a simulated s
    assert floor_rtf(100, 50.0, 5_000.0) == 100.0


def test_the_encoder_floor_adds_each_edge_at_the_bare_handler_cost():
    # 97 exchanges x 40 us = 3,880 us, + 10,000 edges x 0.312 us = 3,120 us: 7,000 us
    assert math.isclose(floor_rtf(97, 40.0, 0.0, 10_000, 0.312), 1e6 / 7_000)


def test_nothing_to_pay_is_no_floor():
    assert floor_rtf(0, 50.0) == math.inf


def test_the_verdict_says_whether_the_target_is_above_the_floor():
    assert floor_text(400.0, 400) == "floor: 400x real time (target 400x: reachable)"
    assert floor_text(399.6, 400) == "floor: 400x real time (target 400x: beyond the floor)"
    assert ratio_floor_text(1.0, 1.3) == "floor: 1.00x raw (target <= 1.3x: reachable)"
    assert ratio_floor_text(1.4, 1.3).endswith("beyond the floor)")


def test_the_compute_total_sums_a_budget_histogram():
    assert compute_us_total({100: 3, 250: 2}) == 800


def test_a_run_line_takes_its_terms_from_the_run():
    run = {"round_trips": 2_000, "sim_s": 10.0, "wall_s": 0.05, "compute_total_us": 20_000}
    # 200 exchanges x 20 us = 4 ms, + 2 ms of compute a simulated s: 166.7x; the run made 200x
    line = lockstep_floor_line(run, 20.0, 400.0)
    assert line.startswith("floor: 167x real time (target 400x: beyond the floor) = 1 s / (200 exchanges x raw 20 us")
    assert "firmware compute 2.0 ms" in line
    assert line.endswith("reached 120%")


def test_the_encoder_line_names_the_edges_and_the_bare_handler():
    run = {"round_trips": 970, "sim_s": 10.0, "wall_s": 1.0, "edges": (50_000, 50_000)}
    line = encoder_floor_line(run, 10_000, 40.0, 0.312)
    assert line.startswith("floor: 143x real time (target 100x: reachable) = 1 s / (97 exchanges x raw 40 us")
    assert "10,000 edges x bare 0.31 us" in line
    assert line.endswith("reached 7%")
    assert encoder_floor_line(run, 40_000, 40.0, 0.312).startswith("floor: 143x real time = ")


def test_the_bus_heavy_floor_counts_every_exchange_and_the_driver_code_at_its_rates():
    # 750 exchanges x 20 us = 15,000 us; 208 ticks x 10 us + 200 polls x 2 us = 2,480 us
    run = {"sim_s": 10.0, "wall_s": 4.0, "exchanges": 7_500}
    floor, line = imu_floor(run, 20.0, (10.0, 2.0))
    assert math.isclose(floor, 1e6 / 17_480), f"expected 1 s / 17,480 us, got {floor}x"
    assert "750 exchanges x raw 20 us + driver code 2.48 ms" in line, line
    assert line.endswith(f"reached {2.5 / floor:.0%}"), line

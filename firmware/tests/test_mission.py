"""The pool cleaner's mission state machine, driven quantum by quantum with a simple
machine model: width measurement, Run_Straight / Run_Cross on the latched bumper,
open-loop windows, stops in whole quanta, the sonar switch, dead reckoning, the end."""

import pytest
from mission import (
    CROSS,
    DELAY_MS,
    DONE,
    FRONT,
    LANE_M,
    LEAVE_WALL_MS,
    NO_ECHO,
    REAR,
    SLOT_TIMEOUT_MS,
    START,
    STRAIGHT,
    SWITCH_SETTLE_MS,
    TO_EDGE,
    Mission,
)
from steering import MAX_STOP_MS, turn_rad

QUANTUM_MS = 50


class Machine:
    """d (distance to the reference wall) and phi, moved 0.015 m per quantum; stops turn
    phi by eq. 7.1 when they end. ``pool_m`` apart, sonar 1 reads pool_m - d."""

    def __init__(self, d_m=7.5, phi_rad=0.0, pool_m=7.5):
        self.d_m, self.phi_rad, self.pool_m = d_m, phi_rad, pool_m
        self.stop_ms = 0

    def step(self, m: Mission):
        stopping = (-1 if m.stop_left else 0) + (1 if m.stop_right else 0)
        if m.stop_left and m.stop_right:
            return
        if stopping:
            self.stop_ms += stopping * QUANTUM_MS
        elif self.stop_ms:
            self.phi_rad += turn_rad(self.stop_ms)
            self.stop_ms = 0
        self.d_m += 0.3 * QUANTUM_MS / 1000 * self.phi_rad

    def reading(self, m: Mission):
        return self.d_m if m.sonar == 0 else self.pool_m - self.d_m


def drive(m, machine, until_ms, t_ms=0, bumper_at=(), silent=False, log=None):
    """Quanta from t_ms to until_ms; a reading every 500 ms; bumpers at given times."""
    bumps = dict(bumper_at)
    while t_ms < until_ms:
        depth = None if silent or t_ms % 500 else machine.reading(m)
        m.quantum(t_ms, depth, bumps.get(t_ms, 0))
        if log is not None:
            log.append((t_ms, m.stop_left, m.stop_right))
        machine.step(m)
        t_ms += QUANTUM_MS
    return t_ms


def started(width_m=7.5):
    m = Mission(log=lambda *_: None)
    machine = Machine(width_m, pool_m=width_m)
    t = drive(m, machine, 5_000)
    return m, machine, t


def test_tracks_are_held_until_ten_readings_give_the_width():
    m = Mission(log=lambda *_: None)
    assert (m.stop_left, m.stop_right, m.phase) == (1, 1, START)
    for i, depth in enumerate([2.0, NO_ECHO] + [7.4, 7.6] * 5):  # under 3 m and no echo: not counted
        m.quantum(i * 500, depth, 0)
    assert m.phase == TO_EDGE and (m.stop_left, m.stop_right) == (0, 0)
    assert m.width_m == pytest.approx(7.5) and m.reference_m == pytest.approx(7.5)


def test_runs_alternate_on_the_latched_bumper():
    m, machine, t = started()
    m.quantum(t, None, REAR)
    assert m.phase == TO_EDGE, "bumper2 before bumper1 starts nothing"
    m.quantum(t + 50, None, FRONT)
    assert m.phase == STRAIGHT and m.latched == FRONT
    m.quantum(t + 100, None, FRONT)
    assert m.runs == 1, "the same bumper again (bounce, pressed on) is no new run"
    m.quantum(t + 80_000, None, REAR)
    assert m.phase == CROSS and m.run_ms == 80_000 - 50
    m.quantum(t + 160_000, None, FRONT)
    assert m.phase == STRAIGHT and m.runs == 3


def test_no_feedback_before_the_reversal_and_leave_wall_windows_end():
    m, machine, t = started()
    t0 = t
    m.quantum(t, None, FRONT)
    t = drive(m, machine, t0 + DELAY_MS + LEAVE_WALL_MS, t + 50)
    assert not m.tracking and m.slots == 0
    drive(m, machine, t + 1000, t)
    assert m.tracking and m.slots >= 1


def test_the_cross_lead_in_is_a_sixth_of_the_pool_open_loop():
    """Run_Cross: DELAY, then L/6 with L = (run - DELAY) * SPEED (seed 000 §6.2.2)."""
    m, machine, t = started()
    m.quantum(t, None, FRONT)
    m.quantum(t + 82_000, None, REAR)
    assert m.open_until_ms - (t + 82_000) == DELAY_MS + (82_000 - DELAY_MS) // 6


def test_stops_are_whole_quanta_of_at_most_300ms_inside_their_500ms_slot():
    m = Mission(log=lambda *_: None)
    machine = Machine(7.5, pool_m=7.5)
    t = drive(m, machine, 5_000)
    m.quantum(t, None, FRONT)
    machine.d_m = 7.2  # 0.3 m off the lane: the law steers
    log = []
    drive(m, machine, t + 60_000, t + 50, log=log)
    pulses, length, start = [], 0, 0
    for t_ms, left, right in log:
        if left or right:
            start = start if length else t_ms
            length += QUANTUM_MS
        elif length:
            pulses.append((start, length))
            length = 0
    assert pulses, "expected the machine 0.3 m off its lane to be steered"
    assert all(0 < ms <= MAX_STOP_MS and ms % QUANTUM_MS == 0 for _, ms in pulses), pulses
    assert all(start % 500 == 0 for start, _ in pulses), "each stop starts with its sonar slot"
    assert abs(machine.d_m - 7.5) < 0.1, f"expected the lane regained in a minute, got d = {machine.d_m:.2f} m"


def test_the_sonar_switches_a_lane_before_readings_would_go_under_3m():
    m, machine, t = started()
    m.reference_m = machine.d_m = 3.5
    m.quantum(t, None, FRONT)
    t = drive(m, machine, t + DELAY_MS + LEAVE_WALL_MS + 600, t + 50)
    assert m.sonar == 1 and m.switch_until_ms > 0
    assert m.switch_until_ms - t <= SWITCH_SETTLE_MS
    t = drive(m, machine, t + 20_000, t)
    assert m.sonar == 1 and abs(m.filter.d_m - 3.5) < 0.1, "sonar 1's readings are converted: width - reading"
    m.quantum(t, None, REAR)
    assert m.phase == CROSS and m.target_m == m.reference_m == 3.5, "the lane after a switch is repeated"


def test_a_silent_sounder_gives_dead_reckoning_slots():
    m, machine, t = started()
    m.quantum(t, None, FRONT)
    t = drive(m, machine, t + 10_000, t + 50)
    slots, missing = m.slots, m.missing
    drive(m, machine, t + 5_500, t, silent=True)
    assert m.slots - slots == 5_500 // SLOT_TIMEOUT_MS and m.missing - missing == m.slots - slots


def test_wrong_readings_are_rejected_unless_three_agree():
    m, machine, t = started()
    m.quantum(t, None, FRONT)
    t = drive(m, machine, t + 15_000, t + 50)
    d = m.filter.d_m
    for depth in (11.0, 4.2, 14.5):
        m.quantum(t, depth, 0)
        t += 500
    assert m.rejected == 3 and abs(m.filter.d_m - d) < 0.05 and m.restarts == 0
    for depth in (6.5, 6.6, 6.5):
        m.quantum(t, depth, 0)
        t += 500
    assert m.restarts == 1 and m.filter.d_m == pytest.approx(6.5, abs=0.05)


def test_time_to_finish_is_two_runs_per_lane_left():
    m, machine, t = started()
    m.quantum(t, None, FRONT)
    m.quantum(t + 81_000, None, REAR)
    assert m.estimate_total_s == pytest.approx((t + 81_000) / 1000 + 2 * 81.0 * 7.5 / LANE_M)


def test_the_mission_ends_after_the_straight_run_on_the_last_lane():
    m, machine, t = started()
    m.quantum(t, None, FRONT)
    m.reference_m = 0.0
    m.quantum(t + 81_000, None, REAR)
    assert m.phase == DONE and (m.stop_left, m.stop_right) == (1, 1) and m.done_ms == t + 81_000

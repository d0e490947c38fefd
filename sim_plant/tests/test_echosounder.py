"""The pool cleaner's side echo sounder: range model and NMEA bytes (seeds 000/001)."""

import math

import numpy as np
import pytest

from sim_plant.physics.echo_sounder import DROPOUT_TABLE_7_1, NavmanSideSounder, dpt_sentence, nmea_checksum
from sim_plant.pool import ADC_V_PER_M
from sim_plant.tests.rigs import pool_cleaner
from sim_plant.world import pool

HALF_WIDTH_M = 0.24
LEFT_MOUNT = (0.0, HALF_WIDTH_M, math.pi / 2)


def left_sonar_pose(range_m, x_m=12.5, heading_rad=0.0, width_m=8.0):
    """Pose that puts the left sonar ``range_m`` from the wall y = width (square on)."""
    return x_m, width_m - range_m - HALF_WIDTH_M, heading_rad


def readings(model, pose, world, n, seed=1):
    rng = np.random.default_rng(seed)
    return [model.measure(1 << 40, pose, world, rng)[1] for _ in range(n)]


def parse_dpt(sentence: bytes):
    body, cs = sentence.decode().strip()[1:].split("*")
    assert int(cs, 16) == nmea_checksum(body)
    fields = body.split(",")
    assert fields[0] == "SDDPT"
    return float(fields[1]) if fields[1] else None


def test_dpt_sentence_has_the_nmea_checksum():
    """NMEA 0183 DPT (seed 000 notes: emit $SDDPT,d.d,0.0*hh): checksum = XOR between $ and *."""
    assert dpt_sentence(7.5) == b"$SDDPT,7.5,0.0*55\r\n"
    assert parse_dpt(dpt_sentence(None)) is None


def test_no_reading_below_0_8_m():
    """Seed 000 §7.1: "for distances shorter than 0.8 meters, the sonar was effectively not
    able to give measurements at all"."""
    model, world = NavmanSideSounder(LEFT_MOUNT), pool()
    for range_m in (0.3, 0.6, 0.79):
        assert readings(model, left_sonar_pose(range_m), world, 50) == [None] * 50


@pytest.mark.parametrize("range_m, rate", DROPOUT_TABLE_7_1)
def test_dropouts_between_0_8_and_1_3_m_follow_table_7_1(range_m, rate):
    """Seed 000 Table 7.1: no reading in 5/8, 4/8, 1/8, 2/8, 0/8, 0/8 of the trials at
    0.8, 0.9, 1.0, 1.1, 1.2, 1.3 m."""
    model, world = NavmanSideSounder(LEFT_MOUNT), pool()
    got = readings(model, left_sonar_pose(range_m), world, 3000)
    missing = sum(r is None for r in got) / len(got)
    assert missing == pytest.approx(rate, abs=0.03)
    present = [r for r in got if r is not None]
    if present:
        assert statistics_mean(present) == pytest.approx(range_m, abs=0.02)


def statistics_mean(values):
    return sum(values) / len(values)


def test_readings_have_a_resolution_of_0_1_m_to_20_m_and_1_m_beyond():
    """Seed 001 §3: "precision of one decimeter between 2-20 meters and 1 meter between
    20-150 meters"; seed 000: "The sonar output data have a resolution of ten centimeters"."""
    model = NavmanSideSounder(LEFT_MOUNT, noise_sd_m=0.0)
    near = readings(model, left_sonar_pose(7.26), pool(), 5)
    assert near == [7.3] * 5
    wide = pool(50.0, 40.0)
    far = readings(model, left_sonar_pose(27.4, x_m=25.0, width_m=40.0), wide, 5)
    assert far == [27.0] * 5


def test_no_reading_beyond_15_degrees_of_incidence():
    """Seed 000 §7.1: "for values of the angle over 15 degrees, it becomes arduous to use the
    sensor"; within the 9 degree beam the echo is the perpendicular distance."""
    model, world = NavmanSideSounder(LEFT_MOUNT, noise_sd_m=0.0), pool()
    x, y, _ = left_sonar_pose(5.0)
    square = readings(model, (x, y, 0.0), world, 3)
    in_beam = readings(model, (x, y, 4.0 * math.pi / 180), world, 3)
    off_beam = readings(model, (x, y, 12.0 * math.pi / 180), world, 3)
    beyond = readings(model, (x, y, 16.0 * math.pi / 180), world, 20)
    assert square == in_beam == [5.0] * 3
    along_m = model.geometry((x, y, 12.0 * math.pi / 180), world)[0]
    edge_m = along_m * math.cos(12 * math.pi / 180) / math.cos(7.5 * math.pi / 180)  # the beam's edge
    assert along_m > 5.1 and off_beam[0] == round(edge_m, 1)
    assert beyond == [None] * 20


def test_readings_are_corrupted_near_the_end_walls():
    """Seed 000 §5.4 (Fig. 5.9): near the perpendicular wall "the measure is corrupted";
    seed 001: "readings coming from the close by wall and the far away parallel wall"."""
    model, world = NavmanSideSounder(LEFT_MOUNT), pool()
    mid = readings(model, left_sonar_pose(5.0, x_m=12.5), world, 400)
    at_end = readings(model, left_sonar_pose(5.0, x_m=0.5), world, 400)
    off = lambda rs: sum(r is not None and abs(r - 5.0) > 0.5 for r in rs) / len(rs)  # noqa: E731
    assert off(mid) == 0.0
    assert off(at_end) > 0.2
    assert any(r is not None and r < 1.0 for r in at_end), "the close-by end wall"


def test_sentences_come_every_500ms_at_4800_baud_one_change_per_byte():
    """Seed 000 §4.3 "every 500 ms"; serial.c COMPARMS 0xc3 = 4800-n-8-1: 10 bits per byte,
    2.083 ms per character, a DPT sentence takes about 40 ms on the wire."""
    plant = pool_cleaner(start_pose=(5.0, 4.0, 0.0), **{"sonar.phase_us": 100_000})
    changes = [c for c in plant.advance_to(2_000_000) if c.name == "sonar.uart"]
    assert all(len(c.value) == 1 for c in changes)
    stream = b"".join(c.value for c in changes)
    sentences = stream.split(b"\r\n")[:-1]
    assert len(sentences) == 4
    starts = [c.t_us for c in changes if c.value == b"$"]
    assert starts == [100_000 + math.ceil(1e7 / 4800) + k * 500_000 for k in range(4)]
    first = [c.t_us for c in changes[: len(sentences[0]) + 2]]
    assert first == [100_000 + math.ceil((k + 1) * 1e7 / 4800) for k in range(len(first))]
    assert first[-1] - 100_000 == pytest.approx(len(first) * 1e7 / 4800, abs=1)
    assert 35_000 < first[-1] - 100_000 < 45_000
    assert parse_dpt(sentences[1] + b"\r\n") == pytest.approx(8.0 - 4.0 - HALF_WIDTH_M, abs=0.35)


@pytest.mark.parametrize("group", [0, 4])
def test_bytes_can_be_batched_into_fewer_changes(group):
    """bytes_per_change=N: N bytes per Change, at the end of the last; 0: a whole sentence."""
    plant = pool_cleaner(start_pose=(5.0, 4.0, 0.0), **{"sonar.bytes_per_change": group})
    changes = [c for c in plant.advance_to(1_000_000) if c.name == "sonar.uart"]
    sentence = plant.truth()["sonar_sentence"]
    if group == 0:
        assert [c.value for c in changes] == [changes[0].value, sentence]
        assert changes[1].t_us == 600_000 + math.ceil(len(sentence) * 1e7 / 4800)
    else:
        assert all(len(c.value) <= 4 for c in changes)
        assert b"".join(c.value for c in changes).endswith(sentence)


def test_select_line_puts_the_right_sonar_on_the_uart():
    """Seed 000 Set_Sonar: parallel-port bit 2 selects sonar 0 (left) or sonar 1 (right)."""
    plant = pool_cleaner(start_pose=(5.0, 2.0, 0.0), **{"sonar.bytes_per_change": 0, "sonar.noise_sd_m": 0.0})
    left = [parse_dpt(c.value) for c in plant.advance_to(700_000) if c.name == "sonar.uart"]
    plant.set_input("sonar.select", 1)
    right = [parse_dpt(c.value) for c in plant.advance_to(1_700_000) if c.name == "sonar.uart"]
    assert left == [pytest.approx(8.0 - 2.0 - HALF_WIDTH_M, abs=0.05)] * 2
    assert right == [pytest.approx(2.0 - HALF_WIDTH_M, abs=0.05)] * 2
    assert plant.truth()["sonar_selected"] == 1


def test_adc_option_gives_two_analog_sonars_with_the_same_model():
    """The harness's ADC sonar (design card) with the seed's range model: 0.33 V/m on a
    12-bit 3.3 V ADC, 0 V when there is no reading (the right sonar at 0.26 m < 0.8 m)."""
    plant = pool_cleaner(
        "rig-adc.toml", start_pose=(5.0, 0.5, 0.0), **{"sonar_l.noise_sd_m": 0.0, "sonar_r.noise_sd_m": 0.0}
    )
    assert "sonar.select" not in plant.inputs
    samples = {c.name: c.value for c in plant.advance_to(700_000)}
    counts = round(round(8.0 - 0.5 - HALF_WIDTH_M, 1) * ADC_V_PER_M / 3.3 * 4095)
    assert samples["sonar_l.adc"] == (counts << 4) | (counts >> 8)
    assert samples["sonar_r.adc"] == 0


def sentences(plant, until_us):
    """(time of its first byte, depth) of every sentence the plant sends until ``until_us``."""
    out, line, t0 = [], b"", 0
    t = 0
    while t < until_us:
        t = min(plant.next_change_us(), until_us)
        for change in plant.advance_to(t):
            if change.name == "sonar.uart":
                t0 = change.t_us if not line else t0
                line += change.value
                if line.endswith(b"\n"):
                    out.append((t0, parse_dpt(line)))
                    line = b""
    return out


def fault_pool(faults=(), rig="rig.toml"):
    """Faults on every sounder of the rig's pool cleaner."""
    sounders = ("sonar",) if rig == "rig.toml" else ("sonar_l", "sonar_r")
    plant = pool_cleaner(rig, start_pose=(12.5, 3.0, 0.0), **{f"{s}.faults": list(faults) for s in sounders})
    plant.reset(5)
    plant.set_input("track_l.stop", 1)  # both tracks stopped: the machine stands still
    plant.set_input("track_r.stop", 1)
    return plant


def test_a_burst_of_wrong_readings_replaces_the_readings_inside_its_window_only():
    """Seed 000 §3.4.4/§7.3.3: bursts of wrong readings. Inside the window the depths are
    drawn from 0.8-15 m; before it they are those of the same seed without faults."""
    clean = sentences(fault_pool(), 20_000_000)
    burst = sentences(fault_pool([(5.0, 10.0, "wrong")]), 20_000_000)
    assert [t for t, _ in clean] == [t for t, _ in burst], "faults must not move the sentences in time"
    true_m = 8.0 - 3.0 - HALF_WIDTH_M
    before = [(c, b) for (t, c), (_, b) in zip(clean, burst) if t < 5_000_000]
    inside = [b for t, b in burst if 5_100_000 <= t < 10_000_000]
    assert before and all(c == b for c, b in before), f"readings before the burst changed: {before}"
    assert len(inside) == 10 and all(0.8 <= d <= 15.0 for d in inside), inside
    far = [d for d in inside if abs(d - true_m) > 1.0]
    assert len(far) >= 7, f"expected most of the burst far from the true {true_m:.2f} m, got {inside}"


def test_a_silent_window_sends_no_sentences_and_a_none_window_empty_fields():
    plant = fault_pool([(2.0, 6.0, "silent"), (8.0, 10.0, "none")])
    sent = sentences(plant, 12_000_000)
    times = [t for t, _ in sent]
    assert not [t for t in times if 2_000_000 <= t < 6_000_000], f"sentences inside the silent window: {times}"
    assert len([t for t in times if t < 2_000_000]) == 4
    empty = [d for t, d in sent if 8_100_000 <= t < 10_000_000]
    assert empty == [None] * 4, f"expected 4 empty depth fields, got {empty}"
    assert sent[-1][1] is not None, "readings come back after the window"


def test_the_adc_option_reads_0v_while_silent():
    plant = fault_pool([(2.0, 6.0, "silent")], rig="rig-adc.toml")
    plant.advance_to(4_000_000)
    assert plant.output("sonar_l.adc") == 0 and plant.output("sonar_r.adc") == 0
    plant.advance_to(7_000_000)
    assert plant.output("sonar_l.adc") > 0


@pytest.mark.parametrize("faults, field", [([(1.0, 2.0, "noise")], "kind"), ([(2.0, 1.0, "wrong")], "window")])
def test_bad_fault_windows_are_rejected_by_name(faults, field):
    with pytest.raises(ValueError, match=field):
        pool_cleaner(**{"sonar.faults": faults})

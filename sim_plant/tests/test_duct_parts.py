"""Seed 002's duct robot, the parts added for the loop: the master that drains the record
stream (sim_plant.duct_link) and the tether snag at spins (sim_plant.physics.tether)."""

import math

import pytest

from sim_plant.duct_link import RecordReader
from sim_plant.physics.tether import TetherSnag
from sim_plant.plant import NEVER_US
from sim_plant.tests.rigs import duct_robot


def reader_plant(**options):
    return duct_robot("bench_duct", **{f"link.{k}": v for k, v in options.items()})


def test_the_master_polls_every_poll_ms_and_sends_its_script():
    plant = reader_plant(poll_ms=100, script=[(0, "K 25"), (0.25, "S 60 60")])
    changes = [c for c in plant.advance_to(300_000) if c.name == "link.uart"]
    assert [(c.t_us, c.value) for c in changes] == [
        (0, b"K 25\n"),
        (100_000, b"R\n"),
        (200_000, b"R\n"),
        (250_000, b"S 60 60\n"),
        (300_000, b"R\n"),
    ]


def test_the_link_is_an_output_with_no_level_at_reset():
    """A recorder asks every output's value at reset: a UART line has only bytes."""
    assert reader_plant().output("link.uart") == b""


def test_records_are_counted_gaps_found_and_lines_timed_at_the_baud_rate():
    plant = reader_plant(poll_ms=0, baud=10_000)  # 1 ms a byte
    reader = plant.part(RecordReader)
    batch = b"D 0 1 2 3 4 5\nD 1 1 2 3 4 5\nD 4 1 2 3 4 5\nK 2\n"
    plant.set_input("link.uart", batch)
    assert (reader.records, reader.skipped, reader.overruns, reader.batches) == (3, 2, 2, 1)
    assert reader.values[2] == (4, 1, 2, 3, 4, 5)
    # the first line ends after its 14 bytes, the second 14 bytes later (1 ms each)
    assert reader.latencies_us[:2] == [14_000, 28_000 - 50_000]
    assert reader.line_free_us == len(batch) * 1000
    plant.set_input("link.uart", b"garbage\n")
    assert reader.bad_lines == 1


def spinning_plant(p_snag, seed=0):
    plant = duct_robot("bench_duct", start_pose=(2.0, 0.2, 0.0), spin_slip=0.0, **{"tether.snag_p": p_snag})
    plant.reset(seed)
    plant.set_input("motor_l.dir", 1)
    plant.set_input("motor_r.dir", 0)
    for side in "lr":
        plant.set_input(f"motor_{side}.pwm", 20_000)
    return plant


def test_a_certain_snag_pulls_the_body_back_and_twists_it_unseen_by_the_encoders():
    plant = spinning_plant(1.0)
    plant.advance_to(100_000)
    before = plant.truth()
    edges_before = (before["enc_l_edges"], before["enc_r_edges"])
    plant.advance_to(200_000)
    snag = plant.part(TetherSnag)
    assert len(snag.events) == 1 and snag.spins == 1
    t, x, y, th, nx, ny, nth = snag.events[0]
    assert t == 150_000
    pulled = math.hypot(nx - x, ny - y)
    assert 0.04 <= pulled <= 0.08 + 1e-9, "pulled back by 0.5..1 x 80 mm"
    assert math.radians(12.5) - 1e-9 <= abs(math.remainder(nth - th, 2 * math.pi)) <= math.radians(25) + 1e-9
    after = plant.truth()
    assert after["snags"] == 1
    # the wheels' encoders kept counting at their own rate: a snag is not seen by them
    assert after["enc_l_edges"] - edges_before[0] == pytest.approx(before["enc_l_edges"], abs=2)


def test_no_snag_without_a_spin_and_none_when_p_is_zero():
    plant = duct_robot("bench_duct", start_pose=(2.0, 0.2, 0.0), **{"tether.snag_p": 1.0})
    for side in "lr":
        plant.set_input(f"motor_{side}.dir", 1)
        plant.set_input(f"motor_{side}.pwm", 20_000)
    plant.advance_to(1_000_000)
    assert plant.truth()["snags"] == 0 and plant.part(TetherSnag).next_us == NEVER_US
    assert "snags" not in duct_robot("bench_duct").truth()


def test_snags_come_at_about_p_of_the_spins():
    hits = 0
    for seed in range(200):
        plant = spinning_plant(0.12, seed)
        plant.advance_to(200_000)
        hits += plant.truth()["snags"]
    assert 12 <= hits <= 38, f"expected about 24 of 200 spins to snag, got {hits}"

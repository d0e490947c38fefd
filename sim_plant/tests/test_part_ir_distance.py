"""Part ir_distance: the Sharp GP2Y0A21YK's inverse voltage curve on an ADC."""

import pytest

from sim_plant.catalogue import ir_distance
from sim_plant.catalogue.assembly import assemble

MOTORS = [
    {"kind": "dc_motor", "name": "motor_l", "drives": "left"},
    {"kind": "dc_motor", "name": "motor_r", "drives": "right"},
]


def test_the_curve_follows_the_datasheet_and_folds_back_near():
    assert ir_distance.volts(0.10) == pytest.approx(2.3, abs=0.05)
    assert ir_distance.volts(0.20) == pytest.approx(1.3, abs=0.1)
    assert ir_distance.volts(0.80) == pytest.approx(0.4, abs=0.03)
    assert ir_distance.volts(0.05) < ir_distance.volts(0.10), "nearer than 10 cm the output falls again"
    ranges = [0.1 + 0.05 * i for i in range(14)]
    assert all(ir_distance.volts(a) > ir_distance.volts(b) for a, b in zip(ranges, ranges[1:]))


def test_it_reads_the_wall_ahead_every_38_ms():
    plant = assemble(
        {
            "body": "differential",
            "start_pose": [2.5, 1.0, 0.0],  # 0.5 m from the wall at x = 3
            "parts": [*MOTORS, {"kind": "ir_distance", "name": "ir", "mount": {"x_m": 0.05}, "noise_sd_m": 0}],
        }
    )
    changes = [c for c in plant.advance_to(200_000) if c.name == "ir.adc"]
    assert [c.t_us for c in changes] == [38_000, 76_000, 114_000, 152_000, 190_000]
    truth = plant.truth()
    assert truth["ir_range_m"] == pytest.approx(0.45)
    volts = changes[-1].value / 65535 * 3.3
    assert volts == pytest.approx(ir_distance.volts(0.45), abs=0.01)

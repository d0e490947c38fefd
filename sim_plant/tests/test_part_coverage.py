"""Part coverage: the swept floor as ground truth, over whatever world the body is in."""

import pytest

from sim_plant.catalogue.assembly import assemble

MOTORS = [
    {"kind": "dc_motor", "name": "motor_l", "drives": "left", "time_constant_ms": 0},
    {"kind": "dc_motor", "name": "motor_r", "drives": "right", "time_constant_ms": 0},
]


def test_driving_1_m_sweeps_a_strip_as_wide_as_the_body():
    """A 3 x 2 m room, a disc of r = 0.08 m driven 1 m straight: about 1.16 x 0.16 m of
    the 6 m^2 floor is swept (10 cm cells: a strip 2 cells wide, 12 long)."""
    plant = assemble(
        {"body": "differential", "parts": [*MOTORS, {"kind": "coverage", "name": "floor", "coverage_cell_m": 0.1}]}
    )
    assert plant.truth()["coverage_fraction"] < 0.01
    for side in "lr":
        plant.set_input(f"motor_{side}.in1", 1)
        plant.set_input(f"motor_{side}.pwm", 65535)
    plant.advance_to(2_500_000)  # 0.4 m/s: 1 m
    assert plant.truth()["x_m"] == pytest.approx(1.4, abs=0.01)
    assert plant.truth()["coverage_fraction"] == pytest.approx(2 * 12 / 600, abs=0.01)


def test_the_grid_follows_the_world_and_the_width_option():
    plant = assemble(
        {
            "body": "differential",
            "world": "vacuum_room",
            "parts": [*MOTORS, {"kind": "coverage", "name": "floor", "coverage_cell_m": 0.05, "half_width_m": 0.2}],
        }
    )
    from sim_plant.physics.coverage import CoverageRecorder

    grid = plant.part(CoverageRecorder).grid
    assert grid.cell_m == 0.05 and grid.half_width_m == 0.2 and grid.x0_m == 0.0

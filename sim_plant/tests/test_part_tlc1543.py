"""The tlc1543 part (a serial ADC with floor sensors): the address latched on the first
four rising clock edges, the previous conversion shifted out MSB first on the falling ones,
the addressed channel converted at the tenth; edges given now (the CPU's pins) or ahead
at their instants (``LevelAt``: a PIO's clock)."""

import pytest

from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError
from sim_plant.plant import LevelAt

TAPE = [[0.5, 1.0], [2.5, 1.0]]  # along the heading at y = 1 m, 19 mm wide
MOTORS = [
    {"kind": "dc_motor", "name": f"motor_{s}", "drives": side, "time_constant_ms": 0}
    for s, side in (("l", "left"), ("r", "right"))
]


def plant_with(**options):
    # channel 0 on the tape, channel 1 on the floor 30 mm to its left
    adc = {"kind": "tlc1543", "name": "tr", "offsets_m": [[0.0, 0.0], [0.0, 0.03]], **options}
    return assemble({"body": "differential", "start_pose": [1.0, 1.0, 0.0], "tape": TAPE, "parts": [*MOTORS, adc]})


def cycle_now(plant, channel: int, t_us: int) -> int:
    """One cycle with the CPU's pins, all at ``t_us``: the 10 bits read before each clock."""
    plant.advance_to(t_us)
    plant.set_input("tr.cs", 0)
    plant.advance_to(t_us)
    word = 0
    for i in range(10):
        if i < 4:
            plant.set_input("tr.addr", channel >> (3 - i) & 1)
        plant.advance_to(t_us)
        word = word << 1 | plant.output("tr.dout")
        plant.set_input("tr.clk", 1)
        plant.set_input("tr.clk", 0)
        plant.advance_to(t_us)
    plant.set_input("tr.cs", 1)
    plant.advance_to(t_us)
    return word


def test_each_cycle_shifts_out_the_conversion_the_cycle_before_addressed():
    plant = plant_with()
    assert plant.output("tr.dout") == 0
    assert cycle_now(plant, 0, 1_000) == 0, "no conversion before the first cycle"
    assert cycle_now(plant, 1, 2_000) == 900, "channel 0's sensor over the tape"
    assert cycle_now(plant, 13, 3_000) == 100, "channel 1's over the floor"
    assert cycle_now(plant, 11, 4_000) == 1023, "channel 13: Vref+"
    assert cycle_now(plant, 12, 5_000) == 512, "channel 11: half the reference"
    assert cycle_now(plant, 0, 6_000) == 0, "channel 12: Vref-"
    truth = plant.truth()
    assert truth["tr_on_tape"] == [True, False] and truth["tr_counts"] == [900, 100]
    assert truth["tr_conversions"] == 6
    assert plant.output("tr.dout") == 0, "cs high: the line let go reads 0"


def test_edges_given_ahead_change_dout_at_their_instants():
    plant = plant_with(floor_counts=40, tape_counts=1000)
    cycle_now(plant, 0, 1_000)  # (channel 0 converted: 1000 = 0b1111101000)
    t0 = 2_000
    plant.advance_to(t0)
    plant.set_input("tr.cs", 0)
    plant.advance_to(t0)
    for k in range(12):  # a 200 kHz clock: rising at t0 + 5k + 2.5, falling at t0 + 5k + 5
        plant.set_input("tr.clk", LevelAt(1, t0 + 5 * k + 2.5))
        plant.set_input("tr.clk", LevelAt(0, t0 + 5 * k + 5))
    assert plant.output("tr.dout") == 1, "the MSB at cs falling"
    changes = [(c.t_us - t0, c.value) for c in plant.advance_to(t0 + 100) if c.name == "tr.dout"]
    # bits 9..0 of 1000 = 1111101000: dout takes bit 9 - n at falling edge n (low after the tenth)
    assert changes == [(25, 0), (30, 1), (35, 0)], changes
    assert plant.truth()["tr_converted"][0] == 1000


def test_floor_above_tape_is_refused():
    with pytest.raises(PartsError, match="floor_counts <= tape_counts"):
        plant_with(floor_counts=800, tape_counts=200)

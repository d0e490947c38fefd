"""pico_pio_bot in the loop: its encoders are counted by PIO state machines that run on the
host beside the plant (docs/shim.md, "PIO"); the counts it reads equal the plant's edges."""

import re
from pathlib import Path

import pytest

RIG = str(Path(__file__).parent / "rig.toml")
pytestmark = pytest.mark.hil


def test_pio_counts_equal_the_plants_encoder_edges(make_rig):
    rig = make_rig(RIG, seed=1)
    rig.expect(r"pio_bot: done (-?\d+) (-?\d+)", timeout_s=120)
    left, right = map(int, re.search(r"pio_bot: done (-?\d+) (-?\d+)", rig.console).groups())
    truth = rig.truth()
    assert (left, right) == (truth["enc_l_edges"], truth["enc_r_edges"]), truth
    assert abs(left - (4 * 1500 - 4 * 420)) < 80, "each leg stops a few edges past its target"


def test_every_side_is_read_as_the_plant_counted_it(make_rig):
    rig = make_rig(RIG, seed=2)
    rig.expect(r"pio_bot: side 0 ", timeout_s=60)
    start = re.search(r"pio_bot: start (-?\d+) (-?\d+)", rig.console).groups()
    assert start == ("0", "0")
    left = int(re.search(r"pio_bot: side 0 (-?\d+) (-?\d+)", rig.console).group(1))
    assert 1500 <= left < 1540, "it stops a few edges past the target"

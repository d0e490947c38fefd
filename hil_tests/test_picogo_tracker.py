"""The Pico-Go's line sensor board: a TLC1543 serial ADC (the ``tlc1543`` part) read as
the robot's published demos read it, by a PIO program that side-sets the I/O clock,
shifts the address out and the data in (12 clocks at 200 kHz, the CPU's chip select
around each put and get), and as the first boards' code reads it, the CPU toggling the
pins (hil_tests/firmware/picogo, written in the demos' style, not copied). Each channel's
value is the plant's conversion of the floor under its sensor, both ways, with the CPU's
time free and with an RP2040's (docs/mcu-time.md). Before the part, the data pin was
wired to nothing and every read was ``[0, 0, 0, 0, 0]``."""

import ast
import re
import shutil
from pathlib import Path

import pytest

pytestmark = pytest.mark.hil
FIRMWARE = Path(__file__).parent / "firmware" / "picogo"
OFF_LINE = "start_pose = [0.5, 1.016, 0.0]"  # the tape under channel 3's sensor (16 mm to the right)


@pytest.mark.parametrize("cpu", ["free", "rp2040@125MHz"])
@pytest.mark.parametrize("pose", ["centre", "right"])
def test_picogo_line_sensors_read_the_plants_conversions_by_pio_and_by_the_cpu(
    make_rig, monkeypatch, tmp_path, cpu, pose
):
    monkeypatch.setenv("MPYFIL_CPU", cpu)
    folder = tmp_path / "picogo"
    shutil.copytree(FIRMWARE, folder)
    if pose == "right":
        rig_file = folder / "rig.toml"
        rig_file.write_text(rig_file.read_text().replace("start_pose = [0.5, 1.0, 0.0]", OFF_LINE))
    rig = make_rig(str(folder / "rig.toml"), allow_exit=True)
    rig.expect("done")
    truth = rig.truth()
    where = f"console:\n{rig.console}\ntruth: {truth}\nartefacts: {rig.artefacts}"
    on = [False, False, True, False, False] if pose == "centre" else [False, False, False, True, False]
    assert truth["tr_on_tape"] == on, f"the tape under channel {on.index(True)}'s sensor; {where}"
    assert truth["tr_counts"] == [900 if o else 100 for o in on], where
    reads = {"pio": [], "cpu": []}
    for way, values in re.findall(r"^(pio|cpu) (\[[\d, ]+\]) \d+$", rig.console, re.M):
        reads[way].append(ast.literal_eval(values))
    assert len(reads["pio"]) == len(reads["cpu"]) == 3, where
    for way, got in reads.items():
        assert got == [truth["tr_counts"]] * 3, (
            f"expected each {way} read to be the plant's conversions {truth['tr_counts']}, got {got}; {where}"
        )
    assert truth["tr_conversions"] == 36, f"6 cycles a read, 6 reads: {truth['tr_conversions']}; {where}"

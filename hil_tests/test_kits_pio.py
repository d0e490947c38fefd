"""The 3pi+ 2040's QTR line and bump sensors read with a PIO program, as Pololu's library
reads them (docs/kits.md, "Pololu 3pi+ 2040"): the program charges the seven channels
(``out pindirs`` of ones), lets them go (``out pindirs`` of zeros) and times each fall in
a loop of 1 us a pass. The pins' direction changes reach the ``qtr`` part at their cycles
(docs/shim.md, "PIO"), so each reading is the plant's discharge time. Pololu's library is
not on PyPI: the firmware (hil_tests/firmware/kits/pololu_3pi_pio) is written in its
style, with a PIO program of its shape, not copied."""

import math
import re
import shutil

import pytest

from hil_tests.test_kits import FIRMWARE, kit_folder

pytestmark = pytest.mark.hil
PASS_US = 1  # the program's loop: 8 instructions at 8 MHz (and the plant's whole µs)
TAPE = "tape = [[0.535, 0.5], [0.535, 1.5]]   # under the line sensors, across the robot's heading\n"


@pytest.mark.parametrize("cpu", ["free", "rp2040@125MHz"])
@pytest.mark.parametrize("floor", ["white", "black"])
def test_3pi_pio_line_and_bump_reads_are_the_plants_discharge_times(
    capsys, make_rig, monkeypatch, tmp_path, floor, cpu
):
    """With compute free and with MCU time (docs/mcu-time.md): the CPU's exec'd words, its
    active(1), the program's cycles, the plant's discharge and the CPU's gets (each after the
    compute before it, on an RP2040) agree on their instants, so each reading is the plant's
    discharge time to the program's pass, however long the CPU takes between its gets."""
    monkeypatch.setenv("MPYFIL_CPU", cpu)
    folder = kit_folder(capsys, tmp_path, "pololu_3pi_2040", "pololu_3pi_pio")
    rig_file = folder / "rig.toml"
    if floor == "black":
        text = rig_file.read_text()
        rig_file.write_text(text.replace("start_pose = [0.5, 1.0, 0.0]\n", "start_pose = [0.5, 1.0, 0.0]\n" + TAPE))
    rig = make_rig(str(rig_file), allow_exit=True)
    where = lambda: f"console:\n{rig.console}\nartefacts: {rig.artefacts}"  # noqa: E731
    lines, bumps = [], []
    for _ in range(3):
        lines.append([int(v) for v in re.findall(r"\d+", rig.expect(r"line \[([\d, ]+)\]").group(1))])
        bumps.append([int(v) for v in re.findall(r"\d+", rig.expect(r"bump \[([\d, ]+)\]").group(1))])
    truth = rig.truth()
    assert truth["line_on_tape"] == [floor == "black"] * 5, f"the sensors over the {floor} floor: {truth}; {where()}"
    want = {"white": 150, "black": 800}[floor]
    # (the bump read, last, charges and lets go all seven channels with the down emitters let
    # go: GP26 an input, the battery's divider on the line, so they are off, and the line
    # channels' last discharge is the unlit time; the line reads had them on)
    assert truth["line_discharge_us"] == [5000] * 5, f"the line's last discharge, its emitters off: {truth}; {where()}"
    assert truth["bump_discharge_us"] == [300, 300], f"the flaps released: {truth}; {where()}"
    for line, bump in zip(lines, bumps, strict=True):
        for got, plant in zip(line + bump, [want] * 5 + truth["bump_discharge_us"], strict=True):
            assert 0 <= got - plant <= PASS_US, (
                f"expected each reading the plant's discharge time {plant} us (to the loop's {PASS_US} us, "
                f"late), got line {line} bump {bump}; {where()}"
            )


@pytest.mark.parametrize("cpu", ["free", "rp2040@125MHz"])
def test_3pi_pio_bump_sensors_read_pressed_and_released(capsys, make_rig, monkeypatch, tmp_path, cpu):
    """Pololu's wall_bumper.py's way (hil_tests/firmware/kits/pololu_3pi_bump) with the PIO
    reads: calibrated standing (flaps released), driven at the east wall 10 degrees off
    square, the left flap is read pressed and the right one released, as the plant has them;
    the same with MCU time (the PIO times the discharge: the CPU's compute moves no reading)."""
    monkeypatch.setenv("MPYFIL_CPU", cpu)
    folder = kit_folder(capsys, tmp_path, "pololu_3pi_2040", "pololu_3pi_bump")
    shutil.copytree(FIRMWARE.parent / "kitbot" / "lib", folder / "lib")
    shutil.copy(FIRMWARE / "pololu_3pi_pio" / "ir_sensors.py", folder)
    rig_file = folder / "rig.toml"
    text = rig_file.read_text().replace('name = "button_b"\n', 'name = "button_b"\npresses = [[0.2, 0.3]]\n')
    rig_file.write_text(text.replace("start_pose = [0.5, 1.0, 0.0]", "start_pose = [2.88, 1.0, -0.17]"))
    rig = make_rig(str(rig_file), allow_exit=True)
    where = lambda: f"console:\n{rig.console}\nartefacts: {rig.artefacts}"  # noqa: E731
    low, high = rig.expect(r"thresholds \[(\d+), \d+\] \[(\d+), \d+\]").groups()
    released = 300 + PASS_US  # (each released read: the flap's 300 us, to the loop's pass)
    assert (int(low), int(high)) == (round(released * 1.4), round(released * 1.6)), (
        f"140 % and 160 % of the released flaps' {released} us read standing; {where()}"
    )
    bumped = rig.expect(r"bumped (\d) (\d) \[(\d+), (\d+)\]").groups()
    left, right, data_l, data_r = (int(v) for v in bumped)
    truth = rig.truth()
    assert truth["bump_on_tape"] == [True, False], f"the left flap pressed, the right not: {truth}; {where()}"
    assert (left, right) == (1, 0), f"expected the left flap read pressed, the right released; {where()}"
    assert 0 <= data_l - 700 <= PASS_US and 0 <= data_r - 300 <= PASS_US, (
        f"expected the pressed flap's 700 us and the released one's 300 us, got {data_l}, {data_r}; {where()}"
    )
    gap_m = 3.0 - truth["x_m"] - 0.0485 * math.cos(-0.17)
    assert abs(gap_m) < 0.01, f"stopped {gap_m * 1000:.1f} mm from the wall; {where()}"

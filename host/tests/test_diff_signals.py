"""mpy-fil diff compares every signal kind a run records (a bus's transfers as text, an
LED's colour, numbers) and tells "differs" (exit 1) from "could not compare" (exit 2): a
pose that is no number (NaN, inf) in a recording is named, never "same"."""

import csv
import io
import json
import shutil

import pytest

from host.artefacts.folder import reseal
from host.tests.conftest import run_cli

BUS = "bus:i2c0"
LED = "led.rgb"


@pytest.fixture(scope="module")
def recorded(tmp_path_factory):
    out = tmp_path_factory.mktemp("diffkinds") / "run"
    code, _, err = run_cli("run", "--app", "rover", "--duration", "1", "--out", out)
    assert code == 0, err
    return out


def edited(recorded, folder, *, bus=(), led=(), truth=None):
    """A copy of the recording with ``bus`` and ``led`` changes added as firmware outputs
    (text values) and ``truth(rows)`` applied to truth.csv's rows; sealed again."""
    shutil.copytree(recorded, folder, ignore=shutil.ignore_patterns("plots"))
    header = json.loads((folder / "header.json").read_text())
    header["signals"][BUS] = {"role": "bus", "kind": "text"}
    header["signals"][LED] = {"role": "actuator", "kind": "rgb"}
    (folder / "header.json").write_text(json.dumps(header))
    with (folder / "signals.csv").open("a", newline="") as f:
        out = csv.writer(f, lineterminator="\n")
        out.writerows((t, BUS, text) for t, text in bus)
        out.writerows((t, LED, text) for t, text in led)
    if truth is not None:
        rows = list(csv.reader(io.StringIO((folder / "truth.csv").read_text())))
        truth(rows)
        text = io.StringIO()
        csv.writer(text, lineterminator="\n").writerows(rows)
        (folder / "truth.csv").write_text(text.getvalue())
    reseal(folder)
    return folder


def test_runs_whose_i2c_transfers_and_led_colours_differ_are_compared_and_plotted(recorded, tmp_path):
    a = edited(
        recorded, tmp_path / "a", bus=[(100_000, "0x68 reg 0x75 read 68 (98 us)")], led=[(200_000, "(255, 0, 0)")]
    )
    b = edited(
        recorded, tmp_path / "b", bus=[(100_000, "0x68 reg 0x75 read 70 (98 us)")], led=[(200_000, "(0, 255, 0)")]
    )
    code, text, err = run_cli("diff", a, b, "--out", tmp_path / "plot", "--fail-on-output")
    assert code == 1 and not err, (code, err)
    bus = next(line for line in text.splitlines() if line.startswith(BUS))
    assert "0x68 reg 0x75 read 68 (98 us) at 0.100000 s" in bus and "read 70" in bus, bus
    led = next(line for line in text.splitlines() if line.startswith(LED))
    assert "(255, 0, 0)" in led and "(0, 255, 0)" in led, led
    assert f"output {BUS} first differs at t=0.100000 s" in text, text
    assert (tmp_path / "plot" / "diff.png").read_bytes()[:4] == b"\x89PNG"
    code, text, _ = run_cli("diff", a, a, "--out", tmp_path / "plot", "--fail-on-output")
    assert code == 0 and "same within the thresholds" in text, text


def nan_x(rows, row=5):
    rows[row][rows[0].index("x_m")] = "nan"


@pytest.mark.parametrize("sides", ["B", "both"])
def test_a_nan_position_in_a_truth_file_is_named_and_never_same(recorded, tmp_path, sides):
    a = edited(recorded, tmp_path / "a", truth=nan_x if sides == "both" else None)
    b = edited(recorded, tmp_path / "b", truth=nan_x)
    code, text, err = run_cli("diff", a, b, "--out", tmp_path / "plot", "--max-pos-m", "1", "--max-rms-m", "1")
    assert code == 2, (code, text, err)
    assert "same within the thresholds" not in text
    assert "could not compare: " in text and "B's x_m is nan at t=0.200000 s" in text, text


def test_a_sensor_reading_out_of_range_on_both_sides_is_no_difference_and_on_one_side_is_named(recorded, tmp_path):
    def inf_sonar(rows, both_rows=(3,)):
        column = next(i for i, name in enumerate(rows[0]) if name not in ("t_us", "x_m", "y_m", "theta_rad"))
        for row in both_rows:
            rows[row][column] = "inf"

    a = edited(recorded, tmp_path / "a", truth=inf_sonar)
    b = edited(recorded, tmp_path / "b", truth=inf_sonar)
    code, text, _ = run_cli("diff", a, b, "--out", tmp_path / "plot")
    assert code == 0 and "same within the thresholds" in text, text
    c = edited(recorded, tmp_path / "c")
    code, text, _ = run_cli("diff", a, c, "--out", tmp_path / "plot")
    assert "(not a number on one side)" in text and "inf in A" in text, text


def test_a_diff_that_cannot_be_computed_exits_2_not_1(recorded, tmp_path, monkeypatch):
    import host.diff.command

    def broken(a, b):
        raise ValueError("could not convert string to float: 'x'")

    monkeypatch.setattr(host.diff.command, "compare", broken)
    code, text, err = run_cli("diff", recorded, recorded, "--out", tmp_path / "plot")
    assert code == 2 and "could not be compared: ValueError" in err and err.count("\n") == 1, (code, err)

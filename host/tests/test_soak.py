"""make soak's report, on a run of 36 simulated seconds (make soak itself runs a day)."""

import re

import pytest

from host import soak


def test_a_short_soak_reports_both_processes_memory_at_the_start_and_the_end(capsys):
    code = soak.main(["--hours", "0.01"])
    out = capsys.readouterr().out
    assert code == 0, f"expected exit 0 (growth within 8 MB), got {code}:\n{out}"
    for name in ("host RSS", "firmware RSS"):
        row = re.search(rf"^  {name} +([\d.]+) MB +([\d.]+) MB +([+-][\d.]+) MB$", out, flags=re.M)
        assert row and float(row[1]) > 1 and float(row[2]) > 1, f"expected a {name} row with figures in:\n{out}"
    assert re.search(r"budget control\.period: 720 values in 1 histogram entries, 0 misses", out), out
    assert "growth within 8 MB" in out, out


@pytest.mark.parametrize("hours", ["0", "-1", "1000"])
def test_a_soak_of_no_time_or_of_more_than_ten_days_is_refused(hours, capsys):
    with pytest.raises(SystemExit) as stop:
        soak.main(["--hours", hours])
    assert stop.value.code == 2 and "argument --hours: expected 0 < hours <= 240" in capsys.readouterr().err

"""The trace folder's files made while the run goes (host/artefacts/streaming.py) are the
bytes the folder's writers make from the whole recording at the end: with spills,
rewinds, UART text, notes at instants of their own and at the signals', a signal or a
truth column that comes late, and events out of time order (then the writers' own)."""

import io

import pytest

from host.artefacts import recorder as rec_mod
from host.artefacts.folder import _write_signals, _write_truth
from host.artefacts.recorder import Recorder
from host.artefacts.streaming import Streamed
from host.artefacts.vcd import write_vcd


class _Plant:
    outputs = {"enc": "level", "gps.uart": "bytes"}
    inputs = {"motor": "duty"}

    def __init__(self, late_column_us=None):
        self.t_us = 0
        self.late_column_us = late_column_us

    def output(self, name):
        return 0 if name == "enc" else b""

    def truth(self):
        row = {"x_m": self.t_us / 1e6, "zero": 0.0, "still": 1.5, "contacts": []}
        if self.late_column_us is not None and self.t_us >= self.late_column_us:
            row["late_m"] = -0.0 if self.t_us % 100_000 else 2.0
        return row


def _run(monkeypatch, *, spill_at=10**9, late_signal_us=None, late_column_us=None, swap_at_us=None, lag_us=5000):
    """2 s: an edge every 1 ms, a UART byte every 7 ms, a command every 50 ms, a rewind of
    3 ms at every 200 ms, a commit ``lag_us`` behind and a streaming turn after each step
    (the clock commits no later than it may rewind: a lag under 3 ms breaks that)."""
    monkeypatch.setattr(rec_mod, "SPILL_AT", spill_at)
    plant = _Plant(late_column_us)
    rec = Recorder(plant)
    rec.streamed = Streamed(rec)
    for t in range(1000, 2_000_001, 1000):
        plant.t_us = t
        if t == swap_at_us:  # (real time: an output stamped before an input)
            rec.command(t + 500, "motor", 7)
        rec.sensor(t, "enc", (t // 1000) % 2)
        if t % 7000 == 0:
            rec.sensor(t, "gps.uart", b"$GP,\n"[(t // 7000) % 5 :][:1])
        if t % 50_000 == 0:
            rec.command(t, "motor", t // 50_000)
        if late_signal_us is not None and t >= late_signal_us and t % 100_000 == 0:
            rec.command(t, "probe:late", 1, role="probe", kind="level")
        rec.sample(plant)
        if t % 200_000 == 0:  # a handler changed an output 3 ms back: the batch is void
            rec.rewind(t - 3000)
            plant.t_us = t - 3000
            rec.command(t - 3000, "motor", -1)
        rec.commit(plant.t_us - lag_us)
        rec.streamed.work()  # (a turn every step: Recorder.work waits for a few records)
    return rec


NOTES = [(0, "console", "hello"), (50_000, "console", "at a command"), (50_000, "budget_miss", "x 9 us")]
NOTES += [(123_456, "console", "an instant of its own"), (123_456, "console", "the same one again")]
NOTES += [(3_000_000, "console", "after the last change")]


def _files(tmp_path, rec, streamed) -> dict:
    """signals.csv, truth.csv and trace.vcd made from the recording (streamed: from the lines
    made as it went, where they fit)."""
    if streamed:
        rec.streamed.finish()
    sub = tmp_path / ("streamed" if streamed else "whole")
    sub.mkdir()
    if streamed and rec.streamed.usable:
        (sub / "signals.csv").write_bytes(b"t_us,signal,value\n" + _copied(rec.streamed, rec.streamed.signals_file))
    else:
        _write_signals(sub / "signals.csv", rec.events_in_time_order())
    columns = rec.truth_columns()
    if streamed and rec.streamed.truth_fits(columns):
        head = rec.streamed.truth_lines.header().encode()
        (sub / "truth.csv").write_bytes(head + _copied(rec.streamed, rec.streamed.truth_file))
    else:
        _write_truth(sub / "truth.csv", rec.truth, columns)
    write_vcd(
        sub / "trace.vcd",
        top="bot",
        comment="c",
        signals=rec.signals,
        initial=rec.initial,
        events=list(rec.events_in_time_order()),
        truth=rec.truth,
        notes=NOTES,
        columns=columns,
        streamed=rec.streamed.changes() if streamed else None,
    )
    return {name: (sub / name).read_bytes() for name in ("signals.csv", "truth.csv", "trace.vcd")}


def _copied(streamed, file) -> bytes:
    out = io.BytesIO()
    streamed.copy(file, out)
    return out.getvalue()


CASES = {
    "in memory": {},
    "spilled": {"spill_at": 100},
    "a signal and a column first seen before a spill": {
        "spill_at": 5000,
        "late_signal_us": 300_000,
        "late_column_us": 400_000,
    },
    "a signal first seen after a spill": {"spill_at": 100, "late_signal_us": 1_500_000},
    "a truth column first seen after a spill": {"spill_at": 100, "late_column_us": 1_500_000},
    "events out of time order": {"swap_at_us": 700_000},
    "a rewind past a commit": {"lag_us": 0},
}


@pytest.mark.parametrize("case", CASES)
def test_the_streamed_files_are_the_writers_bytes(tmp_path, monkeypatch, case):
    whole = _files(tmp_path, _run(monkeypatch, **CASES[case]), streamed=False)
    rec = _run(monkeypatch, **CASES[case])
    streamed = _files(tmp_path, rec, streamed=True)
    for name in whole:
        assert streamed[name] == whole[name], f"{case}: the streamed {name} differs from the one made at the end"
    assert b"the\\x20same\\x20one\\x20again" in whole["trace.vcd"] and b"\ns$GP," in whole["trace.vcd"]
    used = (rec.streamed.usable, rec.streamed.columns_ok, rec.streamed.vcd_ok)
    expected = {
        "a signal first seen after a spill": (True, True, False),
        "a truth column first seen after a spill": (True, False, False),
        "events out of time order": (False, True, True),
        "a rewind past a commit": (False, True, True),
    }.get(case, (True, True, True))
    assert used == expected, f"{case}: expected (usable, truth.csv's lines, VCD's) {expected}, got {used}"
    rec.close()

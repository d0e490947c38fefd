"""The recorder holds a bounded number of records in memory: what the clock committed goes
to a temporary file, and everything reads back the same, rewinds included."""

from host.artefacts import recorder as rec_mod
from host.artefacts.recorder import Recorder


class _Plant:
    outputs = {"enc": "level"}
    inputs = {"motor": "duty"}

    def __init__(self):
        self.t_us = 0

    def output(self, name):
        return 0

    def truth(self):
        return {"x_m": self.t_us / 1e6, "contacts": []}


def _record(spill_at, monkeypatch):
    """A run of 2 s: an edge every 1 ms, a command every 50 ms, a rewind of 3 ms at every
    200 ms, a commit after each step; returns the recorder and the most it held."""
    monkeypatch.setattr(rec_mod, "SPILL_AT", spill_at)
    plant = _Plant()
    rec = Recorder(plant)
    most = 0
    for t in range(1000, 2_000_001, 1000):
        plant.t_us = t
        rec.sensor(t, "enc", (t // 1000) % 2)
        if t % 50_000 == 0:
            rec.command(t, "motor", t // 50_000)
        rec.sample(plant)
        if t % 200_000 == 0:  # a handler changed an output 3 ms back: the batch is void
            rec.rewind(t - 3000)
            plant.t_us = t - 3000
            rec.command(t - 3000, "motor", -1)
        rec.commit(plant.t_us)
        most = max(most, len(rec._events) + len(rec._truth))
    return rec, most


def test_a_spilled_recording_reads_back_as_the_one_kept_in_memory(monkeypatch):
    kept, most_kept = _record(10**9, monkeypatch)
    spilled, most_spilled = _record(100, monkeypatch)
    assert spilled.events == kept.events, "the spilled events differ from those kept in memory"
    assert spilled.truth == kept.truth, "the spilled truth rows differ from those kept in memory"
    assert list(spilled.events_in_time_order()) == sorted(kept.events, key=lambda e: e[0])
    assert spilled.firmware_outputs() == kept.firmware_outputs()
    assert most_kept > 2000, f"expected the unspilled recorder to hold everything, it held at most {most_kept}"
    assert most_spilled <= 110, f"expected at most about 100 records in memory, held {most_spilled}"
    spilled.close()
    kept.close()


def test_events_recorded_out_of_time_order_are_written_sorted(monkeypatch):
    monkeypatch.setattr(rec_mod, "SPILL_AT", 2)
    plant = _Plant()
    rec = Recorder(plant)
    for t, value in ((100, 1), (300, 0), (200, 1), (400, 0)):  # (real time: an output stamped early)
        rec.sensor(t, "enc", value)
        rec.commit(t)
    assert [e[0] for e in rec.events] == [100, 300, 200, 400]
    assert [e[0] for e in rec.events_in_time_order()] == [100, 200, 300, 400]
    rec.close()


def test_two_readers_go_through_a_spill_side_by_side(monkeypatch):
    """The VCD writer reads the events twice at once (the signals, and a UART's text)."""
    spilled, _ = _record(100, monkeypatch)
    expected = list(spilled.events_in_time_order())
    a, b = spilled.events_in_time_order(), spilled.events_in_time_order()
    pairs = list(zip(a, b))
    assert [x for x, _ in pairs] == expected and [y for _, y in pairs] == expected, "interleaved readers differ"
    spilled.close()

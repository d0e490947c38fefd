"""The bus-heavy case of ``make bench`` (host/bench/imu_bot): its firmware polls the IMU's
data-ready bits at every tick of its 208 Hz Timer and reads each new sample once, the
ranger's results come at its measuring rate, and every bus reading of a pinned second (the
trace's BUS records: instant, bytes written, bytes read, outcome) is the pinned one, so a
harness that answers some transfers without an exchange must give exactly the same bytes
at the same instants."""

import hashlib
import json

from host.bench import run_imu_bot

# (re-pinned when soft callbacks left queued by a C call began to run at the firmware's next
# bytecode branch, as on a board, instead of at its next call into the shim: the Timer's
# reads that came due in the main loop's bus transfers now come before its next ones)
PINNED_BUS = "19751d0bdca64212b649444a9b3769b454fd3a35f5433a72215cb7f52a839c26"


def test_every_tick_polls_and_every_sample_is_read_once(tmp_path):
    run = run_imu_bot(1000, record=True, trace=True, artefacts=tmp_path / "run")
    assert run["printed"], f"expected the firmware's summary line; artefacts in {tmp_path}"
    samples, polls, ranges = (int(v) for v in run["printed"].split()[1:4])
    assert 200 <= polls <= 210, f"expected 208 Timer ticks in the second driven, got {polls} ({run['printed']})"
    assert samples == polls, f"expected a new sample at every tick (ODR = Timer rate), got {samples} of {polls}"
    assert 25 <= ranges <= 35, f"expected a range about every 33 ms, got {ranges} in a second"
    records = [line for line in (tmp_path / "run" / "trace.jsonl").read_text().splitlines() if '"msg":"BUS"' in line]
    assert len(records) == run["transfers"], f"expected every transfer in trace.jsonl, got {len(records)}"
    digest = hashlib.sha256("\n".join(records).encode()).hexdigest()
    first = json.loads(records[0])
    assert digest == PINNED_BUS, f"the bus readings changed: {digest} (first {first}); artefacts in {tmp_path}"

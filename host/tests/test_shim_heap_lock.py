"""Under micropython.heap_lock() the shim's print, clock reads and waits allocate nothing
the firmware sees (upstream's extmod/asyncio_heaplock.py runs in the loop as on the plain
port: docs/shim.md)."""

import pytest

pytestmark = pytest.mark.hil


def test_print_clock_reads_and_polls_work_with_the_heap_locked(run_case):
    script = [(12_345, "a", 1)]
    rig, r = run_case("heap_locked_waits", 0.5, script)
    assert "Traceback" not in rig.console, rig.console
    assert r["items"] == 3 and r["ends"] == 123456, rig.console
    assert r["read_us"] == 0, "a print moves no virtual time"
    assert r == {**r, "ready": 1, "woke_us": 12_345}, f"expected the poll woken at the edge's instant: {r}"

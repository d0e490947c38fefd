"""The board's _thread (an RP2040's second core, an ESP32's FreeRTOS tasks) on the one
virtual clock (host/shim/_hilthread.py, docs/shim.md "Threads"): the firmware's threads take
turns, at their waits and every millisecond of a busy one, so each sees the others' work at
its virtual instant, and the same seed gives the same trace."""

import pytest


def test_threads_interleave_at_their_instants_share_locks_and_report_their_failures(run_case):
    rig, r = run_case("threads", 0.3)
    where = f"(console: {rig.console!r}; artefacts: {rig.artefacts})"
    # a thread sleeping 15 ms a pass beside a main program sleeping 10 ms: each wakes at its own
    # instant, the two in the order of the clock
    got = r.get("interleaved")
    assert got is not None, f"expected the firmware to finish, {where}"
    times = [t for _who, t in got]
    assert times == sorted(times), f"expected the wakes in the order of virtual time, got {got} {where}"
    assert [t for who, t in got if who == "t"] == [15, 30, 45, 60], f"the thread's wakes, got {got} {where}"
    assert [t for who, t in got if who == "m"] == [10, 20, 30, 40, 50, 60], f"the main program's, got {got} {where}"
    # a busy thread (no sleep) runs while the main program sleeps: its count grows between reads
    seen = r["busy_seen"]
    grows = seen[0] > 0 and all(b > a for a, b in zip(seen, seen[1:]))
    assert grows, f"expected the busy thread to run between the main's sleeps, its passes seen {seen} {where}"
    # a lock held across a 20 ms sleep: the main program gets it when the thread lets go
    lock = r["lock"]
    assert lock[0] == ("held", 0) and ("main got it", 20) in lock, (
        f"expected the lock taken at 20 ms, got {lock} {where}"
    )
    assert "Unhandled exception in thread started by <function fails" in rig.console, where
    assert "ValueError: from the thread" in rig.console and r["after_failure"] is True, where


def test_the_same_seed_gives_the_same_trace_with_threads(run_case):
    a, _ = run_case("threads", 0.3)
    b, _ = run_case("threads", 0.3)
    assert a.trace_digest == b.trace_digest, f"expected one trace, got two ({a.artefacts}, {b.artefacts})"


def test_a_firmware_that_ends_with_a_thread_still_running_ends_cleanly(run_case):
    """The thread ends with the firmware (as the process ends), quietly: no libc complaint
    on the console, no hang."""
    rig, r = run_case("threads_left", 0.1)
    assert r.get("done") is True, f"expected the firmware to end, console: {rig.console!r}"
    assert "pthread" not in rig.console and "Traceback" not in rig.console, rig.console


@pytest.mark.parametrize("cpu", ["free", "rp2040@125MHz"])
def test_a_thread_whose_wake_comes_during_the_main_programs_compute_runs_before_its_print(run_case, monkeypatch, cpu):
    """On a board the second core runs while the main program computes: a thread whose wake
    comes during straight-line compute (no clock read, no loop: no look of the branch hook)
    has run by the time the main program prints, so its print comes first and what it set is
    there after the print (Pololu's line_follower.py reads the list its thread fills). With
    the CPU free the main program's compute takes no time: it prints and reads at its wake,
    before the thread's (as a board infinitely fast would)."""
    monkeypatch.setenv("MPYFIL_CPU", cpu)
    rig, r = run_case("threads_print", 0.05)
    where = f"(console: {rig.console!r}; artefacts: {rig.artefacts})"
    printed = rig.console.index("R printed")
    worker = rig.console.index("R worker_us")
    if cpu == "free":
        assert r["seen"] == [] and printed < worker, f"expected the main program first, {where}"
        return
    assert r["seen"] == [1, 2, 3], f"expected the thread's list after the main program's print, {where}"
    assert worker < printed, f"expected the thread's print before the main program's, {where}"
    assert 1050 <= r["worker_us"] <= r["main_us"], f"expected the thread at 1,050 us, then the main, {where}"

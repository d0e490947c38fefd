"""Loops that call nothing of the board's (`while playing: pass`): on a board the CPU spends
time there, so the Timer or the IRQ they wait for comes due. The harness's interpreter runs
the shim at every 256th of the firmware's own branches (host/core/micropython/hilcount.patch,
_hilfast.branches, _hil._branches): such a loop moves virtual time as a loop of clock reads
does (docs/mcu-time.md, "A loop that calls nothing of the board's")."""

import re

import pytest


@pytest.mark.parametrize("cpu", ["free", "rp2040@125MHz"])
def test_a_wait_on_a_flag_ends_when_the_timer_or_irq_that_clears_it_fires(run_case, monkeypatch, cpu):
    """A buzzer's 100 ms note held by a one-shot Timer (Pololu's Buzzer.play), a bumper's IRQ
    flag set at 250 ms, and a 30 ms Timer wait under heap_lock: each loop ends just after
    its callback. With compute free, the loop's time is a spinning read's (10 us a look);
    on an RP2040 it is the loop's own compute, and the look before the callback's instant
    comes within a few branches of it."""
    monkeypatch.setenv("MPYFIL_CPU", cpu)
    rig, r = run_case("spin_wait", 0.5, [(250_000, "button", 1)])
    where = f"(console: {rig.console!r}; artefacts: {rig.artefacts})"
    # (with MCU time the callbacks' own compute comes on top: the bumper's handler appends
    # a clock read to a list, about 130 us on an RP2040 by the cost model)
    late_us = 20 if cpu == "free" else 60
    played, locked = r.get("played_us", -1), r.get("locked_us", -1)
    assert 100_000 <= played <= 100_000 + late_us, f"expected the 100 ms note to end then, got {r} {where}"
    assert 30_000 <= locked <= 30_000 + late_us, f"expected the locked wait to end at 30 ms, got {r} {where}"
    pressed, seen = r["pressed_at_us"]
    handler_us = 20 if cpu == "free" else 200
    assert seen - pressed <= handler_us, f"expected the flag seen just after the IRQ, got {r} {where}"


def test_a_loop_that_never_yields_runs_on_in_virtual_time_as_on_a_board(run_case):
    """`while True: pass` after a sleep: a board spins there while time goes on; so does the
    loop (the watchdog named it before the branch hook: test_shim.py, with HIL_PURE), and the
    run says once, a second after the firmware last called the board, where it spins."""
    rig, _ = run_case("hangs", 1.3)
    where = f"(console: {rig.console!r}; artefacts: {rig.artefacts})"
    assert rig.t_us == 1_300_000, f"expected the run to reach 1.3 s, got t={rig.t_us} us {where}"
    notes = [text for _t, text in rig.bus_trace.notes if "a loop that never ends?" in text]
    assert len(notes) == 1, f"expected the loop named once, 1 s after its last call into the board, got {notes} {where}"
    assert "from virtual t=0.100000 s to t=1.1" in notes[0] and 'File "main.py", line' in notes[0], notes[0]


def test_a_soft_callback_that_spins_forever_runs_on_in_virtual_time_and_is_named(run_case):
    """A Timer callback (soft) that waits for what only the main program could do never ends
    on a board either, while the board's clock goes on: so does the run's (each look at the
    branches a read of the callback's), the main program never runs again, and the run says
    once, a second after the callback began, where it spins."""
    rig, _ = run_case("spin_in_callback", 1.2)
    where = f"(console: {rig.console!r}; artefacts: {rig.artefacts})"
    assert rig.t_us == 1_200_000, f"expected the run to reach 1.2 s, got t={rig.t_us} us {where}"
    notes = [text for _t, text in rig.bus_trace.notes if "a loop that never ends?" in text]
    assert len(notes) == 1, f"expected the loop named once, got {notes} {where}"
    assert re.search(r'File "main.py", line 1[12], in tick', notes[0]), notes[0]

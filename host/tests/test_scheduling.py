"""Scheduling as the port does it (docs/shim.md, "Where callbacks run"): soft callbacks
(Timer, Pin.irq without hard=True, micropython.schedule) run at the firmware's bytecode
boundaries and in the waits that handle events, never inside what is a C call on a board
(time_pulse_us, the busy end of sleep_us, bus transfers); hard IRQs' handlers run at their
edges even there; the scheduler's queue holds MICROPY_SCHEDULER_DEPTH (8 on rp2 and esp32)
callbacks, as py/scheduler.c's. Each case runs on both of the shim's paths for a STATE's
changes (_hilfast's C loop and the pure-Python one)."""

import re

import pytest

from host.core.errors import FirmwareHung
from host.rig.config.app import App, BoardSettings
from host.rig.config.budgets import PeriodBudget
from host.tests.conftest import FIRMWARE, results
from sim_plant.scripted import ScriptedPlant

pytestmark = pytest.mark.hil

DEPTH = 8  # MICROPY_SCHEDULER_DEPTH in ports/rp2/mpconfigport.h and ports/esp32/mpconfigport.h


@pytest.fixture(params=["c", "pure"], autouse=True)
def path(request, monkeypatch):
    if request.param == "pure":
        monkeypatch.setenv("HIL_PURE", "1")
    else:
        monkeypatch.delenv("HIL_PURE", raising=False)
    return request.param


def _where(rig) -> str:
    return f"(console and trace: {rig.artefacts})"


def test_a_timer_callback_never_runs_inside_time_pulse_us_and_the_control_loop_is_late(run_case):
    """A 10 ms control loop on a Timer and a main program reading a ranger with
    time_pulse_us (an echo from 5 to 30 ms, then every 70 ms): the ticks due during a read
    run when it has returned (at the echo's end), none of them sees the read's flag set,
    and the loop probe's period budget sees the lateness."""
    echoes = [(5_000 + k * 70_000, 30_000 + k * 70_000) for k in range(4)]
    script = [e for start, end in echoes for e in ((start, "echo", 1), (end, "echo", 0))]
    budget = PeriodBudget("control.period", "probe:control", period_us=10_000, tolerance_us=500)
    rig, r = run_case("sched_sonar", 0.4, script, budgets=[budget])
    assert r["inside"] == 0, f"{r['inside']} Timer callbacks ran inside time_pulse_us {_where(rig)}"
    assert r["reads"] == [(25_000, end) for _start, end in echoes], r["reads"]
    # a read begins when the sleep of 25 ms after the one before ends (at 0, 55, 125, 195 ms)
    # and lasts to its echo's end
    reads = [(0 if k == 0 else echoes[k - 1][1] + 25_000, end) for k, (_start, end) in enumerate(echoes)]
    expected = []  # each tick at its time, or at the end of the read it came due in
    for k in range(1, (echoes[-1][1] + 25_000) // 10_000 + 1):  # (to the last sleep's end, 265 ms)
        due = 10_000 * k
        late = [end for begin, end in reads if begin < due <= end]
        expected.append(late[0] if late else due)
    assert r["ticks"] == expected, f"ticks ran at {r['ticks']}, expected {expected} {_where(rig)}"
    stats = budget.stats()
    assert budget.misses > 0 and stats["max"] >= 20_000, f"the period budget did not see the late loop: {stats}"


def _echo_and_edges_app(name: str, script: list) -> App:
    """An RP2040 bench with an echo on GP5 and two edge lines on GP6 and GP7, as ``script`` sets them."""
    return App(
        name=name,
        default_board="rpi_pico_bench",
        wiring={"ECHO": "echo", "A": "a", "B": "b"},
        make_plant=lambda: ScriptedPlant(script, outputs={"echo": "level", "a": "level", "b": "level"}, inputs={}),
        board=BoardSettings(pins={"ECHO": 5, "A": 6, "B": 7}, console_baud=0),
    )


def test_a_hard_irq_runs_inside_time_pulse_us_and_a_soft_one_after_it(make_rig):
    """On an RP2040 (ports/rp2/machine_pin.c: hard=True runs the handler in the interrupt):
    edges at 10 and 12 ms during a read that ends at 30 ms, then at 38 and 39 ms while a
    Timer callback (due at 35 ms) sleeps 10 ms."""
    script = [(5_000, "echo", 1), (10_000, "a", 1), (12_000, "b", 1), (30_000, "echo", 0)]
    script += [(36_000, "a", 0), (36_000, "b", 0), (38_000, "a", 1), (39_000, "b", 1)]
    app = _echo_and_edges_app("sched-hard", script)
    rig = make_rig(app, main_dir=FIRMWARE / "sched_hard", allow_exit=True)
    rig.run_for(0.05)
    rig.stop()
    r = results(rig.console)
    assert r.get("width") == 25_000, rig.console
    assert r["hard"] == [(10_000, True), (38_000, True)], f"the hard handler: {r['hard']} {_where(rig)}"
    assert r["soft"] == [(30_000, False), (45_000, False)], f"the soft handler: {r['soft']} {_where(rig)}"


@pytest.mark.parametrize(
    "board, ran, ran_ms",
    [
        # ports/rp2/mphalport.c: mp_hal_delay_us handles events for 2 ms, then a tight loop;
        # mp_hal_delay_ms handles them all along
        ("rpi_pico", [1500, 2500, 2500], [1500, 2900]),
        # ports/esp32/mphalport.c: both handle events but in their last 155 us
        ("esp32_devkitc", [1500, 2200, 2500], [1500, 3000]),
    ],
)
def test_sleep_us_runs_callbacks_only_where_the_ports_delay_handles_events(make_rig, board, ran, ran_ms):
    app = App(
        name="sched-sleep-us",
        default_board=board,
        wiring={},
        make_plant=lambda: ScriptedPlant((), outputs={}, inputs={}),
        board=BoardSettings(console_baud=0),
    )
    rig = make_rig(app, main_dir=FIRMWARE / "sched_sleep_us", allow_exit=True)
    rig.run_for(0.01)
    rig.stop()
    r = results(rig.console)
    assert r.get("returned") == 2500 and r.get("returned_ms") == 3000, rig.console
    assert r["ran"] == ran, f"{board}: timers in sleep_us ran at {r['ran']}, expected {ran} {_where(rig)}"
    assert r["ran_ms"] == ran_ms, f"{board}: timers in sleep_ms ran at {r['ran_ms']}, expected {ran_ms} {_where(rig)}"


def test_micropython_schedule_raises_queue_full_past_the_ports_depth(run_case):
    rig, r = run_case("sched_queue", 0.05)
    full = "schedule queue full"
    assert r.get("queued") == list(range(DEPTH)), rig.console
    assert r["refused"] == [(i, "RuntimeError", full) for i in range(DEPTH, 12)], rig.console
    assert r["ran"] == list(range(DEPTH)), f"what was queued must run, in order {_where(rig)}"


def test_a_job_an_irq_handler_schedules_during_a_sleep_runs_at_the_edge(run_case):
    """micropython.schedule from a soft pin IRQ's handler while the main program sleeps:
    the sleep's next pass runs the job at once (ports/rp2/mphalport.c, mp_hal_delay_ms;
    ports/esp32/mphalport.c, mp_handle_pending each tick). It ran at the next input change
    (the release, 30 ms later) or at the sleep's end."""
    rig, r = run_case("sched_from_irq", 0.1, [(20_000, "button", 0), (50_000, "button", 1)], initial={"button": 1})
    assert [level for level, _t in r["edges"]] == [0, 1], f"expected the press and the release: {r} {_where(rig)}"
    for (level, edge_us), (job_level, job_us) in zip(r["edges"], r["jobs"], strict=True):
        assert job_level == level and edge_us <= job_us < edge_us + 50, (
            f"expected each job at its edge, got edges {r['edges']}, jobs {r['jobs']} {_where(rig)}"
        )


def test_a_callback_longer_than_its_period_makes_the_main_loop_crawl_with_a_bounded_queue(run_case, path):
    """10 ms ticks, 15 ms callbacks that stop their timer at the 20th run: the ticks that
    came due meanwhile were queued up to the depth (the rest lost, as on a board), so
    DEPTH - 1 more runs follow (the running one is out of the queue). Meanwhile the main
    loop crawls as on a board, where the scheduler runs one callback a pending check
    (py/scheduler.c, mp_sched_run_pending): one at its loop's branch, one in its sleep's
    first pass (ports/rp2/mphalport.c, mp_hal_delay_ms), a turn every 30 ms; the loop
    probe's period budget shows the gap. On an interpreter that cannot see branches (the
    pure path) the queue runs to its end at the firmware's next call into the shim
    instead, and the loop waits for it (docs/shim.md, "Where callbacks run")."""
    budget = PeriodBudget("main.period", "probe:control", period_us=5_000, tolerance_us=500)
    rig, r = run_case("sched_slow", 0.8, budgets=[budget])
    assert r.get("stopped_at") == [20], rig.console
    runs = [10 + 15 * k for k in range(20 + DEPTH - 1)]
    assert r["runs"] == runs, f"runs at {r['runs']} ms, expected {runs} {_where(rig)}"
    resumed = runs[-1] + 15
    steps = r["steps"]
    if path == "c":  # the tick at 10 ms comes due at the sleep's last instant: the branch after runs it
        crawl = [0, 5] + list(range(25, resumed + 1, 30))
        assert steps[: len(crawl) + 1] == crawl + [resumed + 5], (
            f"main loop steps {steps}, expected {crawl} {_where(rig)}"
        )
        assert budget.stats()["max"] == 30_000, budget.stats()
    else:  # (its next call into the shim runs the queue to its end: the loop waits for it)
        assert steps[:3] == [0, 5, resumed], f"main loop steps {steps} {_where(rig)}"
    assert steps[steps.index(resumed) :] == list(range(resumed, 600, 5)), f"main loop steps {steps} {_where(rig)}"


def test_a_callback_that_never_lets_the_main_loop_rest_ends_with_the_run_not_memory_error(run_case, path):
    """A 10 kHz Timer whose callback sleeps 20 ms: the queue stays full (each tick past it
    is lost, as on a board) and the run reaches its end time (the queue used to grow
    without bound until the shim died with a MemoryError, blamed on the callback). The
    main loop crawls as on a board, a turn every two callbacks (40 ms: one at its loop's
    branch, one in its sleep); on the pure path never again (its calls into the shim run the
    queue to its end, which is never empty)."""
    rig, _ = run_case("sched_starved", 2.0, allow_exit=False)
    lines = rig.console.splitlines()
    assert "MemoryError" not in rig.console and "Traceback" not in rig.console, rig.console[-2000:]
    mains = [int(line.split()[1]) for line in lines if line.startswith("M ")]
    if path == "c":
        expected = list(range(0, 2000, 40))  # (to the run's end, 2 s)
        assert mains == expected, f"the main loop ran at {mains[:8]}... ms, expected {expected[:8]}... {_where(rig)}"
    else:  # (its calls into the shim run the queue to its end, which is never empty)
        assert mains == [0], f"the main loop ran again: {mains[:8]} {_where(rig)}"
    calls = [line.split()[1:] for line in lines if line.startswith("C ")]
    assert calls[-1] == ["100", "1980"], f"callbacks (count, ms): {calls[-3:]} {_where(rig)}"


def _hard_irq_app(name: str) -> App:
    script = [(t, "a", i % 2 == 0) for i, t in enumerate(range(2_000, 12_000, 2_000))]
    return App(
        name=name,
        default_board="rpi_pico_bench",
        wiring={"A": "a"},
        make_plant=lambda: ScriptedPlant(script, outputs={"a": "level"}, inputs={}),
        board=BoardSettings(pins={"A": 5}, console_baud=0),
    )


def test_a_hard_handler_does_what_a_board_allows_with_its_heap_locked(make_rig):
    """shared/runtime/mpirq.c, mp_irq_handler: a hard handler runs with the heap locked. What
    it may do on a board it does here: read its pin, the clock and its IRQ's flags, drive a pin
    and a PWM, store into buffers made before, count, run as a bound method, schedule a soft
    callback: five edges, each at its instant, no MemoryError."""
    rig = make_rig(_hard_irq_app("hard-heap"), main_dir=FIRMWARE / "hard_irq_heap", allow_exit=True)
    rig.run_for(0.03)
    rig.stop()
    r = results(rig.console)
    where = _where(rig)
    assert r.get("edges") == 5 and r["scheduled"] == 5, f"expected 5 edges handled and scheduled, got {r} {where}"
    assert [t // 1000 for t in r["at"]] == [2, 4, 6, 8, 10], f"expected the edges at their instants, got {r} {where}"
    # (rp2's IRQ_RISING 8, IRQ_FALLING 4)
    assert r["flags"] == [8, 4, 8, 4, 8], f"expected rising, falling, ... {r} {where}"


def test_a_hard_handler_that_allocates_fails_as_on_a_board(make_rig, path):
    """A float made in a hard handler is an allocation: MemoryError at the first edge, as on a
    board (the heap is locked there), the run ending with the handler named."""
    if path == "pure":
        pytest.skip("the pure path (a user's own interpreter) runs hard handlers unlocked: its outputs allocate")
    rig = make_rig(_hard_irq_app("hard-allocates"), main_dir=FIRMWARE / "hard_irq_allocates", allow_exit=True)
    with pytest.raises(Exception, match=r"on_edge raised MemoryError: memory allocation failed, heap is locked"):
        rig.run_for(0.03)
    assert 'File "main.py", line 10, in on_edge' in rig.console, _where(rig)


def test_a_soft_callback_waiting_on_a_flag_a_hard_handler_sets_ends_at_the_edge(make_rig, path):
    """A soft Timer callback at 10 ms spins on a flag alone (`while not ready: pass`, no read of
    the board's) that a hard IRQ's handler sets at an edge at 13 ms: on a board the handler
    interrupts the callback and the loop ends there. It hung before (the VM's branch hook did
    nothing inside a callback): each look at the branches is a read of the callback's now. On
    the pure path (no branch hook) the watchdog says so."""
    app = _echo_and_edges_app("callback-flag", [(13_000, "a", 1)])
    watchdog_s = 3 if path == "pure" else 20
    rig = make_rig(app, main_dir=FIRMWARE / "callback_flag_spin", allow_exit=True, watchdog_s=watchdog_s)
    if path == "pure":
        with pytest.raises(FirmwareHung, match="an interpreter without the harness's branch hook"):
            rig.run_for(0.04)
        return
    rig.run_for(0.04)
    rig.stop()
    r = results(rig.console)
    ((start, ended),) = r["waited"]
    assert 10_000 <= start < 10_100 and 13_000 <= ended <= 13_020, f"expected the end at 13 ms: {r} {_where(rig)}"


def test_a_hard_handler_that_spins_forever_is_named_by_the_watchdog(make_rig):
    """A hard IRQ's handler runs at its edge's instant (its reads move no time), so one that
    waits for what only the main program could do hangs the run, as nothing else runs on a
    board until it returns: the watchdog stops it and says where it spins, and why."""
    app = _echo_and_edges_app("hard-spins", [(13_000, "a", 1)])
    rig = make_rig(app, main_dir=FIRMWARE / "spin_in_hard_handler", watchdog_s=3.0)
    with pytest.raises(FirmwareHung) as err:
        rig.run_for(0.5)
    text = str(err.value)
    assert re.search(r'File "main.py", line 1[01], in on_a', text), f"expected the handler's line, got {text}"
    assert "In a hard IRQ's handler a loop like that moves no virtual time" in text, text


def test_a_soft_callback_that_busy_waits_sees_the_clock_and_its_pins_go_on(make_rig):
    """A soft Timer callback at 10 ms busy-waits for a sonar echo (up at 12 ms, down at 15 ms)
    as public robot code does, and another at 30 ms for 500 us of the clock alone: on a
    board the clock and the pins go on while a soft callback runs, so each wait ends at the
    plant's instant (to a spinning read's 10 us); a hard IRQ's handler (an edge at 13 ms) runs
    at its edge inside the wait, a soft one's (13.5 ms) once the callback has returned. It
    hung before (a handler's reads moved no time)."""
    script = [(12_000, "echo", 1), (13_000, "a", 1), (13_500, "b", 1), (15_000, "echo", 0)]
    app = _echo_and_edges_app("callback-spin", script)
    rig = make_rig(app, main_dir=FIRMWARE / "callback_spin", allow_exit=True, watchdog_s=20)
    rig.run_for(0.06)
    rig.stop()
    r = results(rig.console)
    ((start, rose, fell),) = r["read"]
    assert 10_000 <= start < 10_100 and 12_000 <= rose <= 12_010 and 15_000 <= fell <= 15_010, (r, _where(rig))
    assert r["hard"] == [13_000], f"the hard handler at its edge, inside the wait: {r} {_where(rig)}"
    ((soft_at, soft_inside),) = r["soft"]
    assert soft_at >= fell and not soft_inside, f"the soft one after the callback returned: {r} {_where(rig)}"
    ((began, ended),) = r["delay"]
    assert 30_000 <= began < 30_100 and 500 <= ended - began <= 510, f"500 us of the clock: {r} {_where(rig)}"

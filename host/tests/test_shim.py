"""The shim's machine/time/select/asyncio behave like a board's, in virtual time."""

import os
import re
import time

import pytest

from host.core.errors import FirmwareError, FirmwareHung

pytestmark = pytest.mark.hil


def test_irq_handlers_run_in_edge_order_with_ticks_at_the_edge(run_case):
    script = [(1000, "a", 1), (1200, "b", 1), (1500, "a", 0), (1700, "b", 0), (5000, "a", 1)]
    _, r = run_case("irq_order", 0.01, script)
    assert r["events"] == [("Pin(34)", 1, 1000), ("Pin(35)", 1, 1200), ("Pin(34)", 0, 1500)], r
    assert r["busy_saw"] == ("Pin(34)", 1, 5000), "a handler must run while main polls the clock"


def test_timers_fire_periodic_one_shot_and_by_freq_in_virtual_time(run_case):
    _, r = run_case("timers", 0.4)
    assert r["periodic"] == [50 * k for k in range(1, 7)], r
    assert r["oneshot"] == [120], r
    assert r["fast"] == [10 * k for k in range(1, 21)], r


def test_time_pulse_us_measures_a_pulse_and_reports_its_timeouts(run_case):
    script = [(10_000, "echo", 1), (10_583, "echo", 0), (40_000, "echo", 1), (100_000, "echo", 0)]
    _, r = run_case("pulse", 0.1, script)
    assert r == {"pulse": 583, "no_start": -2, "too_long": -1}, r


def test_ticks_wrap_like_a_32_bit_board_and_start_near_the_wrap(run_case):
    _, r = run_case("ticks", 12)
    period = 1 << 30
    assert period - 10_001 <= r["ms0"] < period and r["us0"] >= period - 10_000_001, r
    assert r["ms1"] < r["ms0"], "ticks_ms must wrap 10 s into the run"
    assert r["add_wrap"] == 0 and r["diff_wrap"] == 10
    assert r["elapsed_ms"] == 11_000 and r["elapsed_us"] == 11_000_000
    assert r["after_us"] == 250 and r["cpu"] is True


def test_busy_wait_on_ticks_terminates_in_virtual_time(run_case):
    t0 = time.monotonic()
    _, r = run_case("busy_wait", 0.2)
    assert r["waited_ms"] == 100, r
    assert r["polls"] > 1000, "each clock read costs a little virtual time, so the loop polls many times"
    assert time.monotonic() - t0 < 10


def test_asyncio_sleeps_events_and_timeouts_run_in_virtual_time(run_case):
    t0 = time.monotonic()
    _, r = run_case("asyncio_time", 0.5)
    assert r["log"] == [("a", 30), ("b", 50), ("a", 60), ("a", 90), ("b", 100), ("event", 100), ("timeout", 300)], r
    assert time.monotonic() - t0 < 20


def test_pins_signal_pwm_adc_and_irq_masking_reach_the_plant(run_case):
    script = [(1_000, "adc", 1234), (5_000, "button", 0), (15_000, "a", 1)]
    rig, r = run_case("pins", 0.1, script, initial={"button": 1, "adc": 777})
    assert r["button_pressed"] == [0] and r["button_pressed_later"] == [1, 1], r
    assert r["pwm"] == [20_000, 30_000] and r["uid"] == 6
    assert r["adc"] == [1234, 1234], r
    assert r["while_disabled"] == 0 and r["after_enable"] == 1, r
    assert r["done"] == 1
    log = rig.plant.log
    assert [(t, v) for t, n, v in log if n == "out1"] == [(0, 0), (0, 1), (1000, 0), (2000, 1)], log
    assert [(t, v) for t, n, v in log if n == "pwm"] == [(12000, 1000), (13000, 30000), (14000, 0)], log


def test_machine_reset_restarts_the_firmware_and_keeps_virtual_time(run_case):
    rig, _ = run_case("reset", 0.25)
    assert rig.resets == 2, rig.console
    assert rig.console.count("R cause") == 3
    assert rig.t_us == 250_000


def test_firmware_exception_fails_with_the_micropython_traceback(run_case):
    with pytest.raises(FirmwareError) as err:
        run_case("raises", 1.0)
    text = str(err.value)
    assert "ZeroDivisionError" in text and 'File "main.py", line 5, in control_step' in text, text
    assert "virtual t=0.150000 s" in text, text
    assert "artefacts:" in text


def test_firmware_that_never_yields_is_stopped_by_the_watchdog(run_case, monkeypatch):
    """On an interpreter without the harness's branch hook (the shim's pure-Python path, as
    a user's own MICROPYTHON runs it), a loop that calls nothing of the board's moves no
    virtual time: the watchdog names it. (With the hook it runs on: test_spin_wait.py.)"""
    monkeypatch.setenv("HIL_PURE", "1")
    t0 = time.monotonic()
    with pytest.raises(FirmwareHung) as err:
        run_case("hangs", 1.0, watchdog_s=1.0)
    assert "stopped answering" in str(err.value) and "virtual t=0.100000 s" in str(err.value), str(err.value)
    assert "where it was (interrupted by the watchdog)" in str(err.value), str(err.value)
    assert re.search(r'File "main.py", line [45], in <module>', str(err.value)), (
        "the firmware's own line, where it spins"
    )
    assert "a Timer or an IRQ it waits for (`while playing: pass`) never comes due" in str(err.value), str(err.value)
    assert time.monotonic() - t0 < 20


def test_handler_that_drives_an_output_sees_every_edge_at_its_time(run_case):
    """IRQ edges are batched speculatively; a handler's output write rolls the plant back."""
    script = [(1000, "a", 1), (1500, "b", 1), (2000, "a", 0), (2500, "b", 0), (3000, "a", 1)]
    rig, r = run_case("irq_writes", 0.02, script)
    assert r["seen"] == [(1, 0, 1000), (0, 1, 2000), (1, 0, 3000)], r
    writes = [(t, v) for t, n, v in rig.plant.log if n == "out1"]
    assert writes == [(0, 0), (1000, 1), (2000, 0), (3000, 1)], writes
    assert rig.stats.rollbacks >= 1


def test_edges_shared_by_several_pin_objects_all_reach_their_handlers(run_case):
    """1000 edges in 100 ms on one signal that three pins watch (wired together, as a
    board's pins on one encoder line), each with its handler, during one sleep: the host
    splits the batch so that no STATE outgrows a frame, and every handler sees every
    edge. (Three Pin objects for one pin share that pin's one IRQ, as on a board.)"""
    script = [(1_000 + 100 * k, "a", (k + 1) % 2) for k in range(1000)]
    wiring = {"ENC_L_A": "a", "ENC_L_B": "a", "ENC_R_A": "a"}  # pins 34, 35, 36
    rig, r = run_case("shared_pin", 0.3, script, wiring=wiring)
    assert r["counts"] == [1000, 1000, 1000], r
    assert rig.stats.link_round_trips >= 1000 * 3 // 200, "expected the edges split over several batches"


def test_u_prefixed_modules_are_the_shims_in_virtual_time(run_case):
    """`from utime import sleep_us` (older drivers' habit) gets the shim: a 10 us trigger
    pulse lasts 10 virtual us, not 0."""
    rig, r = run_case("u_modules", 0.1)
    assert r == {"slept_us": 250, "slept_ms": 40, "same": [True, True, True]}, r
    writes = [(t, v) for t, name, v in rig.plant.log if name == "out1"]
    assert len(writes) == 3 and writes[2][0] - writes[1][0] == 10, writes


def test_zero_waits_let_time_move_and_board_errors_are_raised(run_case):
    _, r = run_case("zero_waits", 0.5)
    assert r == {
        "zero_sleeps_end": True,
        "async_spins_end": True,
        "uart_str": 3,
        "float_ms_raises": True,
        "overflow": True,
        "add_edge": (1 << 29) - 1,
    }, r


def test_esp32_pwm_duty_is_ten_bits_and_honoured_when_the_pwm_is_made(run_case):
    rig, r = run_case("pwm_duty", 0.01)
    # ports/esp32/machine_pwm.c: duty << 6 (512: 32768); 1023 is 65472 in 1.25 (set_duty_u10),
    # the whole period from 1.26 (check_duty_u10: 1024 << 6, read back as 65535)
    full = 65535 if r["version"] >= [1, 26] else 65472
    assert r == {"made": [32768, 512], "full": [full, 1023], "off": 0, "version": r["version"]}, r
    assert [v for _t, name, v in rig.plant.log if name == "pwm"] == [32768, full, 0]


def test_pins_made_anew_on_every_read_keep_one_handle_their_level_and_their_irq(run_case):
    """3000 Pin objects for one pin: the link does not grow, reads follow the pin, and the
    IRQ set on the first object counts every edge, as on a board."""
    script = [(105_000 + 10_000 * k, "a", (k + 1) % 2) for k in range(300)]
    script.append((100, "adc", 4321))
    script += [(20_000 + 1_000 * k, "b", (k + 1) % 2) for k in range(10)]
    rig, r = run_case("pins_remade", 3.3, script)
    want = {"edges": 300, "highs_between": True, "reads": 3000, "adc": [4321, 4321, 4321], "last_irq_wins": [0, 10]}
    assert r == want, r
    assert len(rig.wiring.handles) <= 4, [h.key for h in rig.wiring.handles]


def test_pin_reads_inside_a_handler_neither_move_time_nor_repeat_edges(run_case):
    """236 edges of A in one long sleep, each handler reading A and B: 236 calls, not
    more (reads in a handler used to count as the main program's spinning, sync from
    inside the dispatch, and bring stale edges back)."""
    script = [(2_000 + 4_000 * k, "a", (k + 1) % 2) for k in range(236)]
    script += [(4_000 + 4_000 * k, "b", (k + 1) % 2) for k in range(236)]  # B a quarter turn behind
    _, r = run_case("irq_reads", 1.1, script)
    assert r == {"calls": 236, "count": 236}, r


def test_a_thread_safe_flag_set_in_an_irq_wakes_asyncio_at_the_edge(run_case):
    script = [(12_345, "a", 1), (12_500, "a", 0), (150_007, "a", 1), (150_100, "a", 0), (333_333, "a", 1)]
    _, r = run_case("tsf", 0.5, script)
    assert r == {"woke": [12_345, 150_007, 333_333]}, r


def test_a_starved_watchdog_resets_the_board_at_its_timeout(make_rig):
    """Fed every 50 ms, then starved from t = 200 ms: reset at 300 ms, and again 300 ms
    into each new run (the host used to restart it at its own, earlier time)."""
    import json

    from host.tests.conftest import FIRMWARE, shim_app

    rig = make_rig(shim_app(), main_dir=FIRMWARE / "watchdog", trace=True)
    rig.run_for(1.0)
    rig.stop()
    lines = (rig.artefacts / "trace.jsonl").read_text().splitlines()
    resets = [m["t"] for m in map(json.loads, lines[1:]) if m.get("msg") == "EXIT" and m["kind"] == 1]
    assert resets[:3] == [300_000, 600_000, 900_000], f"expected resets every 300 ms; got {resets} ({rig.artefacts})"
    assert rig.resets == len(resets) and "R never" not in rig.console


def test_sleeps_work_under_heap_lock_and_an_error_there_keeps_its_traceback(run_case):
    with pytest.raises(FirmwareError) as err:
        run_case("heap_locked", 1.0)
    assert "R slept_ms 30" in err.value.console, err.value.console
    assert "MemoryError" in str(err.value) and "line 14" in str(err.value), str(err.value)


def test_a_handler_that_sleeps_blocks_the_program_and_later_edges_wait_their_turn(run_case):
    """A debounce that sleeps in its handler, as much public code does: each edge's handler
    runs in order, the second late (at 19 ms, when the first has returned), and the main
    program's sleeps wait for them, as soft IRQs on a board do. The edge at 10 ms comes in
    the last 155 us of a sleep on an ESP32 (ports/esp32/mphalport.c): the main program
    reads the clock (10 ms) before the loop's branch runs the handler. (Time used to jump
    back to the batch's end and the host stopped with a link protocol error.)"""
    script = [(10_000, "button", 0), (10_300, "button", 1), (12_000, "button", 0), (18_500, "button", 1)]
    script += [(30_000, "button", 0), (31_000, "button", 1)]
    _, r = run_case("irq_sleeps", 0.1, script, initial={"button": 1})
    assert r["calls"] == [10_000, 19_000, 30_000], r
    if os.environ.get("HIL_PURE"):  # (a user's own interpreter sees no branches: the handler runs in the
        # clock read itself, docs/shim.md "Where callbacks run", so the main program reads 24 ms, not 10)
        assert r["main"] == [5_000, 24_000, 29_000, 35_000, 40_000, 45_000, 50_000, 55_000], r
        return
    assert r["main"] == [5_000, 10_000, 24_000, 29_000, 35_000, 40_000, 45_000, 50_000], r

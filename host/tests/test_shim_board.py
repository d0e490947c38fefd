"""The shim as a board on a bench: outputs wired to inputs (wire parts on a bench body, the pins
of upstream's esp32 target wiring), the board's identity, and the APIs upstream's
hardware tests use (PWM read back with time_pulse_us, Encoder, Counter, RTC, mem32)."""

import pytest

from host.conformance.inloop import BENCH_LIB, PINS, WIRING, bench_plant
from host.rig.config.app import App, BoardSettings, Code
from host.tests.conftest import FIRMWARE, results

pytestmark = pytest.mark.hil


def bench(board: str) -> App:
    return App(
        name="bench",
        default_board=board,
        make_plant=bench_plant,
        wiring=WIRING,
        code=Code(lib_dirs=(BENCH_LIB,)),
        # (the cases print between the edges they time: the API's timing, not the console's)
        board=BoardSettings(pins=PINS, console_baud=0),
    )


def run(make_rig, case: str, board: str, duration_s: float):
    rig = make_rig(bench(board), main_dir=FIRMWARE / case, allow_exit=True)
    rig.run_for(duration_s)
    rig.stop()
    return rig, results(rig.console)


def test_a_write_is_read_back_through_a_wire_at_the_same_instant(make_rig):
    rig, r = run(make_rig, "loopback", "esp32_bench", 2.0)
    assert r["readback"] == [1, 0, 1, 0], (
        f"expected each write seen at once on the wired input; console:\n{rig.console}"
    )
    assert r["readback_us"] < 50, r["readback_us"]  # four writes and reads, no waiting


def test_pwm_phases_timed_by_time_pulse_us_within_5_us(make_rig):
    rig, r = run(make_rig, "loopback", "esp32_bench", 2.0)
    assert len(r["pwm_err"]) == 10 and max(r["pwm_err"]) <= 5, f"low/high phase errors (us): {r['pwm_err']}"
    assert r["pwm_held_low"] == [-2, 0], "duty 0 holds the line low: no pulse starts"


def test_encoder_counts_in_1_2_and_4_phases_as_upstreams_test_partial_expects(make_rig):
    rig, r = run(make_rig, "loopback", "esp32_bench", 2.0)
    want = [
        (1, 1, 1), (1, 1, 2), (1, 2, 3), (1, 2, 4), (2, 3, 5), (2, 3, 6), (2, 4, 7), (2, 4, 8),
        (2, 4, 7), (1, 2, 4), (0, 0, 0), (0, 0, -1), (0, -1, -2), (0, -1, -3), (-1, -2, -4),
        (-1, -2, -5), (-2, -4, -8), (23, 46, 92), (-2, -4, -8),
    ]  # fmt: skip
    assert [tuple(p) for p in r["encoder"]] == want


def test_counter_counts_edges_up_down_and_falling_even_in_a_burst_of_writes(make_rig):
    """300 toggles at one instant (no time passes between writes) are 600 wire edges: more
    than a STATE holds, so the wire hands them over in parts, none lost."""
    rig, r = run(make_rig, "loopback", "esp32_bench", 2.0)
    assert r["counter"] == [100, 101, 0, 75, 300], r["counter"]
    assert r["after_deinit"] == 300


@pytest.mark.parametrize(
    "board, platform, machine, rp2",
    [
        ("esp32_bench", "esp32", "Generic ESP32 module with ESP32", None),
        ("rpi_pico_bench", "rp2", "Raspberry Pi Pico with RP2040", [2, [0xE001]]),
        ("bench", "linux", None, None),
    ],
)
def test_the_firmware_sees_its_boards_platform_and_runs_as_main(make_rig, board, platform, machine, rp2):
    rig, r = run(make_rig, "board_identity", board, 4.0)
    assert r["platform"] == platform
    if machine:
        assert r["machine"] == machine
    assert r["rp2"] == rp2, "import rp2 works on an rp2 board only"
    assert r["argv"] == "main.py" and r["main_module"] == 42, "the entry file is __main__, named in sys.argv"
    assert r["mem"] == ["0x12345678", 0x56, "<16-bit memory>"] and r["mem_align"] == "ValueError"
    assert r["rtc"][0] == [2024, 3, 1, 4, 0, 0, 1], "the RTC runs on in virtual time (3 s later)"
    assert r["rtc"][1] == (2024, 3, 1, 0, 0, 1), "and time.localtime follows it"


@pytest.mark.parametrize(
    "board, names",
    [("esp32_bench", ["gc", "vfs"]), ("rpi_pico_bench", ["machine", "rp2"]), ("bench", [])],
)
def test_main_finds_the_names_the_ports_boot_left(make_rig, board, names):
    """ports/rp2/modules/_boot.py imports machine and rp2 in __main__ and deletes only vfs,
    bdev and fs; ports/esp32/modules/_boot.py imports gc and vfs and deletes nothing (its
    bdev, a flash partition, is not modelled)."""
    rig, r = run(make_rig, "port_boot_names", board, 0.1)
    assert r["names"] == names, rig.console
    assert ("pin" in r) == ("machine" in names), rig.console


def test_a_uart_sends_at_its_baud_rate_and_fires_irq_rx_for_each_byte(make_rig):
    """9600 baud, 10 bits a byte: 1041.7 us each; flush() returns when the last has left.
    Each byte fires IRQ_RX, whose handler is scheduled (ports/esp32/machine_uart.c:
    ishard = false, mp_irq_handler from uart_event_task); the ESP32's flush blocks in
    ESP-IDF's uart_wait_tx_done (mp_machine_uart_ioctl, MP_STREAM_FLUSH), where no
    scheduled callback runs, so the three handlers run once it has returned, at 3125 us."""
    rig, r = run(make_rig, "loopback", "esp32_bench", 2.0)
    flushed, got = r["uart"]
    assert flushed == 3 * 10 * 1_000_000 // 9600, flushed
    assert got == [(3125, b"a"), (3125, b"b"), (3125, b"c")], got


def test_driver_habits_a_board_forgives_hold_in_the_loop(make_rig):
    """Objects made again are the same peripheral; a PWM made per call reuses its channel
    (it used to leak a handle a call and die); irq().flags() gives the edge; UART.init sets
    the baud the line uses and a timeout makes readline wait; a poll that is ready at once
    lets time move in a loop (it froze it)."""
    rig, r = run(make_rig, "board_habits", "esp32_bench", 3.0)
    assert r["same_pin"] == [True, 0], r
    assert r["pwm_same"] is True and len(rig.wiring.handles) < 20, len(rig.wiring.handles)
    assert r["flags"] == [1, 2, 1, 2], r["flags"]
    same, line, took_us = r["uart"]
    assert same and line == b"0123456789\n" and took_us == 11 * 10 * 1_000_000 // 115200 + 1, r["uart"]
    assert r["counter_again"] == [True, 2] and r["timer_same"] is True, r
    assert r["poll_spin"] == [True, True], r

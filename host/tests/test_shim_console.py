"""The board's habits a user notices (docs/shim.md): print() takes the REPL UART's time
(``[board] console_baud``), and a budget feels it; boot.py and the entry file share
globals; lightsleep()/deepsleep() without a time wait for a wake source; the
ImportErrors of what the loop has not got point at docs/shim.md; a syntax error is one
error naming its file and line."""

import textwrap

import pytest

from host.core.errors import FirmwareError, FirmwareExited
from host.tests.conftest import results

LINE = "line %02d of a chatty loop, fifty lines each period"
LOOP_BYTES = 50 * (len(LINE % 0) + 1)  # 50 lines of 49 characters and a newline

CHATTY = f"""
import time
from machine import Pin

led = Pin(2, Pin.OUT)
t0 = time.ticks_us()
for loop in range(4):
    led.toggle()
    for i in range(50):
        print("{LINE}" % i)
    time.sleep_ms(50)
print("R period_us", time.ticks_diff(time.ticks_us(), t0) // 4)
led.toggle()
"""


def rig_file(folder, main, baud=None, extra="", files=None):
    """A rig folder in ``folder``: main.py, its rig.toml (a bench with the LED on pin 2
    watched as a probe, a 50 ms period budget on it) and any other files."""
    (folder / "main.py").write_text(textwrap.dedent(main))
    for name, text in (files or {}).items():
        (folder / name).write_text(textwrap.dedent(text))
    board = f"[board]\nconsole_baud = {baud}\n" if baud is not None else ""
    (folder / "rig.toml").write_text(
        f'name = "habits"\n[firmware]\nallow_exit = true\n{extra}{board}[board.pins]\nLED = 2\n'
        '[plant]\nbody = "bench"\n[wiring]\nLED = "probe:led"\n'
        '[budgets.blink]\nkind = "period"\nsource = "probe:led"\nperiod_us = 50_000\ntolerance_us = 1_000\n'
    )
    return str(folder / "rig.toml")


@pytest.mark.parametrize(
    ("baud", "period_us"),
    [
        (None, 50_000 + (LOOP_BYTES - 128) * 10_000_000 // 115_200),  # 115200 baud (the default), 128-byte FIFO
        (0, 50_000),
    ],
)
def test_printing_takes_the_uarts_time_at_its_baud_rate(make_rig, tmp_path, baud, period_us):
    rig = make_rig(rig_file(tmp_path, CHATTY, baud))
    rig.run_for(2)
    rig.stop()
    assert results(rig.console)["period_us"] == pytest.approx(period_us, abs=2)
    lines = [ln for ln in rig.console.splitlines() if ln.startswith("line ")]
    assert len(lines) == 200 and lines[49] == LINE % 49  # the console's text is as printed


def test_a_budget_the_firmware_holds_silent_feels_its_printing(make_rig, tmp_path):
    (tmp_path / "quiet").mkdir()
    (tmp_path / "chatty").mkdir()
    quiet = make_rig(rig_file(tmp_path / "quiet", CHATTY, 0))
    quiet.run_for(2)
    quiet.stop()
    quiet.budgets["blink"].check()
    chatty = make_rig(rig_file(tmp_path / "chatty", CHATTY))
    chatty.run_for(2)
    chatty.stop()
    with pytest.raises(AssertionError, match="budget blink"):
        chatty.budgets["blink"].check()


def test_a_short_line_a_period_fits_the_fifo_and_costs_nothing(make_rig, tmp_path):
    main = """
    import time
    t0 = time.ticks_us()
    for loop in range(10):
        print("tick", loop, "of a loop printing one line")
        time.sleep_ms(50)
    print("R period_us", time.ticks_diff(time.ticks_us(), t0) // 10)
    """
    rig = make_rig(rig_file(tmp_path, main))
    rig.run_for(1)
    rig.stop()
    assert results(rig.console)["period_us"] == 50_000


def test_boot_py_and_the_entry_file_share_their_globals(make_rig, tmp_path):
    boot = "import time\nCONFIG = {'speed': 3}\n"
    main = "print('R speed', CONFIG['speed'])\nprint('R time', time.ticks_ms() is not None)\n"
    rig = make_rig(rig_file(tmp_path, main, files={"boot.py": boot}))
    rig.run_for(0.1)
    rig.stop()
    assert results(rig.console) == {"speed": 3, "time": True}


LIGHTSLEEP = """
import time
from machine import Pin, Timer, lightsleep

woken = []
t0 = time.ticks_ms()
Timer(0).init(mode=Timer.ONE_SHOT, period=300, callback=lambda t: woken.append("timer"))
lightsleep()
print("R after_timer_ms", time.ticks_diff(time.ticks_ms(), t0))
print("R woken", woken)
"""


def test_lightsleep_without_a_time_sleeps_until_a_timer_wakes_it(make_rig, tmp_path):
    rig = make_rig(rig_file(tmp_path, LIGHTSLEEP))
    rig.run_for(1)
    rig.stop()
    assert results(rig.console) == {"after_timer_ms": 300, "woken": ["timer"]}


def test_lightsleep_and_deepsleep_without_a_wake_source_sleep_on(make_rig, tmp_path):
    (tmp_path / "light").mkdir()
    (tmp_path / "deep").mkdir()
    for kind in ("light", "deep"):
        main = f"import machine\nprint('R asleep', 1)\nmachine.{kind}sleep()\nprint('R woke', 1)\n"
        rig = make_rig(rig_file(tmp_path / kind, main))
        rig.run_for(5)
        rig.stop()
        assert results(rig.console) == {"asleep": 1}, kind
        assert rig.resets == 0


def test_deepsleep_wakes_through_a_reset_and_a_sleepy_node_is_no_reboot_storm(make_rig, tmp_path):
    main = "import machine, time\nprint('R boot', time.ticks_ms())\nmachine.deepsleep(2000)\n"
    rig = make_rig(rig_file(tmp_path, main))
    rig.run_for(30)  # 15 wakes, each 2 s after the last: a storm's rate, by design
    rig.stop()
    assert rig.resets == 15


def test_a_run_that_ends_by_design_is_a_rig_setting(make_rig, tmp_path):
    main = "print('R done', 1)\n"
    (tmp_path / "main.py").write_text(main)
    rig = make_rig(rig_file(tmp_path, main))  # [firmware] allow_exit = true
    rig.run_for(1)
    rig.stop()
    assert results(rig.console) == {"done": 1}
    text = (tmp_path / "rig.toml").read_text().replace("allow_exit = true\n", "")
    (tmp_path / "rig.toml").write_text(text)
    with pytest.raises(FirmwareExited):
        make_rig(str(tmp_path / "rig.toml")).run_for(1)


@pytest.mark.parametrize(
    ("main", "expected"),
    [
        ("import rp2\n", r'set \[board\] family = "rpi_pico"'),
        ("import esp\n", r"no module named 'esp': the loop has it for an ESP32 board only"),
        ("from machine import I2S\n", r"machine.I2S is not in the loop; it has Pin, .*\(docs/shim.md\)"),
        ("import machine\nmachine.CAN(1)\n", r"machine.CAN is not in the loop; .*\(docs/shim.md\)"),
        ("import network\n", r"network is the radio's: the loop has it on a board with one, .*; this board has none"),
        ("import bluetooth\n", r"bluetooth is built into a board's MicroPython and not into the loop: docs/shim.md"),
    ],
)
def test_what_the_loop_has_not_got_says_so_and_points_at_docs_shim(make_rig, tmp_path, main, expected):
    rig = make_rig(rig_file(tmp_path, main))
    with pytest.raises(FirmwareError, match=expected):
        rig.run_for(1)


def test_a_syntax_error_is_one_error_naming_its_file_and_line(make_rig, tmp_path):
    rig = make_rig(rig_file(tmp_path, "import time\n\nwhile True\n    time.sleep_ms(1)\n"))
    with pytest.raises(FirmwareError) as caught:
        rig.run_for(1)
    message = str(caught.value)
    assert message.startswith(f"syntax error in {tmp_path / 'main.py'}, line 3: invalid syntax")
    assert "expected it to keep running" not in message
    assert message.count("SyntaxError") <= 1  # the traceback once (the console's), not twice


def test_mpy_fil_run_allow_exit_runs_a_firmware_that_ends_by_design(tmp_path, capsys):
    from host.cli import main

    rig = rig_file(tmp_path, "print('done')\n")
    (tmp_path / "rig.toml").write_text((tmp_path / "rig.toml").read_text().replace("allow_exit = true\n", ""))
    out = ["--duration", "1", "--no-plots", "--out"]
    assert main(["run", rig, *out, str(tmp_path / "build" / "ended")]) == 1  # (not in the firmware folder: its build/)
    assert "FirmwareExited" in capsys.readouterr().err
    assert main(["run", rig, "--allow-exit", *out, str(tmp_path / "build" / "allowed")]) == 0
    assert "done" in (tmp_path / "build" / "allowed" / "console.log").read_text()


@pytest.mark.parametrize("baud", ["5", "-1", "'fast'", "true", "20_000_000"])
def test_a_bad_console_baud_is_named(tmp_path, baud):
    from host.core.errors import ConfigError
    from host.rig.config.rigfile import load_rig

    with pytest.raises(ConfigError, match=r"\[board\] console_baud: expected"):
        load_rig(rig_file(tmp_path, "print('hi')\n", baud=baud))

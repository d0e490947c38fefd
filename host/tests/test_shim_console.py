"""The board's habits a user notices (docs/shim.md): print() takes the REPL UART's time
(``[board] console_baud``), and a budget feels it; boot.py and the entry file share
globals; lightsleep()/deepsleep() without a time wait for a wake source; the
ImportErrors of what the loop has not got point at docs/shim.md; a syntax error is one
error naming its file and line."""

import textwrap

import pytest

from host.core.errors import FirmwareError
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

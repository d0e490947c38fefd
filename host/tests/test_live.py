"""A rig driven call by call (docs/live.md): the page's notebook runs as written, the
journal replays to the same trace, bad calls are refused before anything runs, and the
firmware looked at in a pause neither moves time nor drives the board."""

import re
from pathlib import Path

import pytest

from host.core.errors import ConfigError
from host.live import LiveRig
from host.rig.loop.introspect import FirmwareEvalError
from host.rig.loop.waits import ExpectTimeout

REPO = Path(__file__).resolve().parents[2]
PAGE = REPO / "docs" / "live.md"
PICO = str(REPO / "examples" / "pico_bot" / "rig.toml")


def python_blocks(page: Path) -> list[str]:
    return re.findall(r"^```python\n(.*?)^```$", page.read_text(), flags=re.S | re.M)


def test_the_live_page_runs_as_a_notebook(monkeypatch):
    monkeypatch.chdir(REPO)
    blocks = python_blocks(PAGE)
    assert len(blocks) >= 8, "docs/live.md: expected its walk-through's Python blocks"
    namespace: dict = {}
    for i, block in enumerate(blocks):
        try:
            exec(compile(block, f"docs/live.md block {i + 1}", "exec"), namespace)
        except BaseException as e:
            rig = namespace.get("rig")
            where = f"\nconsole:\n{rig.console(lines=10)}" if rig is not None and rig.rig is not None else ""
            raise AssertionError(f"docs/live.md block {i + 1} failed: {type(e).__name__}: {e}\n{block}{where}") from e
    assert namespace["rig"].rig.exit_kind is None and not namespace["rig"].rig.target.alive(), "the page stops its rig"


@pytest.fixture
def pico():
    with LiveRig.start(PICO, seed=3) as rig:
        yield rig


def test_a_restored_snapshot_forgets_what_came_after_and_replays_lines_run_in_the_firmware(pico):
    pico.run_until(console="press start")
    pico.exec("marker = [1]")
    snap = pico.snapshot()
    pico.exec("marker.append(2)")
    pico.step(300_000)
    pico.restore(snap)
    assert pico.eval("marker") == [1], "expected the firmware as it was at the snapshot"
    assert pico.t_us == snap.t_us and pico.trace_digest == snap.trace_digest
    pico.exec("marker.append(3)")
    assert pico.eval("marker") == [1, 3]


def test_a_line_that_raises_is_the_firmwares_error_and_the_run_goes_on(pico):
    pico.run_until(t_s=0.05)
    with pytest.raises(FirmwareEvalError, match=r"ZeroDivisionError"):
        pico.eval("1 / 0")
    with pytest.raises(FirmwareEvalError, match=r"cannot drive the board or wait \(it tried to send OUT\)"):
        pico.exec("led.value(1 - led.value())")
    assert pico.t_us == 50_000
    pico.press("start", ms=100)
    pico.run_until(console="go", timeout_s=1)


def test_bad_calls_are_refused_before_the_rig_runs(pico):
    with pytest.raises(ConfigError, match="expected one of t_s, t_us, console, pin"):
        pico.run_until(t_s=1, console="x")
    with pytest.raises(ConfigError, match="acts from the run's start"):
        pico.inject({"kind": "link_stall", "rate": 0.1})
    pico.step(200_000)
    with pytest.raises(ConfigError, match="before now"):
        pico.inject({"kind": "stuck", "signal": "start.out", "value": 0, "start_s": 0.1})
    with pytest.raises(ConfigError, match="no output 'nothing.out'"):
        pico.inject({"kind": "stuck", "signal": "nothing.out", "value": 0})
    with pytest.raises(ValueError, match="pressed"):
        pico.set("start", "held", 1)
    assert pico.t_us == 200_000 and len(pico.entries) == 1


def test_a_pin_wait_that_never_comes_says_so_in_simulated_time(pico):
    with pytest.raises(ExpectTimeout, match="GP25 at level 1"):
        pico.run_until(pin="GP25", level=1, timeout_s=0.2)  # (the LED toggles only once started)
    assert pico.t_us == 200_000


def test_a_fault_injected_now_acts_from_now(pico):
    pico.run_until(t_s=0.3)
    assert "pico_bot: go" not in pico.console(), "it started before the fault"
    pico.inject({"kind": "stuck", "signal": "start.out", "value": 0})  # the button reads pressed
    pico.run_until(console="go", timeout_s=0.1)
    assert 300_000 <= pico.t_us <= 320_000, f"expected the start within 20 ms of the fault, at {pico.t_us} us"


def test_nothing_of_a_live_rig_is_left_behind_once_stopped(pico):
    pico.run_until(t_s=0.1)
    proc = pico.rig.target.proc
    pico.stop()
    assert proc.poll() is not None, f"expected the firmware's process {proc.pid} ended once the live rig stopped"


SCENARIOS = REPO / "host" / "tests" / "wokwi_scenarios"


@pytest.mark.parametrize("cpu", ["free", "rp2040@125MHz"])
def test_reading_the_paused_firmware_leaves_the_run_as_it_was(monkeypatch, cpu):
    """The same course with and without evals between its stops: the same link trace, with
    MCU time too (the line's compute and its clock reads are not the board's). (A line that
    adds to the firmware's heap, a new global, changes what its collections cost later
    with MCU time, as the same line in its code would: only without MCU time here.)"""
    monkeypatch.setenv("MPYFIL_CPU", cpu)

    def course(look: bool) -> str:
        with LiveRig.start(PICO, seed=4) as rig:
            for t_s in (0.02, 0.05, 0.3, 1.2, 1.25, 1.5):
                rig.run_until(t_s=t_s)
                if look:
                    assert rig.eval("enc_l.count + enc_r.count") >= 0 and rig.eval("LOOP_MS") == 50
                    assert rig.eval("sum([i * i for i in range(500)])") == 41541750
                    assert rig.eval("time.ticks_us()") == rig.eval("time.ticks_us()"), "a read moved the clock"
                    if cpu == "free":
                        rig.exec("looked = 1")
            return rig.trace_digest

    assert course(look=True) == course(look=False)


def test_bytes_typed_on_the_console_reach_input_and_replay_from_a_snapshot():
    with LiveRig.start(str(SCENARIOS / "serial_echo" / "rig.toml")) as rig:
        rig.run_until(console="ready")
        snap = rig.snapshot()
        rig.uart_write("on\n")
        rig.run_until(console="ok on", timeout_s=0.5)
        assert rig.pin("GP25") == 1, "expected the LED on after the line 'on'"
        after = rig.snapshot()
        rig.restore(snap)
        assert rig.pin("GP25") == 0 and "ok on" not in rig.console(), "expected the run before the line"
        rig.uart_write("on\n")
        rig.run_until(console="ok on", timeout_s=0.5)
        assert rig.pin("GP25") == 1 and rig.t_us == after.t_us and rig.trace_digest == after.trace_digest


def test_the_bus_log_holds_each_transaction_with_its_decoded_text():
    with LiveRig.start(str(SCENARIOS / "mpu6050" / "rig.toml")) as rig:
        rig.run_until(console="temp: 25.0 C")
        log = rig.bus_log()
        t_set = rig.t_us
        rig.set("imu1", "accelX", 0.5)
        rig.run_until(console="accel: 0.50", timeout_s=0.5)
        later = [tx for tx in rig.bus_log(since_us=t_set) if tx["register"] == 0x3B]
    assert log[0]["address"] == 0x68 and log[0]["register"] == 0x6B and log[0]["wrote"] == "6b00", log[0]
    reads = [tx for tx in log if tx["register"] == 0x3B]
    assert reads and len(reads[0]["read"]) == 28 and "0x68" in reads[0]["text"], reads[:1]
    assert later and later[0]["t_us"] >= t_set and later[0]["read"].startswith("2000"), later[:1]  # 0.5 g: 8192


def test_mpy_fil_run_breaks_at_a_console_line_into_a_prompt_and_goes_on(monkeypatch, capsys, tmp_path):
    from host.cli import main

    typed = iter(["eval LOOP_MS", "press start 100", "until go", "exec CRUISE", "pins", "nonsense", "c"])
    monkeypatch.setattr("builtins.input", lambda prompt: next(typed))
    out = tmp_path / "run"
    assert main(["run", PICO, "--duration", "1.5", "--break-at", "press start", "--out", str(out), "--no-plots"]) == 0
    shown = capsys.readouterr().out
    assert "paused at virtual t=0.010000 s (--break-at 'press start'" in shown, shown
    assert "\n50\n" in shown and "'go'" in shown and "\n0.6\n" in shown, shown
    assert 'BUTTON: {"kind": "pin", "key": "13", "signal": "start.out", "mode": "in", "pull": "up", "level": ' in shown
    assert "no command 'nonsense'" in shown and "ground truth at 1.5 s" in shown, shown
    assert (out / "trace.jsonl").is_file() and "pico_bot: go" in (out / "console.log").read_text()


def test_ctrl_c_pauses_an_interactive_run_instead_of_stopping_it(tmp_path):
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "run"
    command = [sys.executable, "-m", "host.cli", "run", PICO, "--interactive", "--duration", "3600"]
    proc = subprocess.Popen(
        [*command, "--out", str(out), "--no-plots"],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        stderr=subprocess.STDOUT,
        text=True,
        cwd=REPO,
    )
    try:
        assert proc.stdout.readline().startswith("running to t=3600 s"), "expected the run's first line"
        time.sleep(0.3)
        proc.send_signal(signal.SIGINT)
        shown, _ = proc.communicate("eval LOOP_MS\nq\n", timeout=60)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 0, shown
    assert "(Ctrl-C); `help` lists the commands" in shown, shown
    assert "mpy-fil> 50\n" in shown and "ground truth at" in shown, shown


def test_a_battery_set_low_reads_low_at_once_and_drains_on_from_there_across_a_restore():
    """The battery's ``voltage`` control (sim_plant/catalogue/battery.py), as a live rig sets it."""
    from sim_plant.catalogue.assembly import assemble
    from sim_plant.plant import Change
    from sim_plant.sonars import Adc

    plant = assemble({"body": "bench", "parts": [{"kind": "battery", "name": "bat", "drain_v_per_s": 0.1}]})
    plant.reset(0)
    plant.advance_to(1_000_000)
    before = plant.snapshot()
    plant.set_control("bat", "voltage", 6.5)
    low_u16 = Adc(12, 3.3).u16(6.5 / 3)
    assert plant.advance_to(1_000_001) == [Change(1_000_000, "bat.adc", low_u16)], "expected the ADC at once"
    plant.advance_to(2_000_000)
    assert plant.truth()["bat_v"] == pytest.approx(6.4), "expected 6.5 V set at 1 s, drained 0.1 V/s since"
    plant.restore(before)  # (a speculative batch rewound past the set: the set comes again)
    plant.advance_to(2_000_000)
    assert plant.truth()["bat_v"] == pytest.approx(6.4)


def test_a_line_run_in_the_paused_firmware_is_confined_to_the_board_as_the_firmware_is(pico):
    pico.run_until(t_s=0.02)
    with pytest.raises(FirmwareEvalError, match="ImportError: no module named 'socket'"):
        pico.exec("import socket")
    with pytest.raises(FirmwareEvalError, match="AttributeError"):
        pico.exec("import os; os.system('true')")
    with pytest.raises(FirmwareEvalError, match="OSError"):
        pico.eval("open('/etc/passwd').read()")

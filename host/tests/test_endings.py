"""Every way a firmware can end or stall ends the run in seconds with a message that
names it; every bad input is a harness error naming the field (docs/reliability.md)."""

import gc
import math
import os
import signal
import time

import pytest

from host.artefacts.console import stamped_lines
from host.core.errors import ConfigError, FirmwareError, FirmwareExited, SetupError
from host.rig.loop.rig import Rig
from host.rig.loop.spec import RigSpec
from host.tests.conftest import FIRMWARE, our_ptys, shim_app

BENCH = '[plant]\nbody = "bench"\n[[plant.parts]]\nkind = "wire"\nname = "w0"\n[wiring]\nLED = "w0.in"\n'

pytestmark = pytest.mark.hil


def rig_for(make_rig, case, **kw):
    return make_rig(shim_app(), main_dir=FIRMWARE / case, **kw)


def test_an_exit_fails_the_run_with_its_code_unless_the_test_expects_it(make_rig):
    with pytest.raises(FirmwareExited, match=r"sys\.exit\(3\), exit code 3") as err:
        rig_for(make_rig, "exits").run_for(1)
    assert err.value.code == 3 and "done early" in str(err.value)
    with pytest.raises(FirmwareExited, match="entry file returned"):
        rig_for(make_rig, "returns").run_for(1)
    rig = rig_for(make_rig, "exits", allow_exit=True)
    rig.run_for(1)
    assert rig.exit_code == 3 and rig.t_us == 1_000_000, "an expected end: the plant runs on"


def test_a_task_that_dies_unretrieved_fails_the_run(make_rig):
    with pytest.raises(FirmwareError, match="sensor task died") as err:
        rig_for(make_rig, "task_dies").run_for(2)
    assert "virtual t=0.120000" in str(err.value) and "Task exception wasn't retrieved" in err.value.console


def test_a_long_traceback_keeps_its_last_line(make_rig):
    with pytest.raises(FirmwareError) as err:
        rig_for(make_rig, "long_traceback").run_for(1)
    traceback = err.value.traceback.rstrip()
    assert len(traceback) > 3000 and traceback.endswith("ValueError: the bottom of the chain"), traceback[-300:]


def test_a_killed_firmware_process_is_noticed_at_once(make_rig):
    rig = make_rig("rover", seed=1, watchdog_s=5.0)
    rig.run_for(0.5)
    os.kill(rig.target.proc.pid, signal.SIGKILL)
    start = time.monotonic()
    with pytest.raises(FirmwareError, match="exit code -9"):
        rig.run_for(5)
    assert time.monotonic() - start < 1.0, "not after the 5 s watchdog"


def test_an_interpreter_that_is_not_one_is_named_at_once(monkeypatch, tmp_path):
    script = tmp_path / "micropython"
    script.write_text("echo hello\n")  # no shebang: the kernel will not run it
    script.chmod(0o755)
    monkeypatch.setenv("MICROPYTHON", str(script))
    gc.collect()  # (an earlier test's objects closing their files meanwhile would not count)
    fds = our_ptys()
    for _ in range(3):
        with pytest.raises(SetupError, match="cannot start the interpreter .*Exec format error"):
            Rig(RigSpec("rover")).start()
    assert our_ptys() == fds, f"a failed start leaves no pty open: expected {fds}, got {our_ptys()}"
    monkeypatch.setenv("MICROPYTHON", "/bin/true")  # a program that ends at once
    start = time.monotonic()
    with pytest.raises(FirmwareError, match="exit code 0"):
        Rig(RigSpec("rover")).start()
    assert time.monotonic() - start < 2.0


def test_a_run_without_a_seed_draws_one_records_it_and_names_it_when_it_fails(make_rig):
    rig = rig_for(make_rig, "exits", seed=None)
    assert 0 <= rig.seed < 2**32
    with pytest.raises(FirmwareExited, match=f"seed: {rig.seed}"):
        rig.run_for(1)


@pytest.mark.parametrize("seed", [-1, "abc", 2**32, True, 1.5])
def test_a_bad_seed_is_named(seed):
    with pytest.raises(ConfigError, match=r"seed: expected an integer 0\.\.4294967295"):
        RigSpec("rover", seed=seed)


@pytest.mark.parametrize("duration", [math.nan, math.inf, -1, "10", None, 1e300])
def test_a_bad_duration_is_named(make_rig, duration):
    rig = make_rig("rover", seed=1)
    with pytest.raises(ConfigError, match="run_for: expected a number of seconds >= 0"):
        rig.run_for(duration)


@pytest.mark.parametrize("watchdog", [math.nan, 0, -1, "5"])
def test_a_bad_watchdog_is_named(watchdog):
    with pytest.raises(ConfigError, match="watchdog_s: expected a number of seconds > 0"):
        RigSpec("rover", watchdog_s=watchdog)


def test_a_chatty_console_streams_to_its_file_with_a_bounded_tail_in_memory(make_rig):
    ticks = [(100_000 * k, "button", k % 2) for k in range(1, 30)]  # the plant moves: the host keeps up
    # (free printing: at 115 200 baud 2 s carry 23 kB, and this is about 2 MB)
    rig = make_rig(shim_app(ticks, console_baud=0), main_dir=FIRMWARE / "chatty")
    rig.run_for(2.0)
    rig.stop()
    size = (rig.artefacts / "console.log").stat().st_size
    assert size >= 2000 * 1024, f"expected about 2 MB of console in {rig.artefacts / 'console.log'}, got {size}"
    assert len(rig.console) <= 256 * 1024 and rig.console.endswith("x" * 1023 + "\n"), len(rig.console)
    lines = (rig.artefacts / "console.log").read_bytes().splitlines(keepends=True)
    stamp = len(b"[   0.000000] ")
    assert rig.console_log.total_bytes == size - stamp * len(lines), "each line in the file has its stamp"


def test_a_callback_that_raises_ends_the_run_naming_the_callback(make_rig):
    with pytest.raises(FirmwareError, match=r"the callback tick raised ValueError: bad reading") as err:
        rig_for(make_rig, "callback_raises").run_for(1)
    assert "virtual t=0.100000" in str(err.value) and "in tick" in err.value.console


def test_a_scheduled_job_that_raises_at_a_branch_ends_the_run_naming_it(make_rig):
    """The job runs at the spin loop's branch (docs/shim.md, "Where callbacks run"), with
    no call into the shim to run it: its error ends the run there, not a hang."""
    with pytest.raises(FirmwareError, match=r"the callback job raised ValueError: job 7 failed") as err:
        rig_for(make_rig, "scheduled_raises").run_for(1)
    assert "virtual t=0.000000" in str(err.value) and "in job" in err.value.console, err.value.console


def test_the_board_family_of_a_rig_files_own_pins_gives_sys_platform(make_rig, tmp_path):
    folder = tmp_path / "bot"
    folder.mkdir()
    (folder / "main.py").write_text("import sys, os\nprint('R', repr(sys.platform), repr(os.uname().machine))\n")
    (folder / "rig.toml").write_text('[board]\nfamily = "rpi_pico"\n[board.pins]\nLED = 25\n' + BENCH)
    rig = make_rig(str(folder / "rig.toml"), allow_exit=True)
    rig.run_for(0.1)
    rig.stop()
    assert "R 'rp2' 'Raspberry Pi Pico with RP2040'" in rig.console, rig.console


def test_expect_waits_in_virtual_time_for_console_lines_in_order(make_rig):
    rig = make_rig("rover", seed=1)
    first = rig.expect(r"control every (\d+) ms", timeout_s=1)
    assert first.group(1) == "50"
    with pytest.raises(AssertionError, match=r"expected the console to match 'control every' within 0.5 simulated s"):
        rig.expect("control every", timeout_s=0.5)  # said once, and already taken
    assert rig.t_us >= 500_000


def test_run_until_a_predicate_returns_its_value_or_fails_naming_it(make_rig):
    rig = make_rig("rover", seed=1)

    def moved_half_a_metre():
        return rig.truth()["x_m"] - x0 > 0.5 and rig.t_us

    x0 = rig.truth()["x_m"]
    t = rig.run_until(moved_half_a_metre, timeout_s=10)
    assert 1_000_000 < t < 10_000_000
    with pytest.raises(AssertionError, match="expected never to become true within 0.2 simulated s"):
        rig.run_until(never, timeout_s=0.2)


def never():
    return False


def test_the_trace_says_which_firmware_files_ran(make_rig, tmp_path):
    import json
    import shutil

    rig = make_rig("rover", seed=1, trace=True)
    rig.run_for(0.2)
    rig.stop()
    header = json.loads((rig.artefacts / "trace.jsonl").read_text().splitlines()[0])["header"]
    ours = header["firmware"]
    assert ours["folder"].endswith("firmware/apps/rover") and ours["files"] > 3 and len(ours["sha256"]) == 16
    copy = tmp_path / "rover"
    shutil.copytree(ours["folder"], copy)
    (copy / "main.py").write_text((copy / "main.py").read_text() + "\n# changed\n")
    changed = make_rig("rover", seed=1, main_dir=copy, trace=True)
    assert changed.firmware.identity()["sha256"] != ours["sha256"], "a changed file changes the hash"


def test_firmware_lists_files_with_their_sizes_as_on_a_boards_vfs(make_rig, tmp_path):
    folder = tmp_path / "bot"
    folder.mkdir()
    (folder / "main.py").write_text(
        "import os\nfor name, kind, inode, size in os.ilistdir():\n    print('F', name, kind, size)\n"
    )
    (folder / "data").mkdir()
    (folder / "rig.toml").write_text('[board]\nfamily = "esp32"\n[board.pins]\nLED = 2\n' + BENCH)
    rig = make_rig(str(folder / "rig.toml"), allow_exit=True)
    rig.run_for(0.1)
    rig.stop()
    main_size = (folder / "main.py").stat().st_size
    assert f"F main.py 32768 {main_size}" in rig.console and "F data 16384 0" in rig.console, rig.console


def test_console_log_lines_carry_the_virtual_time_they_were_printed_at(make_rig, tmp_path):
    """A bench of wires never changes an input by itself, so the shim could sleep through
    the whole run alone; a print() still sends its next wait to the host, so the log
    knows when each line was printed. The console in memory stays as printed."""
    folder = tmp_path / "bot"
    folder.mkdir()
    (folder / "main.py").write_text(
        "import time\nprint('boot')\nfor i in range(3):\n    time.sleep_ms(250)\n"
        "    print('tick', i, end='')\n    time.sleep_ms(10)\n    print(' done')\n"
    )
    (folder / "rig.toml").write_text('[board]\nfamily = "esp32"\n[board.pins]\nLED = 2\n' + BENCH)
    rig = make_rig(str(folder / "rig.toml"), allow_exit=True)
    rig.run_for(1.0)
    rig.stop()
    assert rig.console == "boot\n" + "".join(f"tick {i} done\n" for i in range(3)), rig.console
    lines = list(stamped_lines(rig.artefacts / "console.log"))
    expected = [(0, "boot"), (250_000, "tick 0 done"), (510_000, "tick 1 done"), (770_000, "tick 2 done")]
    assert lines == expected, f"expected {expected} in {rig.artefacts / 'console.log'}, got {lines}"
    first = (rig.artefacts / "console.log").read_text().splitlines()[0]
    assert first == "[   0.000000] boot", first

"""make flash: compiled with mpy-cross, copied with mpremote, tested on a virtual board."""

import shutil
import signal
import subprocess
import sys
import threading
import time

import pytest

from host.core.errors import HarnessError
from host.core.paths import REPO
from host.device import flash, vboard
from host.rig.config.app import Code
from host.rig.config.apps import App, apps

pytestmark = pytest.mark.hil
BOARD = "esp32_devkitc"


@pytest.fixture
def board_port(tmp_path):
    home = tmp_path / "vboard"
    port = vboard.start_background(BOARD, home=home)
    yield port, home
    vboard.stop_background(BOARD, home)


def mpremote(port, *args, timeout=60):
    return subprocess.run(
        [str(flash.VENV_BIN / "mpremote"), "connect", port, *args], capture_output=True, text=True, timeout=timeout
    )


def test_flash_copies_compiled_firmware_runs_main_and_copies_nothing_the_second_time(board_port):
    port, home = board_port
    lines = []
    first = flash.flash("rover", BOARD, port, wait_s=2.0, log=lines.append)
    assert "main.py" in first["copied"] and "lib/encoder.mpy" in first["copied"], first
    assert sorted((home / "fs").rglob("*.mpy")), "compiled modules on the board"
    assert not (home / "fs" / "rover_control.py").exists()
    assert first["first_lines"][:1] == ["rover on esp32-devkitc control every 50 ms"], first["first_lines"]
    listing = mpremote(port, "ls", ":")
    assert listing.returncode == 0, listing
    sizes = {line.split()[1]: int(line.split()[0]) for line in listing.stdout.splitlines()[1:]}
    main_size = (home / "fs" / "main.py").stat().st_size
    assert sizes.get("main.py") == main_size and sizes.get("lib/") == 0, (
        f"expected mpremote ls to show main.py's {main_size} bytes, as a board's VFS does; got {listing.stdout!r}"
    )
    second = flash.flash("rover", BOARD, port, wait_s=1.0, log=lines.append)
    assert second["copied"] == [] and len(second["unchanged"]) == len(first["copied"]), second


def test_syntax_error_fails_the_flash_with_file_and_line(tmp_path, monkeypatch):
    app = tmp_path / "broken"
    app.mkdir()
    (app / "main.py").write_text("import helper\n")
    (app / "helper.py").write_text("x = 1\n\ndef f(:\n    pass\n")
    monkeypatch.setitem(apps(), "broken", App("broken", BOARD, make_plant=None, wiring={}, code=Code(folder=app)))
    with pytest.raises(HarnessError, match=r"helper\.py:3: SyntaxError"):
        flash.stage("broken", BOARD)


@pytest.mark.parametrize("port", ["/dev/ttyNOPE9", str(REPO / "README.md")])
def test_missing_or_wrong_port_gives_one_line_naming_it(port):
    out = subprocess.run(
        [sys.executable, "-m", "host.device.flash", "--app", "rover", "--port", port],
        capture_output=True,
        text=True,
        timeout=60,
        cwd=REPO,
    )
    assert out.returncode == 2, out
    err = out.stderr.strip().splitlines()
    assert len(err) == 1 and f"PORT={port}" in err[0], out.stderr


def test_ctrl_c_during_a_flash_leaves_the_board_usable(board_port, tmp_path):
    port, home = board_port
    cmd = [sys.executable, "-m", "host.device.flash", "--app", "rover", "--port", port, "--wait", "1"]
    proc = subprocess.Popen(cmd, cwd=REPO, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    out = ""
    deadline = time.monotonic() + 30
    while "compiled" not in out and time.monotonic() < deadline:  # it is copying now
        out += proc.stdout.readline()
    proc.send_signal(signal.SIGINT)
    rest, _ = proc.communicate(timeout=30)
    assert proc.returncode in (130, 0), out + rest
    answer = mpremote(port, "exec", "print(40 + 2)")
    assert answer.returncode == 0 and "42" in answer.stdout, answer
    again = flash.flash("rover", BOARD, port, wait_s=1.0, log=lambda _: None)
    assert again["first_lines"][:1] == ["rover on esp32-devkitc control every 50 ms"]


def test_a_board_slower_to_print_than_the_wait_still_shows_its_first_line(board_port):
    """A loaded host (or a slow boot.py) can take longer than ``--wait`` to reach main.py's
    first print: the flash waits for one whole line rather than showing none."""
    port, home = board_port
    (home / "fs" / "main.py").write_text("import time\ntime.sleep(1.5)\nprint('late hello')\n")
    t0 = time.monotonic()
    lines = flash.reset_and_read(port, 3, wait_s=0.3)
    assert lines[:1] == ["late hello"], f"expected main.py's line after its 1.5 s sleep; got {lines}"
    assert time.monotonic() - t0 < flash.FIRST_LINE_S, "it stopped waiting once the line came"


def test_hil_scenario_runs_from_the_flashed_files(board_port, make_rig):
    port, home = board_port
    flash.flash("rover", BOARD, port, wait_s=1.0, log=lambda _: None)
    fs = home / "fs"
    assert (fs / "rover_control.mpy").exists() and not (fs / "rover_control.py").exists()
    rig = make_rig("rover", firmware_dir=fs, board=BOARD, seed=1)
    rig.run_for(5)
    assert rig.truth()["x_m"] > 1.5, "the flashed firmware drove the rover"
    rig.budgets["control.period"].check()
    assert rig.firmware_folders == [fs, fs / "lib"]


def test_a_virtual_board_knows_a_link_session_by_its_frames_not_by_stray_bytes():
    """Ctrl-C from the port is data during a plant-link session. The session starts at a
    HELLO frame and ends at an EXIT frame, even when a read splits a frame, and the
    bytes of those markers inside other frames' payloads change nothing."""
    from host.shim import _hilframe as F

    con = vboard._Console()
    try:
        hello = F.encode(F.HELLO, 0, b"\x01\x00" + b"1.25.0;linux")
        con.from_interpreter(b"rover on esp32-devkitc\r\n" + hello[:1])
        assert not con.link_session
        con.from_interpreter(hello[1:])
        assert con.link_session, "a HELLO split across two reads starts the session"
        stray = F.encode(F.WAIT, 1, bytes((F.SOF, F.EXIT)) * 4)
        con.from_interpreter(stray)
        assert con.link_session, "an EXIT marker inside a WAIT payload must not end the session"
        con.from_interpreter(F.encode(F.EXIT, 2, b"\x00" * 13) + b"\r\n>>> ")
        assert not con.link_session and con.prompt
    finally:
        con.client.close()
        con.repl.close()


def test_a_board_without_the_apps_pins_is_named_at_once(capsys):
    from host.device import flash as flash_cli

    assert flash_cli.main(["--app", "pool_cleaner", "--board", "rpi_pico"]) == 2
    err = capsys.readouterr().err
    assert "stopped as it started: wiring: board rpi_pico has no pin named BUMPER_FRONT" in err, err


def test_a_board_running_its_own_firmware_enters_the_raw_repl_after_each_soft_reset(tmp_path):
    """A flashed pico_bot runs at boot; mpremote stops it and soft-resets into the raw REPL.
    The restarted interpreter once read the STATE frames its predecessor left unread on the
    plant link ("expected WELCOME from the host, got type 0x82"), so every flash after the
    first failed with "could not enter raw repl"."""
    shutil.copytree(REPO / "examples" / "pico_bot", tmp_path / "pico_bot")
    home = tmp_path / "vboard"
    (home / "fs").mkdir(parents=True)
    shutil.copy(tmp_path / "pico_bot" / "main.py", home / "fs" / "main.py")  # as the first flash left it
    port = vboard.start_background("pins", home=home, app=str(tmp_path / "pico_bot"))
    try:
        time.sleep(1.5)  # main.py drives, the plant link busy
        for _ in range(2):
            assert flash.target_mpy_version(port) == flash.mpy_cross_version()
        assert "expected WELCOME" not in mpremote(port, "exec", "print('ok')").stdout
    finally:
        vboard.stop_background("pins", home)


def test_a_second_flash_of_the_same_app_waits_for_the_first_instead_of_rebuilding_its_folder(board_port):
    """Two flashes of one app and board at once (two terminals, or two test workers) share
    build/flash/<app>-<board>/: the second waits while the first builds and copies it."""
    port, _home = board_port
    done = {}
    with flash.staging_lock("rover", BOARD):
        worker = threading.Thread(target=lambda: done.update(flash.flash("rover", BOARD, port, wait_s=1.0, log=len)))
        worker.start()
        worker.join(timeout=1.5)
        assert worker.is_alive() and not done, "expected the flash to wait for the staging folder's lock"
    worker.join(timeout=120)
    assert not worker.is_alive() and "main.py" in done["copied"], done


# the scenarios make hil FIRMWARE= runs from a flash here: the rover's pinned link traces,
# the spec's one trace from the CLI, the plugin and a worker, a replay, real time
FROM_FLASH = "link_trace_is_unchanged and rover or cli_the_plugin or replay_rebuilds or realtime_mode_runs"


def test_make_hil_firmware_passes_on_what_make_flash_put_on_the_virtual_board(tmp_path, monkeypatch):
    """Before: the README's `make flash` then `make hil FIRMWARE=build/vboard/esp32_devkitc/fs`
    failed 6 scenarios (pinned digests and the spec's one trace held against .mpy files)."""
    monkeypatch.setattr(vboard, "VBOARD_ROOT", tmp_path / "vboard")  # (make flash's own folder, here)
    flash.flash("rover", BOARD, None, wait_s=1.0, log=lambda _: None)  # as `make flash APP=rover BOARD=...`
    fs = tmp_path / "vboard" / BOARD / "fs"
    assert (fs.parent / "flashed.json").is_file() and (fs / "rover_control.mpy").is_file()
    assert vboard.running_port(BOARD) is None, "make flash stops the virtual board it started"
    cmd = [sys.executable, "-m", "host.pytest_plugin.hil_run", "--workers", "0", "--long", "0", "--rig", ""]
    cmd += ["--firmware", str(fs), "--out", str(tmp_path / "hil"), "-k", FROM_FLASH]
    done = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True, timeout=600)
    out = done.stdout + done.stderr
    assert done.returncode == 0, out[-4000:]
    assert "ran from flash: 6 tests" in out and "6 passed" in out, out[-4000:]
    assert (tmp_path / "hil" / "report.html").is_file(), "the report under --out, not the project's build/hil"

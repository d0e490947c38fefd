"""The firmware's traceback as its board prints it (docs/shim.md, "Tracebacks as on a
board"): only the firmware's frames (and frozen asyncio's), never the shim's (its boot
that runs main.py, its open, machine, the scheduler), which a board has in C; in the
run's error, on the console and from the firmware's own ``sys.print_exception``."""

import pytest

from host.core.errors import FirmwareError
from host.core.paths import SHIM_DIR
from host.rig.loop.endings import board_traceback
from host.tests.conftest import shim_app

HELPER = """def load(name):
    with open(name, "rb") as f:
        return f.read()
"""
SHIM_MARKS = ("_hil", "build/shim", "host/shim")
"""What names the shim's frames: its modules (_hilboot.py, _hilconfine.py, _hilfs.py, _hil.py)
and its folders (the compiled one, the source one, /_hil/ as the sandbox shows it)."""


def run(make_rig, tmp_path, main: str, seconds: float = 0.1, **files: str):
    fw = tmp_path / "fw"
    fw.mkdir()
    (fw / "main.py").write_text(main)
    for name, text in files.items():
        (fw / f"{name}.py").write_text(text)
    rig = make_rig(shim_app(), main_dir=fw, allow_exit=True)
    try:
        rig.run_for(seconds)
    finally:
        rig.stop()
    return rig


def shim_lines(text: str) -> list[str]:
    return [line for line in text.splitlines() if any(mark in line for mark in SHIM_MARKS)]


@pytest.mark.hil
def test_an_uncaught_exception_raised_in_the_loops_open_shows_only_the_firmwares_frames(make_rig, tmp_path):
    """Pololu's 3pi+ 2040 library opening a file its board has not got: the board's traceback
    ends at the library's line that called open (C on a board)."""
    with pytest.raises(FirmwareError) as err:
        run(make_rig, tmp_path, "import helper\nhelper.load('splash.pbm')\n", helper=HELPER)
    board = (
        "Traceback (most recent call last):\n"
        '  File "main.py", line 2, in <module>\n'
        '  File "helper.py", line 2, in load\n'
        "OSError: [Errno 2] ENOENT\n"
    )
    assert err.value.traceback == board, f"expected the board's traceback:\n{board}got:\n{err.value.traceback}"
    assert f"MicroPython traceback:\n{board}" in str(err.value), str(err.value)
    assert not shim_lines(str(err.value)), f"expected none of the shim's frames, got {shim_lines(str(err.value))}"
    assert err.value.console.count(board) == 1, f"expected the console to show it once:\n{err.value.console}"


MAIN_PRINTS = """import io, sys, micropython
from machine import Pin

def bad_pin():
    Pin("NOPE", Pin.OUT)

try:
    bad_pin()
except ValueError as e:
    buf = io.StringIO()
    sys.print_exception(e, buf)
    print("TEXT", repr(buf.getvalue()))
    sys.print_exception(e)
    micropython.heap_lock()  # (no room for a copy of the text: printed all the same, as a board does)
    try:
        sys.print_exception(e)
    finally:
        micropython.heap_unlock()
print("DONE")
"""


@pytest.mark.hil
def test_the_firmwares_own_print_exception_leaves_out_the_shims_frames(make_rig, tmp_path):
    rig = run(make_rig, tmp_path, MAIN_PRINTS)
    board = (
        "Traceback (most recent call last):\n"
        '  File "main.py", line 8, in <module>\n'
        '  File "main.py", line 5, in bad_pin\n'
        "ValueError: invalid pin\n"
    )
    assert f"TEXT {board!r}\n" in rig.console, f"expected the board's text in the buffer:\n{rig.console}"
    assert board in rig.console.split("TEXT", 1)[1], f"expected it on the console too:\n{rig.console}"
    assert rig.console.count("ValueError: invalid pin") == 3 and "DONE" in rig.console, rig.console
    assert rig.console.rstrip().endswith("DONE"), f"expected the firmware to go on:\n{rig.console}"


MAIN_TASK = """import asyncio

async def worker():
    await asyncio.sleep_ms(5)
    raise ValueError("in a task")

async def main():
    asyncio.create_task(worker())
    await asyncio.sleep_ms(50)

asyncio.run(main())
"""


@pytest.mark.hil
def test_a_task_that_dies_shows_its_frames_and_asyncios_never_the_shims(make_rig, tmp_path):
    with pytest.raises(FirmwareError) as err:
        run(make_rig, tmp_path, MAIN_TASK)
    text = err.value.traceback
    assert text.startswith('Traceback (most recent call last):\n  File "main.py", line 11, in <module>\n'), text
    assert text.endswith('  File "main.py", line 5, in worker\nValueError: in a task\n'), text
    assert 'File "asyncio/core.py"' in text, f"expected asyncio's own frames, frozen as on a board:\n{text}"
    assert not shim_lines(text), f"expected none of the shim's frames, got {shim_lines(text)}"
    assert not shim_lines(err.value.console), f"expected none on the console, got {shim_lines(err.value.console)}"
    assert "Task exception wasn't retrieved" in err.value.console, err.value.console


@pytest.mark.hil
def test_a_keyboardinterrupt_the_firmware_raises_ends_the_run_with_its_own_frames(make_rig, tmp_path):
    """The shim sends a KeyboardInterrupt's whole stack (the watchdog's interrupt: the host
    reads where the firmware waited from it); a run that ends on one shows it as the board's."""
    with pytest.raises(FirmwareError) as err:
        run(make_rig, tmp_path, "def stop():\n    raise KeyboardInterrupt\n\nstop()\n")
    board = (
        "Traceback (most recent call last):\n"
        '  File "main.py", line 4, in <module>\n'
        '  File "main.py", line 2, in stop\n'
        "KeyboardInterrupt: \n"
    )
    assert err.value.traceback == board, f"expected the board's traceback:\n{board}got:\n{err.value.traceback}"
    assert f"MicroPython traceback:\n{board.rstrip()}" in str(err.value), str(err.value)


def test_the_hosts_view_leaves_out_the_shims_frames_wherever_it_was_compiled():
    """The shim's source folder, its compiled copy, /_hil/ and, on a board in the loop, its
    private modules under their bare names; a firmware's file of a shim module's name in a
    folder of its own, and frozen asyncio, stay."""
    compiled = "/home/u/robot/build/shim/0123456789abcdef"
    text = "\n".join(
        [
            "Traceback (most recent call last):",
            f'  File "{compiled}/_hilboot.py", line 250, in main',
            '  File "_hilboot.py", line 110, in _run',
            '  File "main.py", line 3, in <module>',
            '  File "asyncio/core.py", line 1, in run',
            '  File "asyncio/task.py", line 1, in push',
            '  File "lib/time.py", line 2, in sleep',
            f'  File "{SHIM_DIR}/time.py", line 74, in sleep_us',
            '  File "/_hil/_hilfs.py", line 383, in op',
            f'  File "{compiled}/_hil.py", line 1103, in _sync',
            "OSError: [Errno 2] ENOENT",
            "",
        ]
    )
    want = (
        "Traceback (most recent call last):\n"
        '  File "main.py", line 3, in <module>\n'
        '  File "asyncio/core.py", line 1, in run\n'
        '  File "lib/time.py", line 2, in sleep\n'
        "OSError: [Errno 2] ENOENT\n"
    )
    assert board_traceback(text) == want, board_traceback(text)
    harness = f'Traceback (most recent call last):\n  File "{compiled}/_hilboot.py", line 9, in main\nOSError: x\n'
    assert board_traceback(harness) == harness, "a traceback of the shim's frames only is the harness's: whole"
    assert board_traceback("ValueError: no frames\n") == "ValueError: no frames\n"

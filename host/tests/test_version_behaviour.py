"""What differs between the MicroPython versions the harness builds (docs/versions.md), each
shown by a small firmware run on every version it concerns, asserting that version's own
behaviour (docs/shim.md, "On each MicroPython version"): the language and runtime's changes
come from the version's interpreter (its frozen asyncio, its int), the machine API's from the
shim, which follows the selected version as each port's C does (host/shim/machine.py, _MPY).

Each case names its version; it is skipped, saying which command builds it, when that
version is not built here. Under ``pytest --mpy-version`` a case runs only in the run of its
own version (the other runs skip it, saying so)."""

from dataclasses import replace

import pytest

from host.core import interpreter
from host.core.errors import SetupError
from host.rig.config.app import App, BoardSettings, InterpreterSettings
from host.tests.conftest import FIRMWARE, results
from host.tests.test_shim_board import bench
from sim_plant.scripted import ScriptedPlant

pytestmark = pytest.mark.hil

VERSIONS = tuple(interpreter.RELEASES)  # 1.25, 1.26, 1.27, 1.28


def _built(version: str) -> str | None:
    """Why this version cannot run here, or None when it is built."""
    try:
        return interpreter.version_problem(interpreter.find(version), version)
    except SetupError as e:
        return str(e)


@pytest.fixture
def on_version(make_rig, hil_mpy_version, monkeypatch):
    """Runs a firmware on one version: make_rig's rig for ``app`` with that version's
    interpreter, the console's ``R`` lines back (checked to come from that version)."""

    def run(version: str, app: App, case: str, duration_s: float):
        if hil_mpy_version and hil_mpy_version != version:
            pytest.skip(f"a case for MicroPython {version}: it runs in the --mpy-version {version} run only")
        problem = _built(version)
        if problem:
            pytest.skip(f"MicroPython {version} is not built here ({problem}): mpy-fil setup --micropython {version}")
        if not hil_mpy_version:  # (the version is the app's, as a rig file's [interpreter] version)
            monkeypatch.delenv(interpreter.VERSION_ENV, raising=False)
        rig = make_rig(
            replace(app, interpreter=InterpreterSettings(mpy_version=version)),
            main_dir=FIRMWARE / case,
            allow_exit=True,
        )
        rig.run_for(duration_s)
        rig.stop()
        r = results(rig.console)
        ran = ".".join(str(v) for v in r.get("version", ()))
        assert ran == version, f"expected MicroPython {version} to run, got {ran!r}: console at {rig.artefacts}"
        return rig, r

    return run


def _plain(board: str = "rpi_pico") -> App:
    return App(
        name="versions",
        default_board=board,
        wiring={},
        make_plant=lambda: ScriptedPlant((), outputs={}, inputs={}),
        board=BoardSettings(console_baud=0),
    )


def _v(version: str) -> tuple[int, int]:
    major, minor = version.split(".")
    return int(major), int(minor)


@pytest.mark.parametrize("version", VERSIONS)
def test_asyncio_run_waits_for_a_main_task_an_irq_wakes_from_1_26(on_version, version):
    """extmod/asyncio/core.py, run_until_complete (1.26: "Fix early exit of asyncio
    scheduler"): nothing queued and nothing to poll, 1.25 returns at once; 1.26 and later
    poll every 3 ms until the Timer callback (at 50 ms) has set the Event, and the main task
    returns at the first poll's end after it (51 ms)."""
    rig, r = on_version(version, _plain(), "ver_asyncio_exit", 0.2)
    expected = [None, 0] if _v(version) < (1, 26) else ["set", 51]
    got = r.get("run")
    assert got == expected, f"{version}: asyncio.run gave {got}, expected {expected} ({rig.artefacts})"


def _timer_expected(board: str, version: str) -> dict:
    refused = ["TypeError", "extra keyword arguments given"]  # (py/argcheck.c, mp_arg_parse_all)
    soft = (30_000, False)  # (after time_pulse_us's 30 ms, at the next call into the shim)
    if board == "rpi_pico_bench":  # ports/rp2/machine_timer.c: ARG_hard from 1.26
        if _v(version) < (1, 26):
            return {"hard_made": refused, "soft_made": refused}
        return {"hard_made": "ok", "hard_ran": (10_000, True), "soft_made": "ok", "soft_ran": soft}
    if _v(version) < (1, 27):  # ports/esp32/machine_timer.c: ARG_hard from 1.27, True refused
        return {"hard_made": refused, "soft_made": refused}
    return {"hard_made": ["ValueError", "hard Timers are not implemented"], "soft_made": "ok", "soft_ran": soft}


@pytest.mark.parametrize("board", ["rpi_pico_bench", "esp32_bench"])
@pytest.mark.parametrize("version", VERSIONS)
def test_timer_hard_as_each_ports_version_takes_it(on_version, version, board):
    """Timer(hard=True) on an rp2 from 1.26 runs its callback at its due time inside a C call
    (as Pin.irq(hard=True) does); hard=False (the default) runs it after the call; a version
    whose port has no hard= refuses the keyword, as the port's argument parser does."""
    rig, r = on_version(version, bench(board), "ver_timer_hard", 0.2)
    got = {k: v for k, v in r.items() if k != "version"}
    expected = _timer_expected(board, version)
    assert got == expected, f"{board} {version}: got {got}, expected {expected} ({rig.artefacts})"


def _uart_expected(board: str, version: str) -> dict:
    """What the bench's looped UART gives ver_uart_read: 3 bytes back at 87, 174 and 260 us
    (then 2, at 87 and 174 us after their write), a read of 5 with a 20 ms timeout."""
    if board == "rpi_pico_bench":  # ports/rp2/machine_uart.c: the next byte within timeout_char (1 ms here)
        first = {"read": [b"abc", 1_260], "left": None, "readinto": [2, b"de", 1_174]}
    else:  # ports/esp32/machine_uart.c: before 1.27 all within timeout; from 1.27 the first,
        # then what has come (timeout_char 0)
        first = {"read": [b"abc", 20_000], "left": None, "readinto": [2, b"de", 20_000]}
        if _v(version) >= (1, 27):
            first = {"read": [b"a", 87], "left": b"bc", "readinto": [1, b"d", 87]}
    if _v(version) < (1, 27):  # py/stream.c's mp_stream_rw: the port's read again, a timeout with nothing
        first["read"][1] += 20_000
        first["readinto"][2] += 20_000
    return first | {"readinto1": False}


@pytest.mark.parametrize("board", ["rpi_pico_bench", "esp32_bench"])
@pytest.mark.parametrize("version", VERSIONS)
def test_a_uart_read_returns_after_one_call_of_the_ports_read_from_1_27(on_version, version, board):
    """extmod/machine_uart.c (1.27: read is mp_stream_read1, readinto mp_stream_readinto1):
    a read returns when the port's read does; before 1.27 py/stream.c's mp_stream_rw calls
    the port's read again after a short read, which waits its timeout once more. The port's
    read as each family's C has it (host/shim/machine.py, UART._port_read). No version's UART
    has a method named readinto1."""
    rig, r = on_version(version, bench(board), "ver_uart_read", 0.2)
    got = {k: v for k, v in r.items() if k != "version"}
    expected = _uart_expected(board, version)
    assert got == expected, f"{board} {version}: got {got}, expected {expected} ({rig.artefacts})"


@pytest.mark.parametrize("version", VERSIONS)
def test_int_to_bytes_takes_no_signed_keyword_up_to_1_28(on_version, version):
    """py/objint.c, int_to_bytes: positional arguments only on every version built here
    (1.29 takes signed=; no 1.29 release is reachable to build: docs/versions.md); a
    negative number is written as if signed=True."""
    rig, r = on_version(version, _plain(), "ver_to_bytes", 0.05)
    assert r.get("signed") == ["TypeError", "function doesn't take keyword arguments"], (version, r, rig.artefacts)
    assert r.get("positional") == b"\xff\xfe", (version, r)


@pytest.mark.parametrize("board", ["rpi_pico", "esp32_devkitc"])
@pytest.mark.parametrize("version", VERSIONS)
def test_no_version_has_i2c_deinit_on_rp2_or_esp32(on_version, version, board):
    """extmod/machine_i2c.c (machine_i2c_locals_dict_table) has no deinit up to 1.28, for the
    rp2's and the ESP32's I2C and for SoftI2C: an AttributeError, as on the board; SPI's
    and SoftSPI's deinit are there (extmod/machine_spi.c, machine_spi_deinit)."""
    rig, r = on_version(version, _plain(board), "ver_bus_deinit", 0.05)
    for name in ("I2C", "SoftI2C"):
        expected = ["AttributeError", f"'{name}' object has no attribute 'deinit'"]
        assert r.get(name) == expected, f"{board} {version}: {name}.deinit gave {r.get(name)} ({rig.artefacts})"
    assert r.get("SPI") == r.get("SoftSPI") == "deinit", (board, version, r)


@pytest.mark.parametrize("version", VERSIONS)
def test_asm_pio_puts_the_modules_globals_back_after_an_error_from_1_28(on_version, version):
    """ports/rp2/modules/rp2.py, asm_pio (1.28: "Don't corrupt globals on asm_pio()
    exception"): a program body that raises (a NameError: it names a module global, which
    it cannot see) leaves the module's globals as the PIO names alone before 1.28, put back
    from 1.28 (host/shim/_pioasm.py, _restores)."""
    rig, r = on_version(version, _plain(), "ver_asm_pio_globals", 0.05)
    expected = ["NameError", "mine"] if _v(version) >= (1, 28) else ["NameError", "globals lost"]
    assert r.get("after") == expected, f"{version}: got {r.get('after')}, expected {expected} ({rig.artefacts})"

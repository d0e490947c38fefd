"""Shim tests: tiny firmwares under host/tests/firmware/<case>/main.py run in the loop
against a ScriptedPlant wired to the esp32_devkitc pin map. Each firmware prints
``R <name> <value>`` lines that the tests read back."""

import ast
import contextlib
import io
import os
from pathlib import Path

import pytest

from host.rig.config.app import CONSOLE_BAUD, App, BoardSettings, Code
from host.rig.hardware.wiring import PROBE_PREFIX
from sim_plant.catalogue.assembly import assemble
from sim_plant.scripted import ScriptedPlant

FIRMWARE = Path(__file__).parent / "firmware"

WIRING = {
    "ENC_L_A": "a",  # pin 34
    "ENC_L_B": "b",  # pin 35
    "ENC_R_A": "echo",  # pin 36
    "SONAR_ADC": "adc",  # pin 32
    "BUMPER": "button",  # pin 23
    "MOTOR_L_IN1": "out1",  # pin 26
    "MOTOR_L_PWM": "pwm",  # pin 25
    "LOOP_PROBE": PROBE_PREFIX + "control",  # pin 15
}
OUTPUTS = {"a": "level", "b": "level", "echo": "level", "adc": "u16", "button": "level"}
INPUTS = {"out1": "level", "pwm": "duty"}


def shim_app(script=(), initial=None, wiring=None, console_baud=CONSOLE_BAUD) -> App:
    return App(
        name="shim-test",
        default_board="esp32_devkitc",
        wiring=wiring or WIRING,
        make_plant=lambda: ScriptedPlant(script, outputs=OUTPUTS, inputs=INPUTS, initial=initial),
        board=BoardSettings(console_baud=console_baud),
    )


def bench_app(
    name: str, plant: dict, *, board: str = "esp32_bench", wiring=None, pins=None, identity=None, lib_dirs=()
) -> App:
    """A firmware on a bench board (``esp32_bench``, ``rpi_pico_bench``) against a plant
    built from the catalogue (``plant``: a rig file's ``[plant]`` table), printing taking
    no time (``console_baud=0``)."""
    return App(
        name=name,
        default_board=board,
        make_plant=lambda: assemble(plant),
        wiring=wiring or {},
        code=Code(lib_dirs=tuple(lib_dirs)),
        board=BoardSettings(pins=pins or {}, identity=identity, console_baud=0),
    )


def our_ptys() -> list[str]:
    """Open fds of this process on a pty, as ``"fd -> target"`` (stdin/stdout/stderr, maybe a
    terminal, aside)."""
    fds = []
    for fd in Path("/proc/self/fd").iterdir():
        if int(fd.name) < 3:
            continue
        try:
            target = os.readlink(fd)
        except OSError:
            continue
        if target == "/dev/ptmx" or target.startswith("/dev/pts/"):
            fds.append(f"{fd.name} -> {target}")
    return fds


def results(console: str) -> dict:
    """The firmware's `R name value` lines as a dict of Python values."""
    out = {}
    for line in console.splitlines():
        if line.startswith("R "):
            _, name, value = line.split(" ", 2)
            out[name] = ast.literal_eval(value)
    return out


@pytest.fixture
def run_case(make_rig):
    def run(case: str, duration_s: float, script=(), initial=None, wiring=None, **kwargs):
        kwargs.setdefault("allow_exit", True)  # these firmwares print their results and end
        rig = make_rig(shim_app(script, initial, wiring), main_dir=FIRMWARE / case, **kwargs)
        rig.run_for(duration_s)
        rig.stop()  # also drains the console pipe
        return rig, results(rig.console)

    return run


@pytest.fixture(scope="session")
def settrace():
    """The line-tracing interpreter of firmware coverage: ``make setup`` builds it; built
    here (once, under a lock) when it is missing, e.g. beside a user's own MICROPYTHON."""
    from host.core import interpreter
    from host.core.errors import SetupError

    try:
        return interpreter.find_variant("settrace")
    except SetupError:
        return interpreter.build_variant("settrace")


def run_cli(*args) -> tuple[int, str, str]:
    """mpy-fil's main() in this process: (exit code, stdout, stderr)."""
    from host.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
        try:
            code = main([str(a) for a in args])
        except SystemExit as e:
            code = e.code
    return code, out.getvalue(), err.getvalue()

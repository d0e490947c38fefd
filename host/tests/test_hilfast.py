"""The shim's hot path in C (``_hilfast``, a user C module of the harness's MicroPython
build: host/shim/cmod/) and its pure-Python path (a user's own interpreter, or
``HIL_PURE=1``) give the same runs: the same link trace byte for byte, the same console
and the same recorded signals, over apps that exercise pins with IRQs (encoders), ADC
samples, UART bytes and the lookahead's held changes."""

import os
import subprocess
from pathlib import Path

import pytest

from host.bench import run_encoder_bot
from host.core import interpreter
from host.core.paths import REPO, SHIM_DIR
from host.rig.config.apps import get_app
from host.tests.conftest import FIRMWARE, bench_app, results
from host.tests.test_shim_polls import PINS, PLANT, RP2040, WIRING

pytestmark = pytest.mark.hil


def _has_c_path() -> bool:
    probe = subprocess.run([str(interpreter.find()), "-c", "import _hilfast"], capture_output=True, timeout=10)
    return probe.returncode == 0


needs_c = pytest.mark.skipif(
    not _has_c_path(), reason="this MicroPython has no _hilfast (a user's own interpreter: the pure path only)"
)


def _shim_picks(env: dict) -> str:
    code = "import os, _hil; print(_hil._fast_path(os.getenv) is not None)"
    env = {**env, "MICROPYPATH": str(SHIM_DIR)}
    out = subprocess.run([str(interpreter.find()), "-c", code], capture_output=True, text=True, env=env, timeout=10)
    return out.stdout.strip() or out.stderr


@needs_c
def test_the_shim_takes_the_c_path_unless_told_not_to():
    assert _shim_picks({}) == "True"
    assert _shim_picks({"HIL_PURE": "1"}) == "False"


RUNS = {  # (app or rig file, world, seed, simulated s)
    "rover": ("rover", "room", 11, 3.0),
    "pico_bot": (str(Path(REPO, "examples", "pico_bot", "rig.toml")), "box-ahead", 11, 3.0),
    "duct": ("duct", "bench", 1, 3.0),  # slot encoders, a 160 Hz timer, a record stream on a UART
    "pool_cleaner_adc": ("pool_cleaner_adc", "default", 1, 10.0),
}


def _run(make_rig, key, pure, monkeypatch) -> tuple[bytes, str]:
    name, world, seed, seconds = RUNS[key]
    if pure:
        monkeypatch.setenv("HIL_PURE", "1")
    else:
        monkeypatch.delenv("HIL_PURE", raising=False)
    rig = make_rig(name, seed=seed, plant_options=dict(get_app(name).worlds[world]), trace=True)
    rig.run_for(seconds)
    console = rig.console
    rig.stop()
    return (rig.artefacts / "trace.jsonl").read_bytes(), console


@needs_c
@pytest.mark.parametrize("key", list(RUNS))
def test_both_paths_give_the_same_trace(make_rig, monkeypatch, key):
    fast, fast_console = _run(make_rig, key, False, monkeypatch)
    pure, pure_console = _run(make_rig, key, True, monkeypatch)
    assert "Traceback" not in fast_console, fast_console[-800:]
    assert fast_console == pure_console
    assert fast == pure, f"{key}: the C path's link trace differs from the pure-Python path's"


@needs_c
def test_both_paths_record_the_same_encoder_edges(tmp_path, monkeypatch):
    signals = {}
    for pure in (False, True):
        if pure:
            monkeypatch.setenv("HIL_PURE", "1")
        run = run_encoder_bot(40_000, run_ms=300, record=True, trace=False, artefacts=tmp_path / f"run{pure}")
        assert run["counts"] == run["edges"]
        signals[pure] = (tmp_path / f"run{pure}" / "signals.csv").read_bytes()
    assert signals[False] == signals[True]


def _both_paths(make_rig, monkeypatch, case: str, plant: dict, seconds: float) -> dict:
    """``case`` run on an RP2040 with the C path (False) and the pure path (True):
    {pure: (the link trace's bytes, the console)}."""
    traces = {}
    for pure in (False, True):
        if pure:
            monkeypatch.setenv("HIL_PURE", "1")
        else:
            monkeypatch.delenv("HIL_PURE", raising=False)
        app = bench_app(case, plant, board="pins", identity=RP2040, pins=PINS, wiring=WIRING)
        rig = make_rig(app, main_dir=FIRMWARE / case, allow_exit=True, trace=True)
        rig.run_for(seconds)
        console = rig.console
        rig.stop()
        traces[pure] = ((rig.artefacts / "trace.jsonl").read_bytes(), console)
    return traces


@needs_c
def test_both_paths_give_the_same_trace_for_pins_the_main_program_polls(make_rig, monkeypatch):
    """Pin.value() read by the main program (C when the read needs no look at the host):
    a button read until its press, a pin nothing drives read for ever, with sleeps between
    reads and without, up to the poll named after POLL_READS reads."""
    traces = _both_paths(make_rig, monkeypatch, "polls_forever", PLANT, 2.0)
    assert "R button" in traces[False][1], traces[False][1][-800:]
    assert traces[False][1] == traces[True][1]
    assert traces[False][0] == traces[True][0], "the C path's link trace differs from the pure-Python path's"


@needs_c
def test_both_paths_give_the_same_trace_for_edges_inside_a_c_call(make_rig, monkeypatch):
    """Edges applied while the main program is in what is a C call on a board (an RP2040's
    sleep_us under 1 ms, _hil.c_begin): the soft handler's runs wait for its return, the
    hard handler's run at their edges, on both paths (the C apply's dispatch defers them
    from _Link.defer_from on, as _hil.dispatch does)."""
    plant = {**PLANT, "parts": [*PLANT["parts"][:3], {"kind": "button", "name": "stop", "presses": [[0.3, 0.45]]}]}
    traces = _both_paths(make_rig, monkeypatch, "irq_in_c_call", plant, 1.5)
    got = results(traces[False][1])
    assert len(got.get("soft", ())) == 2 and len(got.get("hard", ())) == 2, traces[False][1][-800:]
    assert traces[False][1] == traces[True][1]
    assert traces[False][0] == traces[True][0], "the C path's link trace differs from the pure-Python path's"


def test_the_codes_the_c_module_spells_out_are_the_codecs():
    """_hilfast.c writes the change layout and the codes it tests as numbers."""
    from host.shim import _hilframe as F

    source = (SHIM_DIR / "cmod" / "_hilfast" / "_hilfast.c").read_text()
    assert F.CHANGE_FMT == "<IHBiI" and F.CHANGE_LEN == 15 and "#define CHANGE_LEN 15" in source
    assert f"#define CH_BYTES {F.CH_BYTES} " in source
    assert f"#define IRQ_RISING {F.IRQ_RISING} " in source and f"#define IRQ_FALLING {F.IRQ_FALLING}\n" in source
    assert os.path.isfile(SHIM_DIR / "cmod" / "_hilfast" / "micropython.mk")

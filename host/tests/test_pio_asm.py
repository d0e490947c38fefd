"""rp2.asm_pio assembles as the RP2040 port does (docs/shim.md, "PIO"): the shim's
assembler (host/shim/_pioasm.py) gives the same instruction words as Adafruit's pioasm, an
independent assembler, on a corpus of programs written as public code writes them; the
same program list (words, EXECCTRL, SHIFTCTRL, pin inits) as the port's own rp2.py when
the MicroPython source is at hand; and the same words in MicroPython as in CPython."""

import importlib.util
import json
import os
import subprocess
import sys
import types
from pathlib import Path

import adafruit_pioasm
import pytest

from host.core.paths import REPO
from host.tests import pio_corpus

SHIM = REPO / "host" / "shim"
sys.path.insert(0, str(SHIM))
import _pioasm  # noqa: E402

PORT_RP2 = sorted((REPO / "build" / "micropython").glob("src/micropython-*/ports/rp2/modules/rp2.py"))


def assemble(name, assembler=_pioasm):
    body, settings, _text = pio_corpus.CORPUS[name]
    return assembler.asm_pio(**settings)(body)


def _port_assembler():
    """The port's rp2.py, its C half (_rp2: the PIO constants) stood in for."""
    rp2_c = types.ModuleType("_rp2")
    rp2_c.PIO = types.SimpleNamespace(SHIFT_LEFT=0, SHIFT_RIGHT=1, JOIN_NONE=0, JOIN_TX=1, JOIN_RX=2)
    rp2_c.__all__ = ["PIO"]
    micropython = types.ModuleType("micropython")
    micropython.const = lambda v: v
    saved = {k: sys.modules.get(k) for k in ("_rp2", "micropython")}
    sys.modules.update(_rp2=rp2_c, micropython=micropython)
    try:
        spec = importlib.util.spec_from_file_location("port_rp2", PORT_RP2[-1])
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
    finally:
        for k, v in saved.items():
            if v is None:
                sys.modules.pop(k, None)
            else:
                sys.modules[k] = v
    return module


@pytest.mark.parametrize("name", sorted(pio_corpus.CORPUS))
def test_words_equal_adafruit_pioasm(name):
    prog = assemble(name)
    theirs = adafruit_pioasm.Program(pio_corpus.CORPUS[name][2])
    assert [f"{w:04x}" for w in prog[0]] == [f"{w:04x}" for w in theirs.assembled]
    execctrl = prog[3]
    wrap_top, wrap_target = execctrl >> 12 & 0x1F, execctrl >> 7 & 0x1F
    assert wrap_top == theirs.pio_kwargs.get("wrap", len(prog[0]) - 1)
    assert wrap_target == theirs.pio_kwargs.get("wrap_target", 0)
    assert bool(execctrl >> 30 & 1) == bool(theirs.pio_kwargs.get("sideset_enable", False))


@pytest.mark.skipif(not PORT_RP2, reason="the MicroPython source (build/micropython/src) is not unpacked")
@pytest.mark.parametrize("name", sorted(pio_corpus.CORPUS))
def test_program_equals_the_ports_own_assembler(name):
    port = _port_assembler()
    ours, theirs = assemble(name), assemble(name, port)
    assert list(ours[0]) == list(theirs[0])
    assert ours[1:] == theirs[1:]


@pytest.mark.skipif(not PORT_RP2, reason="the MicroPython source (build/micropython/src) is not unpacked")
def test_asm_pio_encode_equals_the_ports():
    port = _port_assembler()
    cases = [
        ("set(pins, 1)", 0, False),
        ("nop()", 0, False),
        ("set(x, 31)[3]", 0, False),
        ("out(pins, 8).side(1)", 1, False),
        ("mov(y, invert(x)).side(1)[2]", 2, True),
        ("irq(clear, rel(1))", 0, False),
        ("push(iffull, noblock)", 0, False),
        ("wait(1, irq, 4)", 0, False),
        ("pull(ifempty)", 0, False),
    ]
    for instr, count, opt in cases:
        assert _pioasm.asm_pio_encode(instr, count, opt) == port.asm_pio_encode(instr, count, opt), instr


def test_asm_pio_encode_known_words():
    assert _pioasm.asm_pio_encode("set(pins, 1)", 0) == 0xE001
    assert _pioasm.asm_pio_encode("nop()", 0) == 0xA042
    assert _pioasm.asm_pio_encode("out(pins, 8).side(1)", 1) == 0x7008


def test_errors_are_the_ports():
    def too_long():
        nop()[32]  # noqa: F821

    def no_side():
        nop().side(1)  # noqa: F821

    def unknown():
        jmp("nowhere")  # noqa: F821

    with pytest.raises(_pioasm.PIOASMError, match="delay too large"):
        _pioasm.asm_pio()(too_long)
    with pytest.raises(_pioasm.PIOASMError, match="no sideset"):
        _pioasm.asm_pio()(no_side)
    with pytest.raises(_pioasm.PIOASMError, match="unknown label nowhere"):
        _pioasm.asm_pio()(unknown)


MICROPYTHON_SCRIPT = """
import json, pio_corpus, _pioasm
out = {}
for name in sorted(pio_corpus.CORPUS):
    body, settings, text = pio_corpus.CORPUS[name]
    prog = _pioasm.asm_pio(**settings)(body)
    out[name] = [list(prog[0])] + list(prog[1:5])
print(json.dumps(out))
"""


def test_micropython_assembles_the_same_words(tmp_path: Path):
    micropython = os.environ.get("MICROPYTHON") or str(REPO / "build" / "micropython" / "micropython")
    if not Path(micropython).exists():
        pytest.skip("no MicroPython interpreter")
    script = tmp_path / "asm.py"
    script.write_text(MICROPYTHON_SCRIPT)
    env = {**os.environ, "MICROPYPATH": f"{SHIM}:{REPO / 'host' / 'tests'}"}
    done = subprocess.run([micropython, str(script)], capture_output=True, text=True, env=env, timeout=60)
    assert done.returncode == 0, done.stderr + done.stdout
    words = json.loads(done.stdout)
    for name in pio_corpus.CORPUS:
        prog = assemble(name)
        assert words[name] == [list(prog[0])] + list(prog[1:5]), name

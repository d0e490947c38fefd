"""The host side of the peripherals (host/rig/hardware/peripherals.py): one handler per CFG kind in a
table, the codes on the wire named once in the codec (no bare numbers for them on the host),
and a new kind (a bus, later) dispatched by registering it, with nothing else changed."""

import ast
import json
from types import SimpleNamespace

import pytest

from host.core.errors import ConfigError, LinkError
from host.core.paths import REPO
from host.link import frames as F
from host.rig.hardware.inputs import Inputs
from host.rig.hardware.peripherals import FIRED, HANDLERS, Peripheral, register
from host.rig.hardware.wiring import Wiring
from host.rig.loop.speculation import Speculation

CODED_FIELDS = {"mode", "pull", "irq", "trigger"}  # CFG fields whose values the codec names


def test_every_cfg_kind_of_the_codec_has_one_handler_and_every_handler_a_kind():
    kinds = {value for name, value in vars(F).items() if name.startswith("CFG_") and name not in ("CFG_FMT", "CFG_LEN")}
    assert set(HANDLERS) == kinds
    assert all(p.kind == kind for kind, p in HANDLERS.items())
    assert len({p.name for p in HANDLERS.values()}) == len(HANDLERS)


def test_the_shim_says_its_modes_pulls_and_triggers_by_the_codecs_names():
    shim = (REPO / "host/shim/machine.py").read_text()
    for name in ("PIN_IN", "PIN_OUT", "PIN_OPEN_DRAIN", "PULL_NONE", "PULL_UP", "PULL_DOWN", "IRQ_RISING", "IRQ_RX"):
        assert f"_F.{name}" in shim, f"host/shim/machine.py does not say {name} by the codec's name"


def bare_codes(tree: ast.AST) -> list[int]:
    """Lines comparing or masking a coded CFG field (mode, pull, irq, trigger) with a bare int."""
    lines = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Compare):
            operands = [node.left, *node.comparators]
        elif isinstance(node, ast.BinOp) and isinstance(node.op, (ast.BitAnd, ast.BitOr)):
            operands = [node.left, node.right]
        else:
            continue
        names = {getattr(o, "attr", getattr(o, "id", None)) for o in operands}
        if names & CODED_FIELDS and any(isinstance(o, ast.Constant) and type(o.value) is int for o in operands):
            lines.append(node.lineno)
    return lines


def test_the_scan_finds_bare_codes_and_passes_named_ones():
    assert bare_codes(ast.parse("if info.pull == 1: pass\nx = info.irq & 2\ny = mode == 0")) == [1, 2, 3]
    assert not bare_codes(ast.parse("if info.pull == F.PULL_UP: pass\nx = info.irq & F.IRQ_FALLING"))


def test_no_bare_numbers_for_modes_pulls_or_triggers_on_the_host():
    bare = []
    for path in sorted((REPO / "host").rglob("*.py")):
        rel = path.relative_to(REPO).as_posix()
        if not rel.startswith(("host/shim/", "host/tests/")):
            bare += [f"{rel}:{line}" for line in bare_codes(ast.parse(path.read_text(), rel))]
    assert not bare, f"bare codes (say them by the codec's names, host/shim/_hilframe.py): {bare}"


def test_pulls_and_triggers_cross_the_link_as_the_codec_names_them(run_case, tmp_path):
    """Unwired inputs read their pull; a button on a pull-down fires IRQ_RISING at the press
    and, re-armed, IRQ_FALLING at the release; the CFGs carry the codec's codes."""
    script = [(10_000, "button", 1), (40_000, "button", 0)]
    rig, r = run_case("pulls", 0.1, script, artefacts=tmp_path, trace=True)
    assert (r["up"], r["down"], r["floating"]) == (1, 0, 0), r
    assert r["events"] == [(F.IRQ_RISING, 10), (F.IRQ_FALLING, 40)], r
    cfgs = {}
    for line in (tmp_path / "trace.jsonl").read_text().splitlines():
        record = json.loads(line)
        if record.get("msg") == "CFG":
            cfgs.setdefault(record["pin"], []).append((record["kind"], record["mode"], record["pull"]))
    assert cfgs["4"] == [("pin", F.PIN_IN, F.PULL_UP)], cfgs
    assert cfgs["5"] == [("pin", F.PIN_IN, F.PULL_DOWN)], cfgs
    assert cfgs["12"] == [("pin", F.PIN_IN, F.PULL_NONE)], cfgs
    assert cfgs["13"] == [("pin", F.PIN_OPEN_DRAIN, F.PULL_NONE)], cfgs
    assert cfgs["23"] == [("pin", F.PIN_IN, F.PULL_DOWN), ("irq", F.IRQ_RISING, 0), ("irq", F.IRQ_FALLING, 0)], cfgs


def wiring() -> Wiring:
    return Wiring({"BTN": "button", "LED": "led"}, {"BTN": 4, "LED": 5}, "test", sensors={"button": "level"})


def test_a_cfg_of_a_kind_the_host_does_not_know_is_a_link_error_naming_the_known_ones():
    with pytest.raises(LinkError, match=r"CFG of kind 42 on handle 0; the host knows 1 pin, 2 adc.*protocol error"):
        wiring().configure(0, 42, 0, 0, "4")


def test_each_handler_refuses_what_no_board_survives():
    with pytest.raises(ConfigError, match=r"drives pin BTN \(4\) as an output, but it is wired to button"):
        wiring().configure(0, F.CFG_PIN, F.PIN_OUT, F.PULL_NONE, "4")
    with pytest.raises(ConfigError, match=r"drives pin BTN \(4\).*button"):
        wiring().configure(0, F.CFG_PWM, 0, 0, "4", 1000)
    with pytest.raises(ConfigError, match=r"reads pin BTN \(4\) with an ADC, but button is a logic level"):
        wiring().configure(0, F.CFG_ADC, 0, 0, "4")
    assert wiring().configure(0, F.CFG_PIN, F.PIN_IN, F.PULL_UP, "4").is_input


def test_an_output_or_bytes_on_the_wrong_kind_of_handle_is_a_link_error():
    w = wiring()
    w.configure(1, F.CFG_ADC, 0, 0, "9")
    outputs = SimpleNamespace(recorder=None, plant_inputs={})
    info = w.handles[1]
    with pytest.raises(LinkError, match="OUT to adc 9, which has no outputs"):
        info.peripheral.out(outputs, 0, info, F.OUT_LEVEL, 1)
    with pytest.raises(LinkError, match="UART_TX from a handle the shim never configured"):
        w.handles[0].peripheral.transmit(outputs, 0, w.handles[0], b"x")


class _Bus(Peripheral):
    """A bus to come: each plant value is one reading, delivered as a level change."""

    kind = 200
    name = "testbus"

    def is_input(self, mode):
        return True

    def deliver(self, inputs, t_us, h, info, value, watch):
        inputs.pending.append((t_us, h, F.CH_LEVEL, value, 0))
        return FIRED


def test_a_new_kind_is_dispatched_once_registered_and_a_taken_kind_is_refused():
    with pytest.raises(ValueError, match="CFG kind 1 .* taken"):
        register(_Bus.__new__(type("Again", (_Bus,), {"kind": F.CFG_PIN})))
    register(_Bus())
    try:
        w = wiring()
        info = w.configure(0, _Bus.kind, 0, 0, "4")
        assert info.is_input and info.peripheral is HANDLERS[_Bus.kind]
        hooks = SimpleNamespace(change={}, sample={})
        inputs = Inputs(w, hooks, Speculation(None), None, SimpleNamespace(irq_edges=0))
        assert inputs.route((7, "button", 3), frozenset()) == (True, False)
        assert inputs.take() == [(7, 0, F.CH_LEVEL, 3, 0)]
    finally:
        del HANDLERS[_Bus.kind]

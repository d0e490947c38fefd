"""A PIO program's pin direction changes reach the pins as the plant sees them
(docs/shim.md, "PIO"; the RP2040 datasheet, 3.5.6: a pin's output enable is its PINDIRS
bit): a pin made an input carries nothing driven (``RELEASED``) from that cycle, a pin made
an output its OUT level from that cycle, and a level driven while it is an input is kept
for later, not seen. ``set pindirs``, ``out pindirs`` and side-set with ``side_pindir``."""

import sys

from host.core.paths import REPO
from sim_plant.pio import PioBlock, PioConfig
from sim_plant.pio.block import RELEASED

sys.path.insert(0, str(REPO / "host" / "shim"))
import _pioasm  # noqa: E402

GPIO = 3
FREQ_HZ = 1_000_000  # a cycle a microsecond
OUT_LOW = 2  # rp2.PIO.OUT_LOW


def run(body, settings: dict, pinctrl: int, until_us: int = 20) -> list:
    """``body`` on state machine 0 from t=0, its pin an input first (as ``*_init`` IN sets
    it): the pin's events (t_us, level or RELEASED)."""
    prog = _pioasm.asm_pio(**settings)(body)
    block = PioBlock()
    block.load(list(prog[0]))
    div256 = 125_000_000 // FREQ_HZ * 256
    block.init(0, PioConfig(prog[3], prog[4], pinctrl, div256, 0), 0)
    block.drive(GPIO, 0, dirs=True)
    block.events.clear()  # (as the host's init: the init levels are no change)
    block.set_active(0, True, 0)
    block.advance(until_us)
    return [(t, level) for t, g, level in block.events if g == GPIO]


def set_pindirs():  # noqa: F821 (the PIO's names exist only while asm_pio assembles it)
    set(pins, 1)  # noqa: F821  an input: the level is kept, not seen
    set(pindirs, 1)  # noqa: F821  an output: high (the level set before)
    set(pins, 0)[2]  # noqa: F821
    set(pindirs, 0)  # noqa: F821  let go
    set(pins, 1)  # noqa: F821  not seen
    set(pindirs, 1)  # noqa: F821  high again
    label("end")  # noqa: F821
    jmp("end")  # noqa: F821


def out_pindirs():
    mov(osr, invert(null))  # noqa: F821
    out(pins, 1)  # noqa: F821  an input: not seen
    out(pindirs, 1)  # noqa: F821  an output: high
    mov(osr, null)[3]  # noqa: F821
    out(pindirs, 1)  # noqa: F821  let go
    label("end")  # noqa: F821
    jmp("end")  # noqa: F821


def side_pindirs():
    nop().side(1)  # noqa: F821  an output: its OUT level (low: nothing drove it)
    set(pins, 1).side(1)  # noqa: F821  high
    nop().side(0)[1]  # noqa: F821  let go
    nop().side(1)  # noqa: F821  high again
    label("end")  # noqa: F821
    jmp("end").side(1)  # noqa: F821


def pinctrl(*, out_base=0, out_count=0, set_base=0, set_count=0, side_base=0, side_count=0):
    return side_count << 29 | set_count << 26 | out_count << 20 | side_base << 10 | set_base << 5 | out_base


def test_set_pindirs_lets_the_pin_go_and_drives_it_again_at_their_cycles():
    got = run(set_pindirs, {}, pinctrl(set_base=GPIO, set_count=1))
    want = [(1.0, 1), (2.0, 0), (5.0, RELEASED), (7.0, 1)]
    assert got == want, f"expected the pin's events (t_us, level; {RELEASED} let go) {want}, got {got}"


def test_out_pindirs_lets_the_pin_go_at_its_cycle():
    got = run(out_pindirs, {}, pinctrl(out_base=GPIO, out_count=1))
    want = [(2.0, 1), (7.0, RELEASED)]
    assert got == want, f"expected the pin's events (t_us, level; {RELEASED} let go) {want}, got {got}"


def test_side_set_pindirs_lets_the_pin_go_and_drives_it_again_at_their_cycles():
    settings = {"sideset_init": OUT_LOW, "side_pindir": True}
    got = run(side_pindirs, settings, pinctrl(set_base=GPIO, set_count=1, side_base=GPIO, side_count=1))
    want = [(0.0, 0), (1.0, 1), (2.0, RELEASED), (4.0, 1)]
    assert got == want, f"expected the pin's events (t_us, level; {RELEASED} let go) {want}, got {got}"

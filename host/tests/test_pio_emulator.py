"""The host's PIO (sim_plant/pio, docs/shim.md "PIO") runs public-style programs as an
RP2040 does: a quadrature decoder with a jump table counts every edge of any sequence;
PWM and servo pulses, WS2812 bits and UART TX frames come out at the PIO clock's
instants; a state machine that waits on a pin, or polls pins that do not change, costs
nothing until they change."""

import sys

from hypothesis import given, settings
from hypothesis import strategies as st

from host.core.paths import REPO
from host.tests import pio_corpus
from sim_plant.pio import PioBlock, PioConfig

sys.path.insert(0, str(REPO / "host" / "shim"))
import _pioasm  # noqa: E402

SYS_HZ = 125_000_000


def machine(name, freq_hz, pinctrl=0, **overrides):
    """The corpus program ``name`` in PIO0 at offset 0 on state machine 0, started at t=0,
    as rp2.StateMachine(0, prog, freq=freq_hz, ...) sets it up (``pinctrl`` as the hardware
    has it: docs/shim.md)."""
    body, settings_, _text = pio_corpus.CORPUS[name]
    prog = _pioasm.asm_pio(**{**settings_, **overrides})(body)
    block = PioBlock()
    block.load(list(prog[0]))
    div = SYS_HZ / freq_hz
    div256 = int(div) * 256 + int((div - int(div)) * 256)
    sm = block.init(0, PioConfig(prog[3], prog[4], pinctrl, div256, 0), 0)
    block.set_active(0, True, 0)
    return block, sm


def pinctrl(*, out_base=0, out_count=0, set_base=0, set_count=0, side_base=0, side_count=0, in_base=0):
    counts = side_count << 29 | set_count << 26 | out_count << 20
    return counts | in_base << 15 | side_base << 10 | set_base << 5 | out_base


def signed(x):
    return x - (1 << 32) if x & 0x80000000 else x


QUAD = [(0, 0), (1, 0), (1, 1), (0, 1)]  # (A, B) forwards, as sim_plant.physics.encoder' QUAD_A/QUAD_B


@settings(max_examples=30, deadline=None)
@given(st.lists(st.tuples(st.sampled_from([1, -1]), st.integers(1, 400)), min_size=1, max_size=120))
def test_the_quadrature_decoder_counts_every_edge_of_any_sequence(steps):
    block, sm = machine("quadrature", 10_000_000, pinctrl(in_base=6))
    phase, t_us, count = 0, 0, 0
    for direction, gap_us in steps:
        t_us += gap_us
        block.advance(t_us)
        phase = (phase + direction) % 4
        a, b = QUAD[phase]
        block.set_input(6, a)
        block.set_input(7, b)
        count += direction
    block.advance(t_us + 10)
    assert signed(sm.x) == count
    assert signed(sm.rx[-1]) == count or len(sm.rx) == 4, "the count is pushed while the FIFO has room"


def test_a_decoder_between_edges_and_a_wait_on_a_pin_cost_nothing():
    block, sm = machine("quadrature", 125_000_000, pinctrl(in_base=0))
    block.advance(10_000_000)  # 10 s at 125 MHz with no edge: 1.25e9 cycles
    assert block.steps < 100, block.steps
    block, sm = machine("uart_rx", 125_000_000, pinctrl(in_base=3))
    block.set_input(3, 1)  # the line idles high: the program waits for a start bit
    block.advance(10_000_000)
    assert block.steps < 100, block.steps


def edges(block, gpio):
    return [(t, level) for t, g, level in block.events if g == gpio]


def preload_isr(block, sm, word: int) -> None:
    """``word`` into the ISR as public PWM and servo classes do: ``put``, then ``exec`` of
    ``pull()`` and ``mov(isr, osr)`` (side-set of 1 bit, optional)."""
    sm.tx.append(word)
    sm.pending_exec = _pioasm.asm_pio_encode("pull()", 2, True)
    block.advance(1)
    sm.pending_exec = _pioasm.asm_pio_encode("mov(isr, osr)", 2, True)


def test_pwm_pulses_come_at_the_pio_clocks_instants():
    """The MicroPython docs' PWM (examples/rp2/pio_pwm.py): put the period into ISR once,
    then each put is a duty count; high for 2 * count + 2 cycles of 2 * (period + 1) + 4."""
    freq, period, count = 1_000_000, 100, 30
    block, sm = machine("pwm", freq, pinctrl(side_base=9, side_count=2))
    preload_isr(block, sm, period)
    sm.tx.append(count)
    block.advance(2_000)
    rises = [t for t, level in edges(block, 9) if level == 1]
    falls = [t for t, level in edges(block, 9) if level == 0 and t > rises[0]]
    assert len(rises) > 5
    period_us = (2 * (period + 1) + 4) / freq * 1e6
    assert all(abs((b - a) - period_us) < 1e-6 for a, b in zip(rises, rises[1:])), rises[:4]
    highs = [f - r for r, f in zip(rises, falls)]
    assert all(abs(h - (2 * count + 2) / freq * 1e6) < 1e-6 for h in highs), highs[:4]


def test_ws2812_bits_are_the_neopixel_timing_and_bytes():
    """MicroPython's pio_ws2812.py at 8 MHz: 10 cycles a bit (1.25 us), a 1 high for 7
    cycles (875 ns), a 0 for 2 (250 ns); 24 bits a pixel, G R B, most significant first."""
    block, sm = machine("ws2812", 8_000_000, pinctrl(side_base=12, side_count=1))
    grb = [0xFF0000, 0x00A501, 0x123456]
    sm.tx.extend(w << 8 for w in grb)
    block.advance(200)
    levels = edges(block, 12)
    pulses = [(b[0] - a[0]) for a, b in zip(levels, levels[1:]) if a[1] == 1]
    assert set(round(p * 1000) for p in pulses) == {875, 250}
    bits = "".join("1" if p > 0.6 else "0" for p in pulses)
    assert bits == "".join(f"{w:024b}" for w in grb)
    rises = [t for t, level in levels if level == 1]
    assert all(abs((b - a) - 1.25) < 1e-9 for a, b in zip(rises[:23], rises[1:24]))


def test_a_uart_tx_sends_start_eight_bits_lsb_first_and_stop_at_its_baud():
    baud = 115_200
    block, sm = machine("uart_tx", 8 * baud, pinctrl(out_base=0, out_count=1, side_base=0, side_count=2))
    block.drive(0, 1)  # (out_init = OUT_HIGH: the line idles high)
    block.events.clear()
    sm.tx.extend([0x55, 0xA3])
    block.advance(300)
    levels = [(0.0, 1)] + edges(block, 0)
    bit_us = 1e6 / baud

    def level_at(t):
        return [lv for tt, lv in levels if tt <= t + 1e-9][-1]

    start = levels[1][0]
    got = []
    for frame in range(2):
        t0 = start + frame * 10 * bit_us
        assert level_at(t0 + bit_us / 2) == 0, "start bit"
        got.append(sum(level_at(t0 + (1.5 + i) * bit_us) << i for i in range(8)))
        assert level_at(t0 + 9.5 * bit_us) == 1, "stop bit"
    assert got == [0x55, 0xA3]


def test_a_decoder_following_10000_edges_a_second_steps_under_one_instruction_an_edge():
    """Each edge's stretch is taken from the table after its first few (sim_plant/pio/trace.py):
    the count is every edge's, the instructions stepped a handful for the whole run."""
    from host.tests.bench_pio import emulator_only

    figures = emulator_only(0.5)  # 5,000 edges at 125 MHz; it checks the count itself
    assert figures["steps_per_edge"] < 1.0, figures


def test_servo_pulses_are_x_plus_2_cycles_high_every_x_plus_y_plus_6():
    """A servo program as RP2040 servo libraries write it (corpus 'servo'): the high count
    in the TX FIFO, the low count in ISR; at 1 MHz, 1.5 ms pulses every 20 ms."""
    block, sm = machine("servo", 1_000_000, pinctrl(side_base=15, side_count=2))
    high, low = 1500 - 2, 20_000 - 6 - 1498
    preload_isr(block, sm, low)
    sm.tx.append(high)
    block.advance(100_000)
    levels = edges(block, 15)
    rises = [t for t, level in levels if level == 1]
    falls = [t for t, level in levels if level == 0 and t > rises[0]]
    assert len(rises) >= 4
    assert all(abs((b - a) - 20_000) < 1e-6 for a, b in zip(rises, rises[1:])), rises
    assert all(abs((f - r) - 1500) < 1e-6 for r, f in zip(rises, falls)), list(zip(rises, falls))


def test_a_block_whose_changes_nobody_reads_jumps_its_periods_to_the_same_state_and_levels():
    """``record_events`` False (the rig's own blocks: what they drive reaches the plant
    through a look-ahead on a copy, host/rig/hardware/pio_out.py): a period of drives jumped over is
    replayed once, not once a period, and the block ends where the one that keeps every
    change does: the same levels, registers, FIFOs and cycle, a change per period fewer."""
    runs = []
    for record in (True, False):
        block, sm = machine("pwm", 1_000_000, pinctrl(side_base=9, side_count=2))
        block.record_events = record
        preload_isr(block, sm, 100)
        sm.tx.append(30)
        steps = block.steps
        block.advance(2_000_000)  # (about 9,700 periods of 206 us)
        state = (dict(block.levels), sm.x, sm.y, sm.isr, sm.osr, sm.pc, list(sm.tx), list(sm.rx))
        runs.append((state, block.running[0].cycle, len(block.events), block.steps - steps))
    (kept, kept_cycle, kept_changes, kept_steps), (state, cycle, changes, steps) = runs
    assert (state, cycle) == (kept, kept_cycle), f"expected the same end, got {state} at {cycle} against {kept}"
    assert kept_changes > 19_000 and changes < 100, f"every period's changes kept, then the last: {runs}"
    assert steps == kept_steps, f"expected the same instructions stepped, got {steps} against {kept_steps}"


def test_a_pin_change_no_state_machine_reads_leaves_the_block_where_running_through_it_does():
    """A servo's program beside an echo pin that it does not read (Kitronik's buggy: the
    ranger's echo, the line sensors): its block, its events not kept, goes on from before the
    changes to after them in one run, and ends where a run stopped at each change does (the
    same levels, registers, FIFOs and cycle), with far fewer steps."""
    changes = [(t, 3, (t // 700) & 1) for t in range(700, 1_000_000, 700)]  # (GP3: not the servo's)
    runs = []
    for at_each in (True, False):
        block, sm = machine("servo", 1_000_000, pinctrl(side_base=15, side_count=2))
        block.record_events = False
        preload_isr(block, sm, 20_000 - 6 - 1498)
        sm.tx.append(1500 - 2)
        steps = block.steps
        if at_each:  # (each change's instant a run of its own, as before a change was known unread)
            for t, gpio, level in changes:
                block.advance(t)
                block.set_input(gpio, level)
            block.advance(1_000_000)
        else:
            block.advance(1_000_000, changes)
        state = (dict(block.levels), sm.x, sm.y, sm.isr, sm.osr, sm.pc, list(sm.tx), list(sm.rx), block.gpio_in)
        runs.append((state, block.running[0].cycle, block.steps - steps))
    (each, each_cycle, each_steps), (once, cycle, steps) = runs
    assert (once, cycle) == (each, each_cycle), f"expected the same end, got {once} at {cycle} against {each}"
    assert steps * 20 < each_steps, f"expected far fewer steps than {each_steps} in one run, got {steps}"

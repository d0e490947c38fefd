"""A batch of pin changes walked along the stretch table (sim_plant/pio/walk.py) leaves a
PIO block exactly as the step-by-step path does: the same registers, FIFOs, cycles,
table, version, replays and instructions stepped, after every batch, for any sequence
of edges on two decoders (forwards, backwards, both pins at once, a count crossing 0),
a UART receiver, a polling counter with delays in its loop, and the firmware taking RX
words between batches."""

import sys

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from host.core.paths import REPO
from host.tests.test_pio_emulator import QUAD, machine, pinctrl
from sim_plant.pio import PioBlock, PioConfig
from sim_plant.pio import block as block_module
from sim_plant.pio import walk as walk_module

sys.path.insert(0, str(REPO / "host" / "shim"))
import _pioasm  # noqa: E402


def poll_counter():  # a rising edge counted by polling the jmp pin, delays in both loops
    wrap_target()  # noqa: F821
    label("low")  # noqa: F821
    jmp(pin, "rise")[2]  # noqa: F821
    jmp("low")[1]  # noqa: F821
    label("rise")  # noqa: F821
    jmp(x_dec, "high")  # noqa: F821
    label("high")  # noqa: F821
    mov(isr, x)  # noqa: F821
    push(noblock)[3]  # noqa: F821
    jmp(pin, "high")[1]  # noqa: F821
    wrap()  # noqa: F821


def blocks():
    block, _sm = machine("quadrature", 10_000_000, pinctrl(in_base=6))
    config = block.sm(0).config
    block.init(1, PioConfig(config.execctrl, config.shiftctrl, pinctrl(in_base=8), config.div256, 0), 0)
    block.set_active(1, True, 0)
    return block


def snapshot(block) -> tuple:
    runs = []
    for sm_id, run in sorted(block.running.items()):
        table = run.table
        kept = None
        if table is not None:
            kept = (table[0].cycles, table[0].period, table[1], table[2], list(table[3]), table[4])
        runs.append((sm_id, run.cycle, run.sm.key(), run.orbit, run.orbit_version == block.version, kept))
    return (block.version, block.gpio_in, block.replays, block.steps, block.irq_flags, runs)


def batches_of(moves):
    """[(t_us, gpio, level)] per batch from (gap_us, wheel, direction, both_at_once) moves."""
    phases, t_us, out = [0, 0], 0, []
    for batch in moves:
        changes = []
        for gap_us, wheel, direction, both in batch:
            t_us += gap_us
            old = QUAD[phases[wheel]]
            phases[wheel] = (phases[wheel] + direction * (2 if both else 1)) % 4
            new = QUAD[phases[wheel]]
            base = 6 + 2 * wheel
            for pin, (was, now) in enumerate(zip(old, new)):
                if was != now:
                    changes.append((t_us, base + pin, now))
        out.append((changes, t_us + 1))
        t_us += 1
    return out


def run(block, batches, pops, walked: bool, monkeypatch) -> list:
    if walked:
        monkeypatch.undo()
    else:
        monkeypatch.setattr(walk_module, "walk", lambda block, t_us, changes, i=0: i)
    seen = []
    for (changes, t_end), pop in zip(batches, pops):
        block.advance(t_end, changes)
        seen.append(snapshot(block))
        for sm_id in (0, 1):  # (the firmware takes words, as PioHost.transfer does)
            rx = block.sm(sm_id).rx
            for _ in range(min(pop, len(rx))):
                rx.popleft()
        if pop:
            block.touch()
    return seen


move = st.tuples(st.integers(1, 300), st.integers(0, 1), st.sampled_from([1, -1]), st.booleans())


@settings(max_examples=60, deadline=None)
@given(
    st.lists(st.lists(move, min_size=0, max_size=40), min_size=1, max_size=8),
    st.lists(st.integers(0, 4), min_size=8, max_size=8),
)
def test_a_walked_batch_leaves_the_block_as_the_step_by_step_path_does(moves, pops):
    with pytest.MonkeyPatch.context() as monkeypatch:
        batches = batches_of(moves)
        slow = run(blocks(), batches, pops, False, monkeypatch)
        fast = run(blocks(), batches, pops, True, monkeypatch)
    assert fast == slow


@settings(max_examples=30, deadline=None)
@given(st.lists(st.tuples(st.integers(1, 200), st.integers(0, 1)), min_size=1, max_size=200), st.integers(1, 50))
def test_a_uart_receiver_walked_or_stepped_ends_the_same(levels, batch):
    changes, t_us = [], 0
    for gap_us, level in levels:
        t_us += gap_us
        changes.append((t_us, 3, level))
    results = []
    for walked in (False, True):
        with pytest.MonkeyPatch.context() as monkeypatch:
            if not walked:
                monkeypatch.setattr(walk_module, "walk", lambda block, t_us, changes, i=0: i)
            block, sm = machine("uart_rx", 125_000 * 8, pinctrl(in_base=3))
            block.set_input(3, 1)
            for start in range(0, len(changes), batch):
                window = changes[start : start + batch]
                block.advance(window[-1][0] + 1, window)
            results.append((snapshot(block), list(sm.rx)))
    assert results[0] == results[1]


def test_the_walk_takes_the_decoders_edges_from_the_table():
    """After the first stretches are in the table, a batch is walked, not stepped."""
    block = blocks()
    batches = batches_of([[(100, k % 2, 1, False) for k in range(200)]] * 5)
    calls = []
    original = walk_module.walk

    def counted(block, t_us, changes, i=0):
        done = original(block, t_us, changes, i)
        calls.append(min(done, len(changes)) - i)
        return done

    walk_module.walk = counted
    steps = []
    try:
        for changes, t_end in batches:
            block.advance(t_end, changes)
            steps.append(block.steps)
    finally:
        walk_module.walk = original
    assert calls[-3:] == [200, 200, 200], calls
    # (a batch's end 1 µs after its last edge falls inside that edge's stretch: a few steps)
    assert steps[-1] - steps[-4] <= 3 * 20, f"instructions stepped in walked batches: {steps}"


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.lists(st.integers(1, 40), min_size=0, max_size=30), min_size=1, max_size=6),
    st.lists(st.integers(0, 4), min_size=6, max_size=6),
)
def test_a_polling_loop_with_delays_walked_or_stepped_ends_the_same(gaps, pops):
    prog = _pioasm.asm_pio()(poll_counter)
    seen = []
    for walked in (False, True):
        with pytest.MonkeyPatch.context() as monkeypatch:
            if not walked:
                monkeypatch.setattr(walk_module, "walk", lambda block, t_us, changes, i=0: i)
            block = PioBlock()
            block.load(list(prog[0]))
            sm = block.init(0, PioConfig(prog[3] | 5 << 24, prog[4], 0, 256 * 25, 0), 0)  # 5 MHz, jmp_pin GP5
            block.set_active(0, True, 0)
            t_us, level, out = 0, 0, []
            for batch, pop in zip(gaps, pops):
                changes = []
                for gap in batch:
                    t_us, level = t_us + gap, 1 - level
                    changes.append((t_us, 5, level))
                block.advance(t_us + 1, changes)
                out.append((snapshot(block), list(sm.rx)))
                for _ in range(min(pop, len(sm.rx))):
                    sm.rx.popleft()
                if pop:
                    block.touch()
                t_us += 1
            seen.append(out)
    assert seen[0] == seen[1]


def machine_state(block) -> tuple:
    """What a block's next cycles and the plant see (not how it got there: steps, tables)."""
    runs = [(sm_id, run.cycle, run.sm.key()) for sm_id, run in sorted(block.running.items())]
    return (block.gpio_in, block.irq_flags, tuple(block.events), runs)


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.lists(move, min_size=0, max_size=12), min_size=1, max_size=12),
    st.lists(st.integers(0, 8), min_size=12, max_size=12),
    st.lists(st.integers(1, 12), min_size=12, max_size=12),
)
def test_a_short_stretch_stepped_leaves_what_its_symbolic_run_leaves(moves, pops, probes_us):
    """A stretch after a change shorter than ``SHORT_CYCLES`` is stepped, not run with X and
    Y as symbols (a read's 1 µs probe, a batch ending just after its edge): the block is where
    the symbolic run leaves it, at every batch end and every probe instant."""
    batches = [  # (the moves' gaps an eighth as long: stretches of a few cycles)
        ([(t // 8 + 1, gpio, level) for t, gpio, level in changes], t_end // 8 + 1)
        for changes, t_end in batches_of(moves)
    ]

    def run_all(short: int) -> list:
        with pytest.MonkeyPatch.context() as monkeypatch:
            monkeypatch.setattr(block_module, "SHORT_CYCLES", short)
            block, seen, t_end = blocks(), [], 0
            for (changes, end), pop, probe_us in zip(batches, pops, probes_us):
                changes = [(max(t, t_end), gpio, level) for t, gpio, level in changes]
                t_end = max(t_end, end, *(t for t, _g, _l in changes))
                block.advance(t_end, changes)
                seen.append(machine_state(block))
                for sm_id in (0, 1):
                    rx = block.sm(sm_id).rx
                    for _ in range(min(pop, len(rx))):
                        rx.popleft()
                if pop:
                    block.touch()
                t_end += probe_us  # (a read's probe: time on, pins as they are)
                block.advance(t_end)
                seen.append(machine_state(block))
            return seen

    assert run_all(64) == run_all(0)


def stepped(block, run, c_end: int) -> None:
    """``run_cycles`` as plain single steps: no table, no loop skipped (the reference)."""
    sm, c = run.sm, run.cycle
    block._run = run
    try:
        while c < c_end:
            block._cycle = c
            c += sm.step()
    finally:
        block._run = None
    run.cycle = max(run.cycle, c)


@settings(max_examples=40, deadline=None)
@given(
    st.lists(st.lists(move, min_size=0, max_size=10), min_size=1, max_size=10),
    st.lists(st.integers(0, 8), min_size=10, max_size=10),
    st.lists(st.lists(st.integers(1, 12), min_size=1, max_size=4), min_size=10, max_size=10),
    st.booleans(),
)
def test_a_stretch_run_past_its_instant_and_put_back_leaves_what_single_steps_leave(moves, pops, probes, poll):
    """A stretch run with symbols past the instant asked for, to its loop, then put back at
    that instant from the states it went through (``block._stretch``, ``AHEAD_CYCLES``; a
    decoder's FIFO refilled after a read, probed 1 µs on): at every batch end and every probe
    instant the block is where single steps leave it, for two decoders and a polling loop with
    delays, edges a few cycles to hundreds of µs apart, the FIFO drained between batches."""
    batches = [  # (some gaps an eighth as long: stretches of a few cycles)
        ([(t // 8 + 1, gpio, level) for t, gpio, level in changes], t_end // 8 + 1)
        for changes, t_end in batches_of(moves)
    ]

    def make():
        if not poll:
            return blocks()
        prog = _pioasm.asm_pio()(poll_counter)
        block = PioBlock()
        block.load(list(prog[0]))
        block.init(0, PioConfig(prog[3] | 6 << 24, prog[4], 0, 256 * 25, 0), 0)  # 5 MHz, jmp_pin GP6
        block.set_active(0, True, 0)
        return block

    def run_all(reference: bool) -> list:
        with pytest.MonkeyPatch.context() as monkeypatch:
            if reference:
                monkeypatch.setattr(walk_module, "walk", lambda block, t_us, changes, i=0: i)
                monkeypatch.setattr(block_module, "run_cycles", stepped)
            block, seen, t_end = make(), [], 0
            for (changes, end), pop, probe in zip(batches, pops, probes):
                changes = [(max(t, t_end), gpio, level) for t, gpio, level in changes]
                t_end = max(t_end, end, *(t for t, _g, _l in changes))
                block.advance(t_end, changes)
                seen.append(machine_state(block))
                for sm_id in block.running:
                    rx = block.sm(sm_id).rx
                    for _ in range(min(pop, len(rx))):
                        rx.popleft()
                if pop:
                    block.touch()
                for probe_us in probe:  # (a read's probes: time on, pins as they are)
                    t_end += probe_us
                    block.advance(t_end)
                    seen.append(machine_state(block))
            return seen

    tabled, reference = run_all(False), run_all(True)
    assert tabled == reference, "expected the block where single steps leave it at every instant (tabled, stepped)"

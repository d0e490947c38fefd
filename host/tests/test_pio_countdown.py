# ruff: noqa: F821  (a PIO body's names exist only while rp2.asm_pio assembles it)
"""A counting loop jumped over (sim_plant/pio/block.py, ``_count_down``; docs/shim.md,
"PIO", cost): the same pin waveforms, IRQs, FIFO contents and registers at the same
instants as stepping each instruction, for the corpus' programs and the kits' (Kitronik's
servo PWM, the kitbot quadrature decoder), under any pins, puts and reads; and a 20 ms
servo period costs a few dozen steps, not 40,000."""

import sys

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from host.core.paths import REPO
from host.tests import pio_corpus
from sim_plant.pio import PioBlock, PioConfig
from sim_plant.pio import block as block_module

sys.path.insert(0, str(REPO / "host" / "shim"))
import _pioasm  # noqa: E402

SYS_HZ = 125_000_000
OUT_LOW = 2


def count_pair():
    """A loop counting X down against Y, with a delay, a pin read and a push each time X
    meets Y: guards on X == 0 and X == Y, a drive only at the meeting."""
    pull(block)
    mov(x, osr)
    set(y, 7)
    label("loop")
    jmp(x_not_y, "skip")[2]
    in_(pins, 1).side(1)
    push(noblock).side(0)
    label("skip")
    jmp(x_dec, "loop")
    irq(0)


def count_up():
    """X counted up as ~(~X - 1) (no drive): the counter in X is inverted each pass."""
    pull(block)
    mov(x, invert(osr))
    label("up")
    mov(x, invert(x))
    mov(x, invert(x))[1]
    jmp(x_dec, "up")


def servo_side_each():
    """A servo program whose every instruction side-sets the pin (each pass drives it, to
    the level it has): 20,000 passes a period, more than the emulator remembers."""
    pull(noblock).side(0)
    mov(x, osr).side(0)
    mov(y, x).side(1)
    label("high")
    jmp(y_dec, "high").side(1)
    mov(y, isr).side(0)
    label("low")
    jmp(y_dec, "low").side(0)


PROGRAMS = {
    **{name: (body, opts) for name, (body, opts, _text) in pio_corpus.CORPUS.items()},
    "count_pair": (count_pair, {"sideset_init": OUT_LOW}),
    "count_up": (count_up, {}),
    "servo_side_each": (servo_side_each, {"sideset_init": OUT_LOW}),
}
FREQS = [125_000_000, 2_000_000, 1_000_000]


def kits_programs():
    """The kits' programs: Kitronik's servo PWM (from the pinned library, when fetched) and
    the kitbot package's quadrature decoder."""
    out = {}
    lib = REPO / "build" / "drivers" / "kitronikpicoautonomousroboticsplatform-1.0.0" / "PicoAutonomousRobotics.py"
    if lib.is_file():
        text = lib.read_text()
        start = text.index("    def _servo_pwm():")
        end = text.index("    #doesnt actually register")
        body = "\n".join(line[4:] for line in text[start:end].splitlines())
        space = {}
        exec(compile(body, str(lib), "exec"), space)  # (the body's names exist only while asm_pio assembles it)
        out["kitronik_servo"] = (space["_servo_pwm"], {"sideset_init": OUT_LOW})
    kit = (REPO / "hil_tests" / "firmware" / "kitbot" / "lib" / "kitbot" / "encoders.py").read_text()
    start = kit.index("def _quadrature():")
    end = kit.index("class _Counter")
    space = {}
    exec(compile(kit[start:end], "encoders.py", "exec"), space)
    out["kitbot_quadrature"] = (space["_quadrature"], {"in_shiftdir": 0, "out_shiftdir": 1, "fifo_join": 2})
    return out


PROGRAMS.update(kits_programs())


def build(name, freq_hz, pins: int, isr_word: int) -> PioBlock:
    body, opts = PROGRAMS[name]
    prog = _pioasm.asm_pio(**opts)(body)
    block = PioBlock()
    block.load(list(prog[0]))
    div = SYS_HZ / freq_hz
    div256 = int(div) * 256 + int((div - int(div)) * 256)
    side = 2 if prog[3] >> 30 & 1 else 1
    pinctrl = side << 29 | 3 << 26 | 4 << 20 | 4 << 15 | 10 << 10 | 12 << 5 | 0
    sm = block.init(0, PioConfig(prog[3], prog[4], pinctrl, div256, 0), 0)
    for gpio in range(16):
        block.set_input(gpio, pins >> gpio & 1)
    sm.tx.append(isr_word)  # (as the kits' servo classes preload ISR: put, exec pull, exec mov isr, osr)
    sm.pending_exec = _pioasm.asm_pio_encode("pull()", 0)
    sm.step()
    sm.pending_exec = _pioasm.asm_pio_encode("mov(isr, osr)", 0)
    sm.step()
    block.set_active(0, True, 0)
    return block


def snapshot(block) -> tuple:
    run = block.running[0]
    return run.cycle, run.sm.key(), list(block.events), list(block.irqs), dict(block.levels), dict(block.dirs)


def play(name, freq_hz, pins, isr_word, ops, counting: bool, monkeypatch) -> tuple[list, int]:
    monkeypatch.setattr(block_module, "COUNTDOWN", counting)
    block = build(name, freq_hz, pins, isr_word)
    sm = block.sm(0)
    t, shots = 0, []
    for op, a, b in ops:
        if op == "advance":
            t += a
            block.advance(t)
        elif op == "pin":
            t += a
            block.advance(t, [(t, b, 1 - (block.gpio_in >> b & 1))])
        elif op == "put":
            if len(sm.tx) < sm.tx_depth:
                sm.tx.append(a)
            block.touch()
        else:
            if sm.rx:
                sm.rx.popleft()
            block.touch()
        shots.append(snapshot(block))
    return shots, block.steps


OPS = st.lists(
    st.one_of(
        st.tuples(st.just("advance"), st.integers(1, 3_000), st.just(0)),
        st.tuples(st.just("pin"), st.integers(1, 500), st.integers(0, 15)),
        st.tuples(st.just("put"), st.integers(0, 600), st.just(0)),
        st.tuples(st.just("pop"), st.just(0), st.just(0)),
    ),
    min_size=1,
    max_size=25,
)


@pytest.mark.parametrize("name", sorted(PROGRAMS))
@settings(max_examples=10, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(freq=st.sampled_from(FREQS), pins=st.integers(0, 0xFFFF), isr_word=st.integers(0, 700), ops=OPS)
def test_counting_loops_jumped_over_leave_what_single_steps_leave(name, freq, pins, isr_word, ops, monkeypatch):
    fast, _ = play(name, freq, pins, isr_word, ops, True, monkeypatch)
    slow, _ = play(name, freq, pins, isr_word, ops, False, monkeypatch)
    for i, (a, b) in enumerate(zip(fast, slow)):
        assert a == b, f"{name} at {freq} Hz, after op {i} {ops[i]}: jumped over {a}, stepped {b}"


def test_a_kitronik_servo_period_costs_a_few_dozen_steps(monkeypatch):
    """Four servo state machines at 2 MHz, 1.5 ms pulses every 20 ms (Kitronik's PWM
    program): each pulse where stepping puts it, for a few dozen steps a period where
    stepping takes 40,000."""
    if "kitronik_servo" not in PROGRAMS:
        pytest.skip("the pinned Kitronik library is not fetched (python -m host.core.drivers)")
    ops = [("put", 1500, 0)] + [("advance", 10_000, 0)] * 20
    fast, fast_steps = play("kitronik_servo", 2_000_000, 0, 20_000, ops, True, monkeypatch)
    slow, slow_steps = play("kitronik_servo", 2_000_000, 0, 20_000, ops, False, monkeypatch)
    assert fast == slow, "the jumped-over waveform differs from the stepped one"
    events = fast[-1][2]
    rises = [t for t, g, level in events if g == 10 and level == 1]
    falls = [t for t, g, level in events if g == 10 and level == 0 and t > rises[0]]
    highs = [f - r for r, f in zip(rises, falls)]
    assert len(rises) >= 9 and all(abs(h - 1500) < 2 for h in highs), (rises, highs)
    assert fast_steps * 100 < slow_steps, f"jumped over: {fast_steps} steps; stepped: {slow_steps}"


@pytest.mark.parametrize(
    "name, counting", [("kitronik_servo", True), ("servo_side_each", True), ("servo_side_each", False)]
)
def test_a_servo_waveform_is_a_pwm_to_the_plant_however_long_its_period(name, counting, monkeypatch):
    """host/rig/hardware/pio_out.py: a 20 ms servo period is given as a PWM (50 Hz, a 1.5 ms pulse's
    duty), whether the emulator sees it repeat (its counting loops jumped over) or only
    measures it (stepped: the period too long to be seen coming back)."""
    monkeypatch.setattr(block_module, "COUNTDOWN", counting)
    from host.rig.hardware.pio_out import look_ahead, pwm_of

    if name not in PROGRAMS:
        pytest.skip("the pinned Kitronik library is not fetched (python -m host.core.drivers)")
    freq, pulse = (2_000_000, 1500) if name == "kitronik_servo" else (1_000_000, 1500 - 2)
    low = 20_000 if name == "kitronik_servo" else 20_000 - 6 - pulse
    block = build(name, freq, 0, low)
    block.sm(0).tx.append(pulse)
    block.advance(5)
    events, periodic = look_ahead(block, 0, 5)
    pwm = pwm_of([(t, level) for t, g, level in events if g == 10])
    assert periodic and pwm is not None, f"{name}: not seen as a waveform; its drives: {events[:8]}"
    freq_hz, duty = pwm
    assert freq_hz == 50 and abs(duty / 65535 * 20_000 - 1500) < 2, f"{name}: expected 50 Hz, 1500 µs; got {pwm}"

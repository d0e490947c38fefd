"""What a PIO state machine drives, given to the plant (``docs/shim.md``, "PIO").

The host runs the PIO lazily, at the firmware's frames; a pin it drives must reach the
plant at its own instants, before the firmware's next frame. After each frame,
:class:`PioOutputs` looks ahead on a copy of the block (the pins it reads staying as they
are, no more FIFO accesses) until the state machine is quiet (stalled, or looping without
driving anything) or repeats what it drives (a waveform), and gives the plant what the
pins it drives will carry, in the terms the plant's parts take:

- a pin that repeats a period (PWM, servo pulses): a PWM at that frequency and duty, to
  1 Hz and 1/65535, as a ``machine.PWM`` gives it: the waveform to an input of kind
  ``pwm`` (``set_pwm``: a wire), the duty_u16 to one of kind ``duty`` (a servo's pulse, a
  motor's speed);
- a burst of pulses ending quiet, on a ``ws2812_strip``'s ``.din``: its bits as a
  bitstream with the pulses' measured timing (``bitstream``);
- a burst on a UART wire: the bytes its frames carry at ``freq / 8`` baud (8 PIO cycles
  a bit, as the public PIO UART programs do), sent from their start bit (``send_bytes``);
- on an input the plant takes edge by edge (``plant.timed_inputs``: a clocked serial
  chip's clock and data), each level at its cycle's instant (``LevelAt``);
- else the level the burst ends on, at the frame's instant; on an io line (a part drives
  it too: ``wiring.shared``) a pin the program makes an input (``set``/``out pindirs``,
  side-set pindirs) lets the line go at that cycle's instant (``ReleasedAt``: an RC sensor
  times its discharge from it), after the level it drove before, if any; on a line only the
  board drives, a pin made an input leaves the part's input as it was (as ``Pin.IN``).

Lookahead costs what the emulator costs over the burst; a burst already given is not
given again (each pin keeps the instant up to which the plant has it).
"""

from host.link import frames as F
from sim_plant.pio.block import RELEASED
from sim_plant.plant import BITSTREAM, LevelAt, ReleasedAt

HORIZON_US = 200_000  # the longest burst looked at (a WS2812 strip of ~6000 LEDs)


def driven_pins(sm) -> set[int]:
    pins = {(sm.set_base + i) & 31 for i in range(sm.set_count)}
    pins |= {(sm.out_base + i) & 31 for i in range(sm.out_count)}
    pins |= {(sm.side_base + i) & 31 for i in range(sm.side_bits)}
    return pins


def look_ahead(block, local: int, t_us: int):
    """(events, periodic) of state machine ``local`` from ``t_us`` on a copy of ``block``:
    its drives until it is quiet or repeats a waveform (``periodic``: True), at most
    :data:`HORIZON_US` ahead (then periodic when the pins' last periods are alike:
    :func:`steady`)."""
    twin = block.fork()
    twin.events.clear()
    twin.record_events = True
    run = twin.running[local]
    run.drive_period = 0
    step_us = 50
    t = t_us
    while t < t_us + HORIZON_US:
        t = min(t_us + HORIZON_US, t + step_us)
        twin.advance(t)
        if run.drive_period:
            return twin.events, True
        if run.orbit and run.orbit_version == twin.version:
            return twin.events, False
        step_us *= 2
    return twin.events, steady(twin.events, driven_pins(run.sm))


def steady(events: list, pins: set[int]) -> bool:
    """Still driving at the horizon, a period too long for the emulator to see it come back
    (more loop passes than it remembers: :data:`sim_plant.pio.block.SEEN_MAX`): a waveform
    all the same, when every pin it drives that moves has its last three periods and pulses
    alike (to 1 ns)."""
    moving = False
    for gpio in pins:
        levels = [(t, level) for t, g, level in events if g == gpio]
        if not levels:
            continue
        rises = [t for t, level in levels if level == 1][-4:]
        falls = [t for t, level in levels if level == 0 and t > rises[0]] if len(rises) == 4 else []
        if len(falls) < 3:
            return False
        periods = [b - a for a, b in zip(rises, rises[1:])]
        highs = [f - r for r, f in zip(rises, falls)]
        if max(periods) - min(periods) > 1e-3 or max(highs) - min(highs) > 1e-3:
            return False
        moving = True
    return moving


class PioOutputs:
    """The plant's side of the pins PIO drives, for one rig."""

    def __init__(self, plant, wiring):
        self.plant = plant
        self.wiring = wiring
        self.given_us: dict[int, float] = {}  # gpio -> the instant up to which the plant has its level
        self.pwm: dict[int, tuple] = {}  # gpio -> the (freq_hz, duty_u16) the plant has

    def signal_of(self, gpio: int) -> str | None:
        for key in (str(gpio), f"GP{gpio}"):
            signal = self.wiring.signal_of(key)
            if signal is not None:
                return signal
        return None

    def after(self, block, t_us: int) -> None:
        """After a frame at ``t_us``: what each active state machine will drive, to the plant."""
        inputs = self.plant.inputs
        for local, run in block.running.items():
            if not run.active:
                self._stopped(block, run.sm)
                continue
            wired = {g: s for g in driven_pins(run.sm) if (s := self.signal_of(g)) is not None and s in inputs}
            if not wired:
                continue
            events, periodic = look_ahead(block, local, t_us)
            freq_hz = run.sm.config.freq_hz
            for gpio, signal in wired.items():
                mine = [(t, level) for t, g, level in events if g == gpio and t > self.given_us.get(gpio, -1.0)]
                pwm = pwm_of(mine) if periodic else None
                kind = inputs.get(signal)
                if pwm is not None and kind in (F.SIG_PWM, F.SIG_DUTY):
                    if self.pwm.get(gpio) != pwm:  # (a PWM given again would restart its period)
                        self._give_pwm(signal, kind, *pwm)
                        self.pwm[gpio] = pwm
                elif mine:
                    self.pwm.pop(gpio, None)
                    self._give(signal, inputs.get(signal), mine, freq_hz)
                    self.given_us[gpio] = mine[-1][0]

    def _stopped(self, block, sm) -> None:
        """A stopped state machine's pins hold their level: a PWM given for one stops there."""
        for gpio in driven_pins(sm) & set(self.pwm):
            freq_hz, _duty = self.pwm.pop(gpio)
            signal = self.signal_of(gpio)
            self._give_pwm(signal, self.plant.inputs.get(signal), freq_hz, 65535 if block.levels.get(gpio) else 0)

    def _give_pwm(self, signal: str, kind, freq_hz: int, duty_u16: int) -> None:
        """A waveform as a machine.PWM on that pin gives it (``host/rig/hardware/peripherals.py``,
        ``PwmPeripheral.out``): the waveform to a ``pwm`` input, its duty_u16 to a ``duty``
        one (a servo's pulse, a motor's speed)."""
        if kind == F.SIG_PWM:
            self.plant.set_pwm(signal, freq_hz, duty_u16)
        else:
            self.plant.set_input(signal, duty_u16)

    def clear(self) -> None:
        self.given_us.clear()
        self.pwm.clear()

    def _give(self, signal: str, kind, levels: list, freq_hz: float) -> None:
        plant = self.plant
        if levels[-1][1] == RELEASED and kind == F.SIG_LEVEL and signal in self.wiring.shared:
            driven = [level for _t, level in levels if level != RELEASED]
            if driven:  # (a charge, then the line let go at its cycle, after the frame's instant)
                plant.set_input(signal, driven[-1])
            plant.set_input(signal, ReleasedAt(levels[-1][0]))
            return
        levels = [(t, level) for t, level in levels if level != RELEASED]
        if not levels:  # (a line only the board drives: a pin made an input leaves it as it was)
            return
        if signal in plant.timed_inputs:  # (a clocked chip: each edge at its cycle's instant)
            for t, level in levels:
                plant.set_input(signal, LevelAt(level, t))
            return
        if kind == F.SIG_UART:
            data = uart_bytes(levels, 1e6 * 8 / freq_hz)
            if data:
                plant.send_bytes(signal, data, round(freq_hz / 8))
            return
        stream = bitstream_of(levels)
        if stream is not None and BITSTREAM in plant.capabilities:
            plant.bitstream(signal, *stream)
        plant.set_input(signal, levels[-1][1])


def pwm_of(levels: list) -> tuple[int, int] | None:
    """(freq_hz, duty_u16) of a repeating waveform from its last rise, fall and rise."""
    rises = [t for t, level in levels if level == 1]
    if len(rises) < 2:
        return None
    r1, r2 = rises[-2], rises[-1]
    falls = [t for t, level in levels if level == 0 and r1 < t < r2]
    if not falls or r2 <= r1:
        return None
    period_us = r2 - r1
    return round(1e6 / period_us), round((falls[0] - r1) / period_us * 65535)


def bitstream_of(levels: list) -> tuple[tuple, bytes] | None:
    """A burst of pulses as (timing_ns (high_0, low_0, high_1, low_1), bytes): each rise to
    the next a bit, a high longer than half of it a 1; None for fewer than 8 pulses. A
    burst with no 0 (or no 1) has None for that bit's high and low: nothing measured them
    (a PIO strip's frame of black, or of white, is bursts of one kind of bit)."""
    rises = [i for i, (_t, level) in enumerate(levels) if level == 1]
    bits, highs = [], []
    for a, b in zip(rises, rises[1:] + [None]):
        t_rise = levels[a][0]
        if a + 1 >= len(levels):
            break
        t_fall = levels[a + 1][0]
        t_next = levels[b][0] if b is not None else t_rise + (highs[-1][1] if highs else 2 * (t_fall - t_rise))
        period = t_next - t_rise
        high = t_fall - t_rise
        highs.append((high, period))
        bits.append(1 if high > period / 2 else 0)
    if len(bits) < 8:
        return None
    timing = ()
    for bit in (0, 1):
        shapes = [(h, p) for (h, p), b in zip(highs, bits) if b == bit]
        timing += (round(shapes[0][0] * 1000), round((shapes[0][1] - shapes[0][0]) * 1000)) if shapes else (None, None)
    data = bytes(int("".join(map(str, bits[i : i + 8])), 2) for i in range(0, len(bits) - 7, 8))
    return timing, data


def uart_bytes(levels: list, bit_us: float) -> bytes:
    """The bytes of 8N1 frames on a line idling high: from each falling start edge, each bit
    sampled in its middle."""

    def level_at(t):
        level = 1
        for te, lv in levels:
            if te > t:
                break
            level = lv
        return level

    out, i = [], 0
    while i < len(levels):
        t_start, level = levels[i]
        if level != 0:
            i += 1
            continue
        out.append(sum(level_at(t_start + (1.5 + k) * bit_us) << k for k in range(8)))
        t_end = t_start + 9.5 * bit_us
        while i < len(levels) and levels[i][0] < t_end:
            i += 1
    return bytes(out)

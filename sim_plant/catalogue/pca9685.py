"""Part ``pca9685``: an NXP PCA9685-class 16-channel, 12-bit PWM expander on I2C (address
0x40 to 0x7F by its A0..A5 pins; 0x40 by default) whose channels drive other parts' inputs
(``drives``: channel 0 first, ``-`` for a channel that drives nothing): a servo's ``.pwm``,
a motor bridge's ``.pwm``, ``.in1``, ``.in2``.

Modelled registers: MODE1 (0x00: resets to 0x11, SLEEP stops the oscillator and every
output, AI turns register auto-increment on; RESTART reads back 0), MODE2 (0x01, plain),
LEDn_ON_L..LEDn_OFF_H (0x06 + 4n: 12-bit on and off counts, bit 4 of ON_H full on, bit 4
of OFF_H full off, which wins), ALL_LED_ON/OFF (0xFA..0xFD: written to every channel,
read as 0), PRE_SCALE (0xFE: resets to 0x1E, written only while SLEEP is set, below 3
read as 3). The PWM frequency is the datasheet's ``osc_hz / (4096 * (PRE_SCALE + 1))``.
The outputs change at the end of the write (MODE2's OCH = 0: at the stop). A channel
drives its input as a board PWM would: a ``duty`` input gets the pulse width it makes
(as a duty_u16 at that part's own PWM frequency when it has one: a servo's ``freq_hz``;
else the duty fraction), a ``level`` input 1 while the duty is at least a half. The truth
has ``<name>_ch<n>_pulse_us`` for each channel that drives an input.

Not modelled: ``NOT_MODELLED`` (docs/parts.md)."""

from sim_plant.buses import BusName, RegisterDevice, check_placement
from sim_plant.catalogue.base import Build, Opt, PartType
from sim_plant.option_table import Name, Num, Rows

MODE1, MODE2, LED0, ALL_LED, PRE_SCALE = 0x00, 0x01, 0x06, 0xFA, 0xFE
SLEEP, AI, RESTART = 0x10, 0x20, 0x80
CHANNELS = 16
COUNTS = 4096
DUTY_FULL = 65535
NO_TARGET = "-"


class Pca9685Chip(RegisterDevice):
    """The register file and the 16 outputs. ``pending`` holds the (input, duty fraction,
    period_us) changes the plant passes on at the end of a transfer."""

    RESET = {MODE1: 0x11, MODE2: 0x04, PRE_SCALE: 0x1E}
    MODELLED = {
        MODE1: "MODE1: SLEEP, AI (RESTART reads 0)",
        MODE2: "MODE2 (plain: OUTDRV, INVRT, OCH not modelled)",
        **{reg: "LEDn_ON/OFF" for reg in range(LED0, LED0 + 4 * CHANNELS)},
        **{reg: "ALL_LED_ON/OFF (to every channel)" for reg in range(ALL_LED, PRE_SCALE)},
        PRE_SCALE: "PRE_SCALE (written while SLEEP, at least 3)",
    }
    FIXED_STATE = (*RegisterDevice.FIXED_STATE, "targets", "osc_hz")

    def __init__(self, name, bus, address, targets: tuple, osc_hz: float):
        super().__init__(name, bus, address)
        self.targets = targets
        self.osc_hz = float(osc_hz)
        self.driven = [(0.0, 0.0)] * CHANNELS  # each channel's (duty, period_us) as last passed on
        self.pending = []

    def next_register(self, reg):
        return (reg + 1) & 0xFF if self.regs[MODE1] & AI else reg

    def load(self, t_us, reg):
        if reg == MODE1:
            return self.regs[MODE1] & ~RESTART & 0xFF
        if reg == PRE_SCALE:
            return max(3, self.regs[PRE_SCALE])
        if ALL_LED <= reg < PRE_SCALE:
            return 0
        return self.regs[reg]

    def store(self, t_us, reg, value):
        value &= 0xFF
        if reg == PRE_SCALE:
            if self.regs[MODE1] & SLEEP:
                self.regs[PRE_SCALE] = value
        elif ALL_LED <= reg < PRE_SCALE:
            for ch in range(CHANNELS):
                self.regs[LED0 + 4 * ch + reg - ALL_LED] = value
        else:
            self.regs[reg] = value

    def end(self, t_us):
        self._update()

    def period_us(self) -> float:
        return 1e6 * COUNTS * (max(3, self.regs[PRE_SCALE]) + 1) / self.osc_hz

    def fraction(self, ch: int) -> float:
        """Channel ``ch``'s duty (0..1): full off wins over full on; asleep, off."""
        r = self.regs
        base = LED0 + 4 * ch
        if r[MODE1] & SLEEP or r[base + 3] & 0x10:
            return 0.0
        if r[base + 1] & 0x10:
            return 1.0
        on = r[base] | (r[base + 1] & 0x0F) << 8
        off = r[base + 2] | (r[base + 3] & 0x0F) << 8
        return ((off - on) % COUNTS) / COUNTS

    def _update(self) -> None:
        period_us = self.period_us()
        for ch, target in enumerate(self.targets):
            if target == NO_TARGET:
                continue
            now = (self.fraction(ch), period_us)
            if now != self.driven[ch]:
                self.driven[ch] = now
                self.pending.append((target, *now))

    def pass_on(self, plant) -> None:
        while self.pending:
            name, share, period_us = self.pending.pop(0)
            plant.set_input(name, duty_for(plant.inputs[name], plant.input_owner(name), share, period_us))

    def truth(self, t_us, plant) -> dict:
        period_us = self.period_us()
        truth = {f"{self.label}_freq_hz": 1e6 / period_us}
        for ch, target in enumerate(self.targets):
            if target != NO_TARGET:
                truth[f"{self.label}_ch{ch}_pulse_us"] = self.fraction(ch) * period_us
        return truth


def duty_for(kind: str, part, share: float, period_us: float) -> int:
    """What a channel at duty ``share`` of ``period_us`` sets an input of ``kind`` of
    ``part`` to (a board's PWM value: duty_u16 at that part's own period, if it has one)."""
    if kind == "level":
        return int(share >= 0.5)
    motion = getattr(part, "motion", None)
    own_period_us = getattr(motion, "period_us", None)
    if own_period_us and 0.0 < share < 1.0:
        share = share * period_us / own_period_us
    return max(0, min(DUTY_FULL, round(share * DUTY_FULL)))


class Pca9685(PartType):
    CHIP = Pca9685Chip  # (its registers: docs/parts.md)
    kind = "pca9685"
    MODELLED_FEATURES = (
        "16 channels of 12-bit on/off counts, full on and full off, at osc_hz / (4096 (PRE_SCALE + 1))",
        "MODE1's SLEEP, AI and RESTART; ALL_LED; each channel driving another part's input as a board's PWM would",
    )
    NOT_MODELLED = (
        "the output delay (ON counts other than 0 only shift the pulse)",
        "MODE2's inverted and open-drain outputs",
        "OE",
        "EXTCLK",
        "the sub-addresses and the all-call address",
        "the software reset general call",
    )
    doc = "A PCA9685-class 16-channel 12-bit PWM expander on I2C whose channels drive servos and motor bridge inputs."
    OPTIONS = (
        Opt("bus", BusName(), "i2c0", "the bus it is on, as the firmware creates it"),
        Opt("address", Num("", 0, 127, whole=True), 0x40, "its 7-bit I2C address (0x40 + its A0..A5 pins)"),
        Opt(
            "drives",
            Rows(Name(), most=CHANNELS),
            [],
            "the input each channel drives, channel 0 first ('pan.pwm', 'motor_l.in1'; '-': none)",
        ),
        Opt("osc_hz", Num("hertz", 1e6, 50e6), 25e6, "its oscillator (the internal one: 25 MHz)"),
    )
    SIGNALS = ()
    TRUTH = ("{name}_freq_hz",)  # (and {name}_ch<n>_pulse_us for each channel that drives an input)
    VIEWS = ()  # (what its channels do shows in the views of the parts they drive: a servo's angle)
    on_bus = True

    def check(self) -> None:
        check_placement(self.options, "the PCA9685")
        o = self.options
        taken = [t for t in o["drives"] if t != NO_TARGET]
        twice = sorted({t for t in taken if taken.count(t) > 1})
        if twice:
            raise ValueError(f"drives: expected each input driven by one channel, got {', '.join(twice)} twice")

    def add(self, build: Build) -> None:
        o = self.options
        build.parts.append(Pca9685Chip(self.name, o["bus"], o["address"], tuple(o["drives"]), o["osc_hz"]))

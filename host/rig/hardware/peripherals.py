"""The host side of each peripheral kind the shim has: one handler class per CFG kind,
registered in :data:`HANDLERS`, as the shim's ``machine.Pin``, ``ADC``, ``PWM`` and
``UART`` are one class each (``host/shim/machine.py``).

A handler owns what its kind means to the host:

- **CFG**: the handle it makes (an IRQ: the handle it arms), whether the firmware reads
  it (the shim syncs after configuring an input, and the host gives its first value), and
  the wiring it refuses (an output on a line the plant drives, an ADC on a logic level);
- **inputs**: how a plant change reaches a handle of its kind in the next STATE (a level,
  an ADC sample, UART bytes), and whether it fires an IRQ or wakes a watched wait;
- **outputs**: how an OUT or a UART_TX of its kind reaches the plant, and what it is
  recorded as (a level, a duty, bytes).

:class:`~host.rig.hardware.wiring.Wiring` looks the kind up once, at CFG; the handle keeps its
handler, and :class:`~host.rig.hardware.inputs.Inputs` and :class:`~host.rig.hardware.outputs.Outputs`
call it. Every code is the codec's name (``F.PIN_OUT``, ``F.IRQ_RISING``, ``F.SIG_PWM``).
A bus (I2C, SPI) is a handle too (:class:`BusPeripheral`): its transfers are BUS frames
the rig answers from the plant's devices (``host.rig.loop.messages.on_bus``, ``PartsPlant.bus_transfer``).
``machine.Timer`` has no host side: it runs in the shim's virtual time.
"""

import struct

from host.core.errors import LinkError
from host.link import frames as F
from sim_plant.plant import BITSTREAM, BUSES

FIRED = 1
"""What :meth:`Peripheral.deliver` returns when the change fires an IRQ handler."""
WOKE = 2
"""... when it wakes a watched wait (``time_pulse_us``, a timed UART read)."""

RELEASED = -1
"""A shared line's plant input while the firmware lets it go (its pin an input again, or
open drain and high): the part drives it (``Wiring.shared``, docs/wiring.md)."""

DUTY_FULL = 65535
"""A plant input of kind ``duty`` at 100 % (``duty_u16``): what a pin held high drives it at."""

_RAW_27C = round(0.706 / 3.3 * 4095)  # (876)
CORE_TEMP_27C_U16 = _RAW_27C << 4 | _RAW_27C >> 8
"""What ``ADC(4).read_u16()`` of an rp2 reads with nothing wired to ``CORE_TEMP`` (14019)."""

_LEVEL, _SAMPLE, _BYTES = F.CH_LEVEL, F.CH_SAMPLE, F.CH_BYTES  # (module globals: the hot path's)
_RISING, _FALLING = F.IRQ_RISING, F.IRQ_FALLING


class Peripheral:
    """One kind of shim object, host side. The defaults: takes no input, drives nothing."""

    kind = 0  # its CFG kind
    name = "unconfigured"  # as the link log names it
    lets_go = False  # it may drive a line the plant drives too, in turn (Wiring.shared), and let it go

    def configure(self, wiring, h: int, mode: int, pull: int, key: str, param: int):
        """A CFG of this kind: the handle's new configuration (None: it makes none)."""
        return wiring.attach(self, h, mode, pull, key, param)

    def is_input(self, mode: int) -> bool:
        """The firmware reads it: the shim syncs after its CFG, the host sends its value."""
        return False

    def refuse(self, mode: int, pin: str, board_name: str, signal: str, sensor: str) -> str | None:
        """Why no board survives this on ``signal``, a line the plant drives (``sensor``: its
        kind); None: it does."""
        return None

    def idle(self, info) -> int:
        """What an input wired to no plant output reads."""
        return 0

    def first(self, t_us: int, h: int, info, value: int) -> tuple:
        """The STATE change that gives a just-configured input its value."""
        return (t_us, h, _LEVEL, value, 0)

    def deliver(self, inputs, t_us: int, h: int, info, value, watch) -> int:
        """A change of the plant signal the handle is wired to, queued for the next STATE:
        0, :data:`FIRED` or :data:`WOKE`."""
        return 0

    def unsample(self, info, extra) -> None:
        """A delivered change was rewound: the samples it counted were never taken."""

    def out(self, outputs, t_us: int, info, attr: int, value: int) -> None:
        raise LinkError(f"OUT to {self._what(info)}, which has no outputs (link protocol error)")

    def transmit(self, outputs, t_us: int, info, data: bytes) -> None:
        raise LinkError(f"UART_TX from {self._what(info)}, which is no UART (link protocol error)")

    def _what(self, info) -> str:
        if not self.kind:
            return "a handle the shim never configured"
        return f"{self.name} {info.key}"


def _drives(pin: str, signal: str, board_name) -> str:
    return (
        f"wiring: the firmware drives {pin} as an output, but it is wired to {signal}, which the plant "
        f"drives (a sensor): check the wiring of {board_name} or the firmware's pin number"
    )


class PinPeripheral(Peripheral):
    """``machine.Pin``: a level in (pulled up: 1 when wired to nothing), a level out."""

    kind = F.CFG_PIN
    name = "pin"
    lets_go = True  # (made an input, or open drain and high: the line the plant's again)

    def is_input(self, mode):
        return mode == F.PIN_IN or mode == F.PIN_ALT  # (ALT: a peripheral's; its pad still read)

    def refuse(self, mode, pin, board_name, signal, sensor):
        return _drives(pin, signal, board_name) if mode == F.PIN_OUT else None

    def idle(self, info):
        return 1 if info.pull == F.PULL_UP else 0

    def deliver(self, inputs, t_us, h, info, value, watch):
        inputs.pending.append((t_us, h, _LEVEL, value, 0))
        if h in watch:
            return WOKE
        if info.irq & (_RISING if value else _FALLING):
            inputs.stats.irq_edges += 1
            return FIRED
        return 0

    def out(self, outputs, t_us, info, attr, value):
        if outputs.recorder is not None:
            outputs.record(t_us, info, value, F.SIG_LEVEL)
        last, info.level = info.level, value
        signal = info.signal
        if signal is None:
            return
        plant_inputs = outputs.plant_inputs
        if info.probe or signal in plant_inputs:
            hooks = outputs.level_hooks.get(signal)
            if hooks:
                changed = last is not None and last != value
                for call in hooks:
                    call(t_us, signal, value, changed)
        sig_kind = plant_inputs.get(signal)
        if sig_kind is not None:
            if value and info.mode == F.PIN_OPEN_DRAIN and signal in outputs.wiring.shared:
                value = RELEASED  # (open drain, high: the pad is let go, the part drives the line)
            elif sig_kind == F.SIG_DUTY:
                value = DUTY_FULL if value else 0  # (a pin held high is a PWM at 100 %: a DRV8833's IN1)
            outputs.plant.set_input(signal, value)

    def transfer(self, plant, info, op: int, address: int, n_read: int, data: bytes) -> tuple:
        """``machine.bitstream`` on the pin (BUS_BITSTREAM: the timing, 4 x <I ns, then the
        bytes): the plant part wired to the pin takes the stream (``PartsPlant.bitstream``);
        a pin wired to nothing sends it to nobody."""
        if op != F.BUS_BITSTREAM or len(data) < 16:
            raise LinkError(f"BUS op {op} on {self._what(info)}, which only sends a bitstream (link protocol error)")
        timing_ns = struct.unpack_from("<4I", data, 0)
        if info.signal is not None and BITSTREAM in plant.capabilities:
            plant.bitstream(info.signal, timing_ns, data[16:])
        return F.BUS_OK, len(data) - 16, b""


class AdcPeripheral(Peripheral):
    """``machine.ADC``: each plant value is the handle's next sample (its number counted
    here and in the shim, which reports the first read of each with SEEN)."""

    kind = F.CFG_ADC
    name = "adc"

    def is_input(self, mode):
        return True

    def idle(self, info):
        """rp2's temperature sensor unwired: the die at 27 degrees C, 0.706 V (the RP2040
        datasheet, 4.9.5), as read_u16 scales the 12-bit reading (ports/rp2/machine_adc.c,
        adc_config_and_read_u16); any other input wired to nothing reads 0."""
        return CORE_TEMP_27C_U16 if info.key == "CORE_TEMP" else 0

    def refuse(self, mode, pin, board_name, signal, sensor):
        if sensor != F.SIG_LEVEL:
            return None
        return (
            f"wiring: the firmware reads {pin} with an ADC, but {signal} is a logic level (0/1), not an "
            f"analog signal: wire the pin to a u16 signal, or read it with Pin.value()"
        )

    def first(self, t_us, h, info, value):
        return (t_us, h, _SAMPLE, value, info.samples)  # (an ADC made again keeps its count)

    def deliver(self, inputs, t_us, h, info, value, watch):
        info.samples += 1
        inputs.sampled(info.signal, t_us, info.samples)
        inputs.pending.append((t_us, h, _SAMPLE, value, info.samples))
        return 0

    def unsample(self, info, extra):
        info.samples -= 1


class PwmPeripheral(Peripheral):
    """``machine.PWM``: a duty out (a waveform, with its frequency, to a plant input of kind
    ``pwm``); deinit holds the line low."""

    kind = F.CFG_PWM
    name = "pwm"
    lets_go = True  # (on a shared line: an LED beside a button, the 3pi+ 2040's GP25; deinit lets it go)

    def refuse(self, mode, pin, board_name, signal, sensor):
        return _drives(pin, signal, board_name)

    def out(self, outputs, t_us, info, attr, value):
        signal = info.signal
        plant_inputs = outputs.plant_inputs
        if attr == F.OUT_FREQ:
            info.freq = value
            if info.level and plant_inputs.get(signal) == F.SIG_PWM:
                outputs.plant.set_pwm(signal, value, info.level)
            return
        if outputs.recorder is not None:
            outputs.record(t_us, info, 0 if attr == F.OUT_DEINIT else value, F.SIG_DUTY)
        info.level = value
        sig_kind = plant_inputs.get(signal) if signal is not None else None
        if sig_kind is None:
            return  # a probe, or wired to nothing the plant takes
        duty = value if attr == F.OUT_DUTY else 0  # (deinit: the line held low)
        if sig_kind == F.SIG_PWM:  # the plant takes the waveform
            outputs.plant.set_pwm(signal, info.freq, duty)
        elif sig_kind == F.SIG_LEVEL and signal in outputs.wiring.shared:
            # a line a part drives too (a button's, with an LED on it): the level the PWM holds
            # it at most of the time (an LED dimmed by it is lit or not, to this model)
            outputs.plant.set_input(signal, 1 if duty >= 32768 else 0)
        else:
            outputs.plant.set_input(signal, duty)


class UartPeripheral(Peripheral):
    """``machine.UART``: bytes in (each line a sample, as the shim counts them; with an RX
    IRQ armed, they fire it), bytes out (timed on the line at the baud rate, ``param``, by
    a plant input of kind ``uart``)."""

    kind = F.CFG_UART
    name = "uart"

    def configure(self, wiring, h, mode, pull, key, param):
        wiring.uart = True  # bytes flow: the plant goes in chunks (for the rest of the run)
        return super().configure(wiring, h, mode, pull, key, param)

    def deliver(self, inputs, t_us, h, info, value, watch):
        for _ in range(value.count(b"\n")):  # a line is a sample (the shim counts them too)
            info.samples += 1
            inputs.sampled(info.signal, t_us, info.samples)
        n = len(value)
        inputs.pending.append((t_us, h, _BYTES, n, value))
        inputs.pending_bytes += n
        if h in watch:
            return WOKE
        if info.irq:  # UART.irq(IRQ_RX): its handler runs at the bytes' time
            inputs.stats.irq_edges += 1
            return FIRED
        return 0

    def unsample(self, info, extra):
        info.samples -= extra.count(b"\n")

    def transmit(self, outputs, t_us, info, data):
        if outputs.recorder is not None:
            outputs.record(t_us, info, data, F.SIG_BYTES)
        sig_kind = outputs.plant_inputs.get(info.signal)
        if sig_kind == F.SIG_UART:  # the plant times the bytes on the line at the baud rate
            outputs.plant.send_bytes(info.signal, data, info.freq)
        elif sig_kind is not None:
            outputs.plant.set_input(info.signal, data)


class IrqPeripheral(Peripheral):
    """``Pin.irq`` / ``UART.irq``: arms (or, trigger 0, disarms) a handle already
    configured; ``mode`` is the trigger (``F.IRQ_RISING | F.IRQ_FALLING``, ``F.IRQ_RX``)."""

    kind = F.CFG_IRQ
    name = "irq"

    def configure(self, wiring, h, mode, pull, key, param):
        if h >= len(wiring.handles):
            raise LinkError(f"CFG: an IRQ on handle {h}, which the shim never configured (link protocol error)")
        wiring.handles[h].irq = mode
        wiring.irq_armed = any(info.irq for info in wiring.handles)
        return None


class BusPeripheral(Peripheral):
    """``machine.I2C`` / ``SoftI2C`` (CFG_I2C), ``SPI`` / ``SoftSPI`` (CFG_SPI): a handle
    named as the plant's parts name their bus (``i2c0``, ``i2c:<scl>,<sda>``, ``spi1``), the
    clock in ``param``; no inputs, no outputs: its transfers are BUS frames."""

    def __init__(self, kind: int, name: str):
        self.kind = kind
        self.name = name

    def configure(self, wiring, h, mode, pull, key, param):
        wiring.buses.add(key)
        return super().configure(wiring, h, mode, pull, key, param)

    def transfer(self, plant, info, op: int, address: int, n_read: int, data: bytes, unclocked=frozenset()) -> tuple:
        """(status, count, bytes read) from the devices on the handle's bus; a plant with
        no bus devices: nobody answers (an I2C address unacknowledged, SPI reads 0xFF).
        ``unclocked``: the SPI clock inputs whose pins are not the SPI's now (their chips
        see nothing: ``Wiring.unclocked``)."""
        if BUSES in plant.capabilities:
            if unclocked and op == F.BUS_SPI_XFER:
                return plant.bus_transfer(info.key, op, address, n_read, data, unclocked=unclocked)
            return plant.bus_transfer(info.key, op, address, n_read, data)
        if op == F.BUS_SPI_XFER:
            return F.BUS_OK, len(data), b"\xff" * len(data)
        return (F.BUS_OK, 0, b"") if op not in (F.BUS_XFER, F.BUS_XFER_NOSTOP) else (F.BUS_NACK_ADDRESS, 0, b"")


TARGET_PREFIX = "i2ctarget:"
"""The name of the change that carries a controller's transaction to a ``machine.I2CTarget``
(``host.rig.loop.boardset``: another board's I2C on the wire to this one): this, then its key."""


class I2CTargetPeripheral(Peripheral):
    """``machine.I2CTarget`` (CFG_I2CT): this board as a target at the address in ``param``
    (-1: deinit). A controller's transaction reaches it as one change at its instant (the
    op, the read count and the bytes written: ``F.I2CT_XACT_FMT``), which ends its wait (an
    interrupt on a board); the shim answers with I2CT_DONE."""

    kind = F.CFG_I2CT
    name = "i2ctarget"

    def configure(self, wiring, h, mode, pull, key, param):
        info = wiring.attach(self, h, mode, pull, key, param)
        for address in [a for a, held in wiring.i2c_targets.items() if held == h]:
            del wiring.i2c_targets[address]
        if param >= 0:
            wiring.i2c_targets[param] = h
        info.signal = TARGET_PREFIX + key
        if h not in wiring.by_signal.setdefault(info.signal, []):
            wiring.by_signal[info.signal].append(h)
        return info

    def deliver(self, inputs, t_us, h, info, value, watch):
        inputs.pending.append((t_us, h, _BYTES, len(value), value))
        inputs.pending_bytes += len(value)
        return FIRED


UNCONFIGURED = Peripheral()
"""A handle below one the shim configured, not configured itself."""

HANDLERS: dict[int, Peripheral] = {}
"""CFG kind -> its handler."""


def register(peripheral: Peripheral) -> Peripheral:
    """Add a peripheral kind (a bus, later): its CFG kind must be new."""
    if peripheral.kind in HANDLERS or not peripheral.kind:
        raise ValueError(f"CFG kind {peripheral.kind} ({peripheral.name}) is taken or not a kind")
    HANDLERS[peripheral.kind] = peripheral
    return peripheral


for _peripheral in (PinPeripheral(), AdcPeripheral(), PwmPeripheral(), UartPeripheral(), IrqPeripheral()):
    register(_peripheral)
register(BusPeripheral(F.CFG_I2C, "i2c"))
register(BusPeripheral(F.CFG_SPI, "spi"))
register(I2CTargetPeripheral())


def handler(kind: int, h: int) -> Peripheral:
    """The handler of a CFG kind; a kind the host does not know is a protocol error."""
    try:
        return HANDLERS[kind]
    except KeyError:
        known = ", ".join(f"{k} {p.name}" for k, p in sorted(HANDLERS.items()))
        raise LinkError(f"CFG of kind {kind} on handle {h}; the host knows {known} (link protocol error)") from None


def name_of(kind: int) -> str | int:
    """The kind's name in the link log (a kind the host does not know: its number)."""
    peripheral = HANDLERS.get(kind)
    return peripheral.name if peripheral is not None else kind

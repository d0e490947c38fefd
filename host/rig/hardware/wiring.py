"""Wiring: the board's named pins to plant signals, and the firmware's pins as the shim
configures them.

A board file names its pins (``MOTOR_L_PWM = const(25)``); an app's wiring maps those
names to plant signals (``"MOTOR_L_PWM": "motor_l.pwm"``), or to a probe that only the
harness watches (``"LOOP_PROBE": "probe:control"``, a logic-analyser probe). When the
firmware creates a Pin, ADC, PWM or UART, the shim sends CFG with the object's *handle*
and the pin's id; :class:`Wiring` keeps the table from handle to signal, and each handle
its kind's handler (``host/rig/hardware/peripherals.py``).
``docs/wiring.md`` describes the whole chain.
"""

from dataclasses import dataclass

from host.core.errors import ConfigError
from host.link import frames as F
from host.rig.config.app import PROBE_PREFIX
from host.rig.hardware.peripherals import UNCONFIGURED, Peripheral, handler
from host.rig.scan.boards import pin_key

RP2_FUNC_SPI = 1
"""GPIO_FUNC_SPI: an rp2 pin's function (FUNCSEL) when it is an SPI controller's."""


@dataclass
class Handle:
    """One shim object (pin, ADC, PWM, UART) and what it is wired to."""

    kind: int  # its CFG kind: F.CFG_PIN, F.CFG_ADC, ...
    key: str  # pin id as the shim names it
    board_name: str | None
    signal: str | None  # plant signal or "probe:<name>"
    is_input: bool = False
    mode: int = 0  # as its CFG said: a pin's F.PIN_IN, F.PIN_OUT, F.PIN_OPEN_DRAIN, F.PIN_ALT
    pull: int = 0  # F.PULL_NONE, F.PULL_UP, F.PULL_DOWN
    irq: int = 0  # trigger mask: F.IRQ_RISING | F.IRQ_FALLING; a UART's F.IRQ_RX
    samples: int = 0  # ADC samples / UART lines routed to it
    level: int | None = None  # last level (or PWM duty) driven on an output
    freq: int = 0  # a PWM's frequency (Hz), a UART's baud rate
    probe: bool = False  # wired to a probe: only the harness watches it
    peripheral: Peripheral = UNCONFIGURED  # its kind's handler: what CFG, inputs and outputs do with it

    def __post_init__(self):
        self.probe = self.signal is not None and self.signal.startswith(PROBE_PREFIX)


class Wiring:
    """Pin names -> signals (fixed for a rig), handles -> pins (per interpreter run)."""

    def __init__(
        self,
        wiring: dict[str, str],
        pins: dict[str, object],
        board: str,
        sensors: dict | None = None,
        shared: frozenset | set = frozenset(),
    ):
        """``sensors``: the plant's outputs and their kinds (what it drives), to refuse a
        firmware that drives them too, or reads a level with its ADC. ``shared``: those of
        them that are plant inputs too, lines both drive in turn (a part's ``io`` signal, an
        RC-decay sensor's node): a pin may drive one, and lets it go when it is made an
        input (:meth:`lets_go`, docs/wiring.md)."""
        unknown = sorted(set(wiring) - set(pins))
        if unknown:
            raise ConfigError(f"wiring: board {board} has no pin named {', '.join(unknown)}")
        self.wiring = dict(wiring)
        self.pin_names = {pin_key(n, v): n for n, v in pins.items() if n in self.wiring}
        self.sensors = dict(sensors or {})
        self.shared = frozenset(shared)
        self.wired = frozenset(self.wiring.values())  # the signals a board pin is wired to
        self.spi_clocks: dict[str, str] = {}  # the SPI chips' clock inputs -> their buses (Rig sets it)
        self.uart = False  # some UART was configured: bytes flow (for the rest of the run)
        self.buses: set[str] = set()  # the buses the firmware created (i2c0, spi1, ...)
        self.i2c_targets: dict[int, int] = {}  # machine.I2CTarget: its address -> its handle
        self.clear()

    def clear(self) -> None:
        """A new interpreter run: nothing configured yet."""
        self.handles: list[Handle] = []
        self.by_signal: dict[str, list[int]] = {}
        self.irq_armed = False  # some input has an IRQ handler
        self.fan_out = 1  # the most handles wired to one signal (a change of it is that many entries)

    def signal_of(self, key: str) -> str | None:
        board_name = self.pin_names.get(key)
        return self.wiring.get(board_name) if board_name else None

    def configure(self, h: int, kind: int, mode: int, pull: int, key: str, param: int = 0) -> Handle | None:
        """A CFG from the shim, handled by its kind's handler (``host/rig/hardware/peripherals.py``):
        the handle's new configuration (None for an IRQ, which arms an existing handle).
        ``param``: a PWM's frequency, a UART's baud rate, a pin's output level (-1: an input)."""
        return handler(kind, h).configure(self, h, mode, pull, key, param)

    def attach(self, peripheral: Peripheral, h: int, mode: int, pull: int, key: str, param: int) -> Handle:
        """Handle ``h`` is now ``key`` as ``peripheral`` configured it, wired to its pin's signal."""
        while len(self.handles) <= h:
            self.handles.append(Handle(0, "", None, None))
        board_name = self.pin_names.get(key)
        signal = self.wiring.get(board_name) if board_name else None
        sensor = self.sensors.get(signal)
        if signal in self.shared and peripheral.lets_go:
            sensor = None  # (a line both drive in turn: the pin drives it, and lets it go)
        if sensor is not None:  # what no board survives: two outputs on one line, an ADC on a logic level
            refused = peripheral.refuse(mode, f"pin {board_name} ({key})", board_name, signal, sensor)
            if refused:
                raise ConfigError(refused)
        kind = peripheral.kind
        is_input = peripheral.is_input(mode)
        info = Handle(kind, key, board_name, signal, is_input, mode, pull, freq=param, peripheral=peripheral)
        old = self.handles[h]
        if old.kind == kind and old.key == key:  # the same pin again (init(), or made anew)
            info.irq, info.samples = old.irq, old.samples  # its IRQ and its samples go on
        if old.signal and h in self.by_signal.get(old.signal, ()):
            self.by_signal[old.signal].remove(h)
        self.handles[h] = info
        if signal:
            self.by_signal.setdefault(signal, []).append(h)
        self.fan_out = max(map(len, self.by_signal.values()), default=1)
        return info

    def lets_go(self, info: Handle | None) -> bool:
        """A CFG made ``info`` an input on a shared line: the firmware lets the line go."""
        return info is not None and info.is_input and info.signal in self.shared and info.peripheral.lets_go

    def unclocked(self, bus: str) -> frozenset:
        """The clock inputs of the chips on SPI ``bus`` that a transfer does not reach now:
        each wired to a board pin that is not in the SPI function (rp2: its FUNCSEL, as
        Pin.ALT, alt=, SPI(..., sck=) or mem32 set it; the CFG's PIN_ALT and function), or
        is the SPI function of the other controller (GPIO n is SPI(n >> 3 & 1)'s: the
        RP2040 datasheet's 2.19.2 function table). A chip whose clock input is not wired
        sees every transfer on its bus (one clock line), as does every chip on a SoftSPI
        (``spi:<sck>,<mosi>,<miso>``: its clock is a GPIO, bit-banged)."""
        if not bus.startswith("spi") or ":" in bus:
            return frozenset()
        out = set()
        for signal, on in self.spi_clocks.items():
            if on != bus or signal not in self.wired:
                continue
            if not any(self._clocks(h, bus) for h in self.by_signal.get(signal, ())):
                out.add(signal)
        return frozenset(out)

    def _clocks(self, h: int, bus: str) -> bool:
        info = self.handles[h]
        if info.kind != F.CFG_PIN or info.mode != F.PIN_ALT or info.freq != RP2_FUNC_SPI:
            return False
        return not (info.key.isdigit() and f"spi{int(info.key) >> 3 & 1}" != bus)

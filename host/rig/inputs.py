"""The firmware's inputs: plant changes routed to the handles wired to them and gathered
into the next STATE (``docs/protocol.md``).

A change goes to every handle wired to its signal, as the handle's kind's handler
delivers it (``host/rig/peripherals.py``): a level to a pin (it may fire an IRQ), the
next sample to an ADC, bytes to a UART (each line a sample). A change of a watched handle
(``time_pulse_us``, a timed UART read) ends the batch at once, as does a full batch.
"""

from host.link import frames as F
from host.rig.peripherals import FIRED, WOKE, PinPeripheral

_LEVEL, _RISING, _FALLING = F.CH_LEVEL, F.IRQ_RISING, F.IRQ_FALLING

MAX_BATCH = 200  # changes in one STATE (15 bytes each)
MAX_BATCH_BYTES = 800  # UART bytes in one STATE


class Inputs:
    def __init__(self, wiring, hooks, speculation, recorder, stats):
        self.wiring = wiring
        self.change_hooks = hooks.change
        self.sample_hooks = hooks.sample
        self.speculation = speculation
        self.recorder = recorder
        self.stats = stats
        self.clear()

    def clear(self) -> None:
        self.pending: list[tuple] = []  # (t_us, handle, kind, value, extra) for the next STATE
        self.pending_bytes = 0
        self.sent: list[tuple] = []  # the last STATE's changes (a rewind may void some)

    def full(self) -> bool:
        return len(self.pending) >= MAX_BATCH or self.pending_bytes > MAX_BATCH_BYTES

    def room(self) -> int:
        """How many plant changes may come before the batch is full."""
        return max(1, (MAX_BATCH - len(self.pending)) // max(1, self.wiring.fan_out))

    def route(self, change, watch) -> tuple[bool, bool]:
        """Queue a plant change for the firmware, each handle wired to it as its kind's
        handler delivers it; (fires an IRQ, wakes a watched wait)."""
        t, name, value = change
        irq = hit = False
        if self.recorder is not None:
            self.recorder.sensor(t, name, value)
        hooks = self.change_hooks.get(name)
        if hooks:
            defer = self.speculation.defer
            for call in hooks:
                defer(t, call, (t, value))
        wiring = self.wiring
        handles = wiring.handles
        for h in wiring.by_signal.get(name, ()):
            info = handles[h]
            took = info.peripheral.deliver(self, t, h, info, value, watch)
            if took:
                if took & FIRED:
                    irq = True
                if took & WOKE:
                    hit = True
        return irq, hit

    def route_all(self, changes, watch) -> tuple[bool, bool]:
        """:meth:`route` for each change in turn, in one loop (the hot path: an encoder's
        edges), a pin's delivery inline (``PinPeripheral.deliver``); (any fires an IRQ, any
        wakes a watched wait)."""
        irq = hit = False
        edges = 0
        recorder = self.recorder
        change_hooks = self.change_hooks
        by_signal = self.wiring.by_signal
        handles = self.wiring.handles
        pending = self.pending
        append = pending.append
        for change in changes:
            t, name, value = change
            if recorder is not None:
                recorder.sensor(t, name, value)
            if change_hooks:
                hooks = change_hooks.get(name)
                if hooks:
                    defer = self.speculation.defer
                    for call in hooks:
                        defer(t, call, (t, value))
            for h in by_signal.get(name, ()):
                info = handles[h]
                peripheral = info.peripheral
                if peripheral.__class__ is PinPeripheral:
                    append((t, h, _LEVEL, value, 0))
                    if h in watch:
                        hit = True
                    elif info.irq & (_RISING if value else _FALLING):
                        edges += 1
                        irq = True
                    continue
                took = peripheral.deliver(self, t, h, info, value, watch)
                if took:
                    if took & FIRED:
                        irq = True
                    if took & WOKE:
                        hit = True
        if edges:
            self.stats.irq_edges += edges
        return irq, hit

    def sampled(self, name: str, t: int, sample_no: int) -> None:
        """A handle wired to ``name`` got its sample ``sample_no`` (an ADC's, a UART's line)."""
        for call in self.sample_hooks.get(name, ()):
            self.speculation.defer(t, call, (t, sample_no))

    def sync(self, t_us: int, h: int, info, plant) -> None:
        """An input was just configured; the shim syncs next: tell it the current value
        (a pin wired to no plant output reads its pull)."""
        if info.signal in plant.outputs:
            value = plant.output(info.signal)
        else:
            value = info.peripheral.idle(info)
        self.pending.append(info.peripheral.first(t_us, h, info, value if value is not None else 0))

    def take(self) -> list[tuple]:
        """The batch for the next STATE; the queue starts empty again."""
        batch, self.sent = self.pending, self.pending
        self.pending = []
        self.pending_bytes = 0
        return batch

    def drop(self) -> None:
        """Nobody will read these (the firmware ended)."""
        self.pending = []
        self.pending_bytes = 0

    def unsample(self, t_us: int) -> None:
        """A rewind to ``t_us``: samples of the last STATE after it were never taken."""
        handles = self.wiring.handles
        for t, h, _kind, _value, extra in self.sent:
            if t > t_us and h < len(handles):
                info = handles[h]
                info.peripheral.unsample(info, extra)

"""The firmware's inputs: plant changes routed to the handles wired to them and gathered
into the next STATE (``docs/protocol.md``).

A level change goes to every pin wired to its signal (and may fire an IRQ); an ADC
sample counts as the handle's next sample number; UART bytes go to the UART, each line
a sample. A change of a watched handle (``time_pulse_us``, a timed UART read) ends the
batch at once, as does a full batch.
"""

from host.link import frames as F

MAX_BATCH = 200  # changes in one STATE (15 bytes each)
MAX_BATCH_BYTES = 800  # UART bytes in one STATE
_IRQ_MASK = (2, 1)  # the trigger bit a new level fires: falling for 0, rising for 1


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
        """Queue a plant change for the firmware; (fires an IRQ, wakes a watched wait)."""
        t, name, value = change
        irq = hit = False
        if self.recorder is not None:
            self.recorder.sensor(t, name, value)
        defer = self.speculation.defer
        for call in self.change_hooks.get(name, ()):
            defer(t, call, (t, value))
        handles = self.wiring.handles
        pending = self.pending
        for h in self.wiring.by_signal.get(name, ()):
            info = handles[h]
            if info.kind == F.CFG_ADC:
                info.samples += 1
                self._sampled(name, t, info.samples)
                pending.append((t, h, F.CH_SAMPLE, value, info.samples))
            elif info.kind == F.CFG_UART:
                for _ in range(value.count(b"\n")):  # a line is a sample (the shim counts them too)
                    info.samples += 1
                    self._sampled(name, t, info.samples)
                pending.append((t, h, F.CH_BYTES, len(value), value))
                self.pending_bytes += len(value)
                if h in watch:
                    hit = True
                elif info.irq:  # UART.irq(IRQ_RX): its handler runs at the byte's time
                    irq = True
                    self.stats.irq_edges += 1
            else:
                pending.append((t, h, F.CH_LEVEL, value, 0))
                if h in watch:
                    hit = True
                elif info.irq & _IRQ_MASK[1 if value else 0]:
                    irq = True
                    self.stats.irq_edges += 1
        return irq, hit

    def _sampled(self, name: str, t: int, sample_no: int) -> None:
        for call in self.sample_hooks.get(name, ()):
            self.speculation.defer(t, call, (t, sample_no))

    def sync(self, t_us: int, h: int, info, plant) -> None:
        """An input was just configured; the shim syncs next: tell it the current level."""
        if info.signal in plant.outputs:
            value = plant.output(info.signal)
        else:
            value = 1 if info.pull == 1 else 0
        kind = F.CH_SAMPLE if info.kind == F.CFG_ADC else F.CH_LEVEL
        sample_no = info.samples if kind == F.CH_SAMPLE else 0  # (an ADC made again keeps its count)
        self.pending.append((t_us, h, kind, value if value is not None else 0, sample_no))

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
        for t, h, kind, _value, extra in self.sent:
            if t > t_us and h < len(handles):
                if kind == F.CH_SAMPLE:
                    handles[h].samples -= 1
                elif kind == F.CH_BYTES:
                    handles[h].samples -= extra.count(b"\n")

"""The firmware's inputs: plant changes routed to the handles wired to them and gathered
into the next STATE (``docs/protocol.md``).

A change goes to every handle wired to its signal, as the handle's kind's handler
delivers it (``host/rig/hardware/peripherals.py``): a level to a pin (it may fire an IRQ), the
next sample to an ADC, bytes to a UART (each line a sample). A change of a watched handle
(``time_pulse_us``, a timed UART read) ends the batch at once, as does a full batch.
"""

from host.link import frames as F
from host.rig.hardware.peripherals import FIRED, WOKE, PinPeripheral

_LEVEL, _RISING, _FALLING = F.CH_LEVEL, F.IRQ_RISING, F.IRQ_FALLING

MAX_BATCH = 200  # changes in one STATE (15 bytes each)
MAX_BATCH_BYTES = 800  # UART bytes in one STATE
MAX_SEGMENTS = 64  # encoder segments in one EDGES (51 bytes each; the shim's C holds as many)


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
        self.segments: list[tuple] = []  # encoder edges as EDGES segments for the next STATE
        self.seg_margin = 0  # the plant's encoders: a window's segments at most (edge_routes)
        self._levels: dict = {}  # (counter class, channels) -> (mask, a's levels, b's levels): edge_routes

    def full(self) -> bool:
        return (
            len(self.pending) >= MAX_BATCH
            or self.pending_bytes > MAX_BATCH_BYTES
            or len(self.segments) + self.seg_margin > MAX_SEGMENTS
        )

    def segment_room(self) -> int:
        """How many segments the plant may add before the EDGES is full (one window's worth,
        one an encoder, kept in hand: the plant stops after the window that goes past it)."""
        return max(1, MAX_SEGMENTS - self.seg_margin - len(self.segments))

    def edge_routes(self, encoders, watch):
        """Where each encoder's channels go as segments: per encoder (handle of channel a,
        of b or NO_HANDLE, mask, a's and b's levels by count & mask, IRQ triggers of a and
        b), or None when an edge must go its own way: a channel wired to more than one
        handle or to anything but a pin, watched, or with change hooks."""
        by_signal, handles, hooks = self.wiring.by_signal, self.wiring.handles, self.change_hooks
        routes = []
        self.seg_margin = len(encoders)
        for enc in encoders:
            names = enc.names
            if len(names) > 2:
                return None
            levels = self._levels.get((type(enc), len(names)))
            if levels is None:  # (a counter's levels by count & mask: its class's, fixed)
                mask = enc.edges_per_line - 1
                by_count = [enc._levels(k) for k in range(mask + 1)]
                levels = self._levels[type(enc), len(names)] = (
                    mask,
                    *(sum(lv[c] << k for k, lv in enumerate(by_count)) if c < len(names) else 0 for c in (0, 1)),
                )
            mask, bits_a, bits_b = levels
            route = [F.NO_HANDLE, F.NO_HANDLE, mask, bits_a, bits_b, 0, 0]
            for c, name in enumerate(names):
                if hooks and hooks.get(name):
                    return None
                hs = by_signal.get(name, ())
                if len(hs) > 1:
                    return None
                if hs:
                    h = hs[0]
                    info = handles[h]
                    if info.peripheral.__class__ is not PinPeripheral or h in watch:
                        return None
                    route[c] = h
                    route[5 + c] = info.irq
            routes.append(route)
        return routes

    def route_segments(self, raw, routes) -> bool:
        """The plant's segments (``RobotPlant.advance_edges``) queued for the next EDGES, each
        with its channels' handles; True when one fires an IRQ."""
        irq = False
        edges = 0
        segments = self.segments
        for k, t1, n, count, t0, p0, rate in raw:
            ha, hb, mask, bits_a, bits_b, irq_a, irq_b = routes[k]
            if ha == F.NO_HANDLE and hb == F.NO_HANDLE:
                continue
            segments.append((ha, hb, mask, bits_a, bits_b, t1, n, count, t0, p0, rate))
            if irq_a or irq_b:
                fired = _irq_edges(mask, bits_a, bits_b, irq_a, irq_b, n, count, 1 if rate > 0.0 else -1)
                if fired:
                    edges += fired
                    irq = True
        if edges:
            self.stats.irq_edges += edges
        return irq

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

    def take_segments(self) -> list[tuple]:
        """The segments for the next STATE's EDGES; none queued after."""
        segments, self.segments = self.segments, []
        return segments

    def drop(self) -> None:
        """Nobody will read these (the firmware ended)."""
        self.pending = []
        self.pending_bytes = 0
        self.segments = []

    def unsample(self, t_us: int) -> None:
        """A rewind to ``t_us``: samples of the last STATE after it were never taken."""
        handles = self.wiring.handles
        for t, h, _kind, _value, extra in self.sent:
            if t > t_us and h < len(handles):
                info = handles[h]
                info.peripheral.unsample(info, extra)


def _irq_edges(mask, bits_a, bits_b, irq_a, irq_b, n, count, step) -> int:
    """How many of a segment's ``count`` edges (from count ``n``, by ``step``) fire an IRQ:
    counted by the residue of the count each edge reaches (mask + 1 of them)."""
    period = mask + 1
    fired = 0
    for r in range(period):
        m = n + step * (r + 1)  # the edges reaching this residue: the (r+1)th, then every period
        if count < r + 1:
            break
        times = (count - (r + 1)) // period + 1
        was, now = m - step, m
        a_was, a_now = bits_a >> (was & mask) & 1, bits_a >> (now & mask) & 1
        if a_was != a_now:
            trigger, level = irq_a, a_now
        else:
            trigger, level = irq_b, bits_b >> (now & mask) & 1
        if trigger & (_RISING if level else _FALLING):
            fired += times
    return fired

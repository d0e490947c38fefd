"""Wires between board pins: a loopback bench, as upstream's hardware tests wire a board.
The catalogue's ``wire`` and ``uart_wire`` parts on a ``bench`` body are built on it
(:class:`WirePart`: every wire of a plant on one timeline).

Each wire ``<name>`` has an input ``<name>.in`` (a board output drives it: a level, or a
PWM waveform) and an output ``<name>.out`` (a board input reads it). A level written to
the input is on the output at the same instant (``zero_delay``: the shim syncs a read that
follows a write). A PWM on the input drives the output with its waveform: rising edges
every period from the instant the PWM started, each high for duty/65535 of the period,
edge times rounded to the microsecond (so ``time_pulse_us`` measures a pulse within 1 µs).
Duty 0 holds the line low, 65535 high.

A UART wire ``<name>`` (``uarts``) is one signal both ways: a UART wired to it receives
what it sends, each byte at the time its stop bit ends at the sender's baud rate (10 bits
a byte), one after another on the line. A crossed pair of UART lines (``crossed``:
``<name>.a`` and ``<name>.b``, the catalogue's ``board_uart``) joins two boards: what one
line's UART sends arrives on the other's, timed the same way at the sender's baud rate.
"""

from operator import itemgetter
from typing import NamedTuple

from sim_plant.engine import Part
from sim_plant.plant import NEVER_US, PWM, UART, Change, Plant

BITS_PER_BYTE = 10  # start, 8 data, stop
_TIME = itemgetter(0)  # a Change's t_us
_BYTE = tuple(bytes((b,)) for b in range(256))  # (a byte's value as a change carries it)
_new_change = tuple.__new__  # (a Change made without its Python __new__: a byte each, the hot path)


class _Waveform(NamedTuple):
    """A PWM's edges: rises at t0 + round(k·P), falls at t0 + round(k·P + H). A value:
    taking an edge gives the next waveform (a snapshot copies the plant's dict of them)."""

    t0: int
    period: float
    high: float
    k: int = 0  # the period the next edge belongs to
    rising: bool = False  # the next edge (the first rise is at t0 itself)

    @classmethod
    def start(cls, t0: int, freq_hz: int, duty_u16: int) -> "_Waveform":
        period = 1e6 / freq_hz
        return cls(t0, period, period * duty_u16 / 65535)

    def next_edge(self) -> tuple[int, int]:
        base = self.k * self.period
        if self.rising:
            return self.t0 + round(base + self.period), 1
        return self.t0 + round(base + self.high), 0

    def after_edge(self) -> "_Waveform":
        return self._replace(k=self.k + 1 if self.rising else self.k, rising=not self.rising)


class Wires(Plant):
    zero_delay = True
    capabilities = frozenset((PWM, UART))

    def __init__(self, wires: tuple, uarts: tuple, crossed: tuple = (), faults: dict | None = None):
        self.names = tuple(wires)
        self.uarts = tuple(uarts)
        self.crossed = tuple(crossed)  # (line a, line b): each receives what the other sends
        # a line's faults: (drop_p, flip_p), each byte sent on it lost, or one bit of it
        # flipped, with that chance (drawn from fault_seed, the byte's line and number)
        self.faults = dict(faults or {})
        self.fault_seed = 0
        self.peer = {a: b for a, b in self.crossed} | {b: a for a, b in self.crossed}
        self.inputs = {f"{w}.in": "pwm" for w in self.names} | dict.fromkeys(self.uarts, "uart")
        self.outputs = {f"{w}.out": "level" for w in self.names} | dict.fromkeys(self.uarts, "bytes")
        self.reset(0)

    def reset(self, seed: int) -> None:
        self._t_us = 0
        self.levels = dict.fromkeys(self.names, 0)
        self.waves: dict[str, _Waveform] = {}
        self.now: list[Change] = []  # changes at the current instant, not yet taken
        self.edges = 0
        self.edges_of = dict.fromkeys(self.names, 0)
        self.bytes: list[Change] = []  # bytes on a UART line, in time order
        self.line_free = dict.fromkeys(self.uarts, 0)  # when each line's last byte ends
        self.sent = dict.fromkeys(self.uarts, 0)  # bytes sent on each line (a byte's number)
        self.lost = dict.fromkeys(self.uarts, 0)
        self.flipped = dict.fromkeys(self.uarts, 0)

    @property
    def t_us(self) -> int:
        return self._t_us

    def at(self, t_us: int) -> None:
        """The clock to ``t_us``, when nothing is due before it (a plant around these wires
        took every change up to then)."""
        self._t_us = max(self._t_us, t_us)

    def _wire(self, name: str) -> str:
        wire = name[: -len(".in")] if name.endswith(".in") else None
        if wire not in self.levels:
            raise KeyError(f"Wires has no input {name!r} (inputs: {', '.join(self.inputs)})")
        return wire

    def _drive(self, wire: str, level: int) -> None:
        if self.levels[wire] != level:
            self.levels[wire] = level
            self.edges += 1
            self.edges_of[wire] += 1
            self.now.append(Change(self._t_us, f"{wire}.out", level))

    def set_input(self, name: str, value) -> None:
        wire = self._wire(name)
        self.waves.pop(wire, None)
        self._drive(wire, 1 if value else 0)

    def set_pwm(self, name: str, freq_hz: int, duty_u16: int) -> None:
        """A PWM on the wire's input from now on (freq in Hz, duty 0..65535)."""
        wire = self._wire(name)
        self.waves.pop(wire, None)
        if duty_u16 <= 0 or duty_u16 >= 65535 or freq_hz <= 0:
            self._drive(wire, 1 if duty_u16 >= 65535 and freq_hz > 0 else 0)
            return
        self.waves[wire] = _Waveform.start(self._t_us, freq_hz, duty_u16)
        self._drive(wire, 1)

    def send_bytes(self, name: str, data: bytes, baud: int) -> None:
        """Bytes a UART sends on line ``name`` at ``baud``, from now (after what is on it)."""
        if name not in self.line_free:
            raise KeyError(f"Wires has no UART line {name!r} (lines: {', '.join(self.uarts)})")
        start = max(self._t_us, self.line_free[name])
        byte_us = BITS_PER_BYTE * 1e6 / max(1, baud)
        faults = self.faults.get(name)
        on_line = self.bytes
        n_before = len(on_line)
        to = self.peer.get(name, name)
        if faults is None:
            on_line += [_new_change(Change, (start + round(i * byte_us), to, _BYTE[b])) for i, b in enumerate(data, 1)]
        else:
            for i, b in enumerate(data):
                b = self._fault(name, faults, b)
                if b is not None:
                    on_line.append(Change(start + round((i + 1) * byte_us), to, bytes((b,))))
        self.line_free[name] = start + round(len(data) * byte_us)
        # (a line's bytes come in time order: sorted only when they land among another
        # line's later ones; a stable sort, so bytes of one instant keep their order)
        if 0 < n_before < len(on_line) and on_line[n_before - 1].t_us > on_line[n_before].t_us:
            on_line.sort(key=_TIME)

    def _fault(self, name: str, faults: tuple, b: int) -> int | None:
        """Byte ``b``, the line's next, lost (None), one bit flipped, or as sent: by a
        hash of the seed, the line and the byte's number (the same run, the same faults,
        whatever else draws from the plant's generator)."""
        k = self.sent[name]
        self.sent[name] = k + 1
        h = _mix(self.fault_seed ^ _mix(self.uarts.index(name) + 1) ^ _mix(k + 0x9E3779B97F4A7C15))
        drop_p, flip_p = faults
        if (h >> 11) / 2**53 < drop_p:
            self.lost[name] += 1
            return None
        h = _mix(h)
        if (h >> 11) / 2**53 < flip_p:
            self.flipped[name] += 1
            return b ^ (1 << (h & 7))
        return b

    def next_change_us(self) -> int:
        if self.now:
            return self._t_us
        t_next = self.bytes[0].t_us if self.bytes else NEVER_US
        if self.waves:
            for wave in self.waves.values():
                t_edge = wave.next_edge()[0]
                if t_edge < t_next:
                    t_next = t_edge
        return t_next

    def advance_to(self, t_us: int, limit: int = 0) -> list[Change]:
        if limit and len(self.now) > limit:  # a burst of writes at one instant: in parts
            changes, self.now = self.now[:limit], self.now[limit:]
            return changes
        changes, self.now = self.now, []
        on_line = self.bytes
        while True:  # (self.now is empty here: a UART's next byte is the next change, or a PWM's edge)
            t_next = self.next_change_us() if self.waves else on_line[0].t_us if on_line else NEVER_US
            if t_next > t_us:
                break
            if limit and len(changes) >= limit and t_next > self._t_us:
                return changes  # stopped after the instant that reached the limit
            self._t_us = t_next
            if on_line and on_line[0].t_us == t_next:
                changes.append(on_line.pop(0))
                continue
            wire = min((w.next_edge()[0], name) for name, w in self.waves.items())[1]
            wave = self.waves[wire]
            level = wave.next_edge()[1]
            self.waves[wire] = wave.after_edge()
            self._drive(wire, level)
            changes += self.now
            self.now = []
        self._t_us = max(self._t_us, t_us)
        return changes

    def output(self, name: str):
        return b"" if name in self.line_free else self.levels[name[: -len(".out")]]

    def truth(self) -> dict:
        return {"t_us": self._t_us, "levels": dict(self.levels), "edges": self.edges}


def _mix(x: int) -> int:
    """SplitMix64's finaliser: a 64-bit hash of ``x``."""
    x = (x + 0x9E3779B97F4A7C15) & 0xFFFFFFFFFFFFFFFF
    x = ((x ^ (x >> 30)) * 0xBF58476D1CE4E5B9) & 0xFFFFFFFFFFFFFFFF
    x = ((x ^ (x >> 27)) * 0x94D049BB133111EB) & 0xFFFFFFFFFFFFFFFF
    return x ^ (x >> 31)


class WirePart(Part):
    """Wires as a part of a body-and-parts plant (the catalogue's ``wire`` and
    ``uart_wire`` on a ``bench``): the engine fires it at each change the wires have due,
    and routes a PWM or a UART's bytes to it (``set_pwm``, ``send_bytes``)."""

    FIXED_STATE = ("inputs", "outputs")

    @classmethod
    def on(cls, parts: list) -> "WirePart":
        """The one WirePart among a plant's ``parts`` (added if none yet): every wire of a
        bench is on one timeline, so the writes of one instant come out in their order."""
        for part in parts:
            if isinstance(part, cls):
                return part
        part = cls()
        parts.append(part)
        return part

    def __init__(self):
        self.wires = Wires((), ())
        self.add()

    def add(self, wires: tuple = (), uarts: tuple = (), crossed: tuple = (), faults: dict | None = None) -> None:
        """More wires and UART lines (while the plant is built, before any input);
        ``crossed``: pairs of UART lines, each receiving what the other sends; ``faults``:
        a line's (drop_p, flip_p)."""
        lines = tuple(line for pair in crossed for line in pair)
        old = self.wires
        self.wires = Wires(
            old.names + tuple(wires),
            old.uarts + tuple(uarts) + lines,
            old.crossed + tuple(crossed),
            {**old.faults, **(faults or {})},
        )
        self.inputs = dict(self.wires.inputs)
        self.outputs = dict(self.wires.outputs)
        self.next_us = NEVER_US

    def initial_outputs(self) -> dict:
        return {name: self.wires.output(name) for name in self.outputs}

    def start(self, t_us: int, plant) -> None:
        if any(p > 0 for faults in self.wires.faults.values() for p in faults):  # (no draw without faults)
            self.wires.fault_seed = int(plant.rng.integers(0, 2**63))

    def _planned(self) -> None:
        self.next_us = self.wires.next_change_us()

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        self.wires.at(t_us)
        self.wires.set_input(name, value)
        self._planned()
        return False

    def set_pwm(self, name: str, freq_hz: int, duty_u16: int, t_us: int) -> None:
        self.wires.at(t_us)
        self.wires.set_pwm(name, freq_hz, duty_u16)
        self._planned()

    def send_bytes(self, name: str, data: bytes, baud: int, t_us: int) -> None:
        self.wires.at(t_us)
        self.wires.send_bytes(name, data, baud)
        self._planned()

    def fire(self, t_us: int, plant, out: list) -> None:
        wires = self.wires
        if wires.waves or wires.now:
            out.extend(wires.advance_to(t_us))
            self._planned()
            return
        on_line = wires.bytes  # (bytes alone on the timeline: Wires.advance_to's loop, written out)
        while on_line and on_line[0][0] <= t_us:
            out.append(on_line.pop(0))
        if t_us > wires._t_us:
            wires._t_us = t_us
        self.next_us = on_line[0][0] if on_line else NEVER_US

    def fire_until(self, t_stop: int, out: list) -> int | None:
        """Every byte due by ``t_stop`` at once, when the wires hold bytes alone (no PWM, no
        write at this instant): the engine's ``_fire_alone``, in place of a ``fire`` at
        each byte's instant. The last byte's instant; None (nothing taken) otherwise."""
        wires = self.wires
        on_line = wires.bytes
        if wires.waves or wires.now or not on_line or on_line[0][0] > t_stop:
            return None
        k, n = 1, len(on_line)
        while k < n and on_line[k][0] <= t_stop:
            k += 1
        last = on_line[k - 1][0]
        out += on_line[:k]
        del on_line[:k]
        if last > wires._t_us:
            wires._t_us = last
        self.next_us = on_line[0][0] if on_line else NEVER_US
        return last

    @property
    def burst(self) -> int:
        """How many changes the writes at this instant made, not yet taken."""
        return len(self.wires.now)

    def take(self, limit: int) -> list[Change]:
        """The first ``limit`` changes of a larger burst (the rest stay due now)."""
        changes = self.wires.advance_to(self.wires.t_us, limit)
        self._planned()
        return changes

    def truth(self, t_us: int, plant) -> dict:
        wires = self.wires
        out = {
            f"{w}_{key}": of[w] for w in wires.names for key, of in (("level", wires.levels), ("edges", wires.edges_of))
        }
        for line in (line for pair in wires.crossed for line in pair):  # (link.a: what its UART sent, lost or damaged)
            base = line.replace(".", "_")
            out[f"{base}_lost"], out[f"{base}_damaged"] = wires.lost[line], wires.flipped[line]
        return out

"""A poll that can never end, named (``docs/reliability.md``, "A poll that never ends").

A driver that waits on a chip polls a register until a bit changes (a BOOT bit to clear, a
data-ready bit to set). When the chip never changes it (a part left powered down, a bit
the model does not honour), the firmware spins in virtual time with nothing on its
console. :class:`PollWatch` counts, per (bus, address, register), the reads in a row that
gave the same answer; once :data:`POLL_READS` of them span :data:`POLL_SPAN_US` of virtual
time, it names the poll once: bus, address, register, the answer, since when, and what
the chip's model honours there. A count and a comparison a read: cheap on every transfer.

A pin read through ``Pin.value()`` and a ``machine.mem8/16/32`` address are read in the
shim, where the host does not see each read: the shim counts them the same way
(``host/shim/_hilpoll.py``) and sends one POLL message when such a poll is due a name;
:func:`shim_poll_text` says it, with what would change it (the part that drives the pin
by the rig's wiring, or that nothing does; whether a register of the board's model lies
at the address). Each (kind, target) is named once a run (:meth:`PollWatch.first`).

The firmware's stack is the shim's, not the host's: a POLL message carries it when the
interpreter can give it (``_hilpoll.firmware_stack``: the harness's build, none on a user's own);
a bus poll, seen here as the host answers the read, asks for it in the reply
(``BUS_ASK_STACK``; the shim answers with a POLL of kind ``POLL_STACK``) and its note is
said with it (``BusTrace.poll_stack``).
"""

from host.link import frames as F

POLL_READS = F.POLL_READS
"""Reads in a row with the same answer ..."""
POLL_SPAN_US = F.POLL_SPAN_US
"""... over at least this much virtual time: a poll that is not going to end (one pair for
the buses here and the pins and memory the shim counts: the codec's)."""


class PollWatch:
    def __init__(self, reads: int = POLL_READS, span_us: int = POLL_SPAN_US):
        self.reads = reads
        self.span_us = span_us
        self.runs = {}  # (bus, address, register) -> [answer, since t_us, reads in a row]
        self.named = set()  # the keys named already (once each)

    def seen(self, t_us: int, bus: str, address, register, answer: bytes) -> tuple | None:
        """A read's answer; (since t_us, reads) when it completes a poll to name, else None."""
        key = (bus, address, register)
        run = self.runs.get(key)
        if run is None or run[0] != answer:
            self.runs[key] = [answer, t_us, 1]
            return None
        run[2] += 1
        if run[2] >= self.reads and t_us - run[1] >= self.span_us and self.first(key):
            return run[1], run[2]
        return None

    def first(self, key) -> bool:
        """True the first time ``key`` (a bus register, a pin, an address) is to be named."""
        if key in self.named:
            return False
        self.named.add(key)
        return True


def poll_text(t_us: int, bus: str, address, register, answer: bytes, since_us: int, reads: int, device) -> str:
    """The note for a poll that never ends, with what the chip's model honours."""
    at = f"0x{address:02x}" if address is not None else "(chip select)"
    reg = f"register 0x{register:02x}" if register is not None else "no register"
    shown = " ".join(f"{b:02x}" for b in answer[:8]) or "nothing"
    text = (
        f"a poll that never ends? the firmware read {bus} {at} {reg} {reads} times from virtual "
        f"t={since_us / 1e6:.6f} s to t={t_us / 1e6:.6f} s and got {shown} each time"
    )
    if device is None:
        return text if address is None else text + " (no chip of the plant answers there)"
    modelled = getattr(device, "MODELLED", None)
    if modelled is None:
        return text + f" ({device.label}: a {type(device).__name__}, not a register chip)"
    here = modelled.get(register)
    what = f"the model honours {here}" if here else "the model keeps it as plain memory: only a write changes it"
    return text + f"; {device.where()}: {what} (all it honours: {device.modelled_text()})"


def shim_poll_text(poll: tuple, wiring, plant) -> str:
    """The note for a POLL message (``F.unpack_poll``): a pin read through ``Pin.value()``
    or a ``machine.mem`` address with one answer, and what would change it."""
    t_us, since_us, reads, kind, bits, target, value, words = poll
    lines = words.decode(errors="replace").split("\n")
    word, stack = lines[0], [line for line in lines[1:] if line]
    span = f"{reads} times from virtual t={since_us / 1e6:.6f} s to t={t_us / 1e6:.6f} s and got"
    if kind == F.POLL_SPIN:
        text = (
            f"a loop that never ends? the firmware's own code called nothing of the board's (no clock or pin "
            f"read, no sleep, no output) from virtual t={since_us / 1e6:.6f} s to t={t_us / 1e6:.6f} s "
            f"({reads} branches): a board spins there too, while time goes on; a loop that waits for what a "
            'callback sets ends when the callback fires (docs/mcu-time.md, "A loop that calls nothing of the '
            "board's\")"
        )
    elif kind == F.POLL_PIN:
        info = wiring.handles[target] if 0 <= target < len(wiring.handles) else None
        key = info.key if info is not None else f"handle {target}"
        pin = f"pin {info.board_name} ({key})" if info is not None and info.board_name else f"pin {key}"
        text = f"a poll that never ends? the firmware read {pin} with Pin.value() {span} {value} each time; "
        text += _pin_driver(info, plant, value)
    else:
        shown = f"0x{value:0{bits // 4}x}"
        text = f"a poll that never ends? the firmware read machine.mem{bits}[0x{target:08x}] {span} {shown} each time; "
        text += word
    return text + ("; the firmware's stack, outermost first: " + " > ".join(stack) if stack else "")


def _pin_driver(info, plant, value) -> str:
    """What would change a pin's level: the part that drives it by the rig's wiring, or nothing."""
    signal = info.signal if info is not None else None
    if signal is None:
        return "it is wired to nothing in the rig, so nothing drives it: it reads its pull (1 on PULL_UP, else 0)"
    if info.probe:
        return f"it is wired to {signal}, which only the harness watches: nothing drives it"
    if signal not in plant.outputs:
        return f"it is wired to {signal}, an input of the plant: nothing drives it"
    part = next((p for p in plant.catalogue_parts if signal in p.signals()), None)
    if part is None:
        return f"the plant drives it ({signal}), and kept it at {value}"
    text = f"{part.kind} {part.name} drives it ({signal}), and kept it at {value}"
    controls = [c.name for c in part.CONTROLS]
    if controls:
        text += f" (a scenario's set-control of {part.name}'s {', '.join(controls)} changes it)"
    return text

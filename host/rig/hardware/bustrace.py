"""Bus transactions as the trace keeps them (``docs/traces.md``, ``docs/budgets.md``).

Each I2C or SPI transfer the firmware makes (one BUS frame, ``host.rig.loop.messages.on_bus``) becomes a
:class:`Transaction`: the bus, the address, the register (the first byte written: the
register pointer of a register chip; on SPI without its read bit), the bytes written
and read, the outcome, and its virtual duration at the bus clock, computed as the shim
charges it (``host/shim/_hilbus.py``: I2C 9 clocks a byte with the address bytes, plus
one for each start, repeated start and stop; SPI 8 a byte). A stuck bus lasts the
constructor's ``timeout``, which the host is not told: its duration is None.

:class:`BusTrace` passes each one to the budgets that listen to its bus (``BUS``
events, :mod:`host.rig.config.budgets`), to the link log (``trace.jsonl``) and to the recorder,
where it is a string signal ``bus:<bus>`` (role ``bus``): a line of ``signals.csv`` and a
decoded string variable in the VCD (``buses.<bus>``), as :func:`describe` writes it.

What the run's output is to say about the buses, once each, it says here (:meth:`BusTrace.say`:
a ``[mpy-fil: ...]`` line in ``console.log``, :attr:`BusTrace.notes` for the trace header and
the command line): a poll that never ends (:mod:`host.rig.hardware.pollwatch`), and a chip's note (a
write to a register its model does not honour, ``sim_plant.buses``).
"""

from typing import NamedTuple

from host.artefacts.linklog import NO_LOG
from host.artefacts.recorder import ROLE_BUS
from host.link import frames as F
from host.rig.hardware.peripherals import BusPeripheral
from host.rig.hardware.pollwatch import PollWatch, poll_text

SCAN_ADDRESSES = 0x78 - 0x08
BYTES_SHOWN = 8  # bytes of a transfer spelled out in its decoded text
# a 1-Wire line's operations (the first byte: host/shim/_onewire.py) -> (text, time on the line in us:
# extmod/modonewire.c's reset 480 + 70 + 410, a bit's slot 70, a byte 8 slots)
ONEWIRE_OPS = {
    0: ("reset", 960),
    1: ("write bit", 70),
    2: ("write byte", 560),
    3: ("read bit", 70),
    4: ("read byte", 560),
}
OUTCOMES = {F.BUS_OK: "", F.BUS_NACK_ADDRESS: " NACK", F.BUS_NACK_DATA: " NACK data", F.BUS_STUCK: " TIMEOUT"}


class Transaction(NamedTuple):  # (immutable, made at every transfer: a tuple is the cheapest)
    t_us: int
    bus: str
    op: int
    address: int | None
    register: int | None
    wrote: bytes
    read: bytes
    status: int
    duration_us: int | None

    @property
    def reads(self) -> bool:
        """A read of the device's registers (bytes came back from an I2C device, or an SPI
        transfer with the read bit set on its first byte)."""
        if self.op == F.BUS_SPI_XFER:
            return bool(self.wrote) and bool(self.wrote[0] & 0x80) and len(self.wrote) > 1
        return bool(self.read) and self.status == F.BUS_OK

    def record(self) -> dict:
        """The fields ``trace.jsonl``'s BUS record adds."""
        return {"bus": self.bus, "register": self.register, "duration_us": self.duration_us}


def _ceil_us(clocks: int, clock_hz: int) -> int:
    return (clocks * 1_000_000 + clock_hz - 1) // clock_hz if clock_hz > 0 else 0


def duration_us(op: int, clock_hz: int, status: int, count: int, n_wrote: int, n_read: int) -> int | None:
    """A transfer's time on the bus, as the shim charges it (None: a stuck bus's timeout)."""
    if status == F.BUS_STUCK:
        return None
    if op == F.BUS_SPI_XFER:
        return _ceil_us(8 * n_wrote, clock_hz)
    if op == F.BUS_SCAN:
        return _ceil_us(SCAN_ADDRESSES * 11, clock_hz)
    if op in (F.BUS_XFER, F.BUS_XFER_NOSTOP):
        if status == F.BUS_NACK_ADDRESS:
            return _ceil_us(9 + 2, clock_hz)
        on_wire = 1 + (count if status == F.BUS_NACK_DATA else n_wrote)
        clocks = 9 * on_wire + 1 + (1 if op == F.BUS_XFER else 0)
        if n_read and n_wrote:
            clocks += 9 * (1 + n_read) + 1
        elif n_read:
            clocks += 9 * n_read
        return _ceil_us(clocks, clock_hz)
    return _ceil_us(9 * (n_wrote + n_read) or 1, clock_hz)  # a SoftI2C primitive


def transaction(t_us, bus, clock_hz, op, address, n_read, wrote, status, count, got) -> Transaction:
    if op == F.BUS_XFER and status == F.BUS_OK and clock_hz > 0 and bus[0] != "o":  # (the usual: a register chip's)
        clocks = 9 * len(wrote) + 11
        if n_read:
            clocks += 9 * (1 + n_read) + 1 if wrote else 9 * n_read
        duration = (clocks * 1_000_000 + clock_hz - 1) // clock_hz
        register = wrote[0] if wrote else None
        return Transaction(t_us, bus, op, address, register, bytes(wrote), bytes(got), status, duration)
    register = None
    if op == F.BUS_SPI_XFER:
        address = None
        register = wrote[0] & 0x7F if wrote else None
    elif op in (F.BUS_XFER, F.BUS_XFER_NOSTOP):
        register = wrote[0] if wrote else None
    else:
        address = None
    duration = duration_us(op, clock_hz, status, count, len(wrote), n_read)
    if bus.startswith("onewire:") and wrote:
        duration = ONEWIRE_OPS.get(wrote[0], ("", None))[1]
    return Transaction(t_us, bus, op, address, register, bytes(wrote), bytes(got), status, duration)


def _hex(data: bytes) -> str:
    shown = " ".join(f"{b:02x}" for b in data[:BYTES_SHOWN])
    return shown + (f" +{len(data) - BYTES_SHOWN}" if len(data) > BYTES_SHOWN else "")


_PRIMITIVES = {
    F.BUS_START: "start",
    F.BUS_STOP: "stop",
    F.BUS_WRITE: "write",
    F.BUS_READ: "read",
    F.BUS_READ_ACK: "read",
}


def describe(tx: Transaction) -> str:
    """The decoded text: ``0x6a reg 0x22 read 0c 00 ... (98 us)``, ``0x3c write 00 ae``,
    ``scan: 0x29 0x6a``, ``spi reg 0x0f read 6c``, ``0x68 NACK``."""
    took = "timeout" if tx.duration_us is None else f"{tx.duration_us} us"
    if tx.bus.startswith("onewire:") and tx.wrote and tx.wrote[0] in ONEWIRE_OPS:
        return f"{_onewire_text(tx)} ({took})"
    if tx.op == F.BUS_SCAN:
        return f"scan: {' '.join(f'0x{a:02x}' for a in tx.read) or 'none'}{OUTCOMES.get(tx.status, '')} ({took})"
    if tx.op in _PRIMITIVES:
        data = tx.wrote or tx.read
        return f"{_PRIMITIVES[tx.op]} {_hex(data)}".rstrip() + f"{OUTCOMES.get(tx.status, '')} ({took})"
    who = "spi" if tx.op == F.BUS_SPI_XFER else f"0x{tx.address:02x}"
    text = [who]
    if tx.op == F.BUS_SPI_XFER:
        if tx.reads:
            text += [f"reg 0x{tx.register:02x}", "read", _hex(tx.read[1:])]
        else:
            text += ["write", _hex(tx.wrote)]
    elif tx.read and tx.wrote and tx.status == F.BUS_OK:
        text += [f"reg 0x{tx.register:02x}", "read", _hex(tx.read)]
    elif tx.wrote:
        text += ["write", _hex(tx.wrote)]
    elif tx.read:
        text += ["read", _hex(tx.read)]
    return " ".join(text) + f"{OUTCOMES.get(tx.status, '')} ({took})"


def _onewire_text(tx: Transaction) -> str:
    """``reset: presence``, ``write byte cc``, ``read byte 28``; ``... (no device)`` on an empty line."""
    what = ONEWIRE_OPS[tx.wrote[0]][0]
    if tx.status != F.BUS_OK:
        return f"{what} (no device)"
    if what == "reset":
        return "reset: presence"
    value = tx.read[:1] if what.startswith("read") else tx.wrote[1:2]
    return f"{what} {_hex(value)}"


class BusTrace:
    """Each transaction to the budgets listening to its bus and to the recorder."""

    def __init__(self, hooks: dict, recorder, linklog, console=None):
        self.hooks = hooks  # bus name -> [call(tx)]
        self.recorder = recorder
        self.linklog = linklog  # () -> the rig's link log (it changes when a trace begins)
        self.console = console  # () -> the rig's console log (its notes go there)
        self.last_failed: Transaction | None = None  # (a board's OSError names no address: errors do)
        self.polls = PollWatch()
        self.notes: list[tuple[int, str]] = []  # (virtual t_us, text): said once each
        self.asking = False  # a BUS frame's transfer: the shim can be asked for its stack
        self.held_poll: tuple[int, str] | None = None  # a poll's note, until the shim's stack comes
        self.tap = None  # call(tx) for every transaction: a live rig's bus log (host/live)

    def say(self, t_us: int, text: str) -> None:
        """A note in the run's output: ``console.log``, the trace header, the command line."""
        self.notes.append((t_us, text))
        if self.console is not None:
            self.console().note(t_us, text)

    def answer(self, plant, info, h, t_us, op, address, n_read, data, unclocked=frozenset()) -> tuple:
        """A BUS frame's transfer answered from the plant's devices (status, count, bytes
        read), traced: a bus's transaction here, every transfer in the link log.
        ``unclocked``: SPI chips' clock inputs not on the SPI now (``Wiring.unclocked``)."""
        if unclocked:  # (an SPI bus's only: BusPeripheral.transfer)
            reply = info.peripheral.transfer(plant, info, op, address, n_read, data, unclocked=unclocked)
        else:
            reply = info.peripheral.transfer(plant, info, op, address, n_read, data)
        return self.replay(plant, info, h, t_us, op, address, n_read, data, reply)

    def replay(self, plant, info, h, t_us, op, address, n_read, data, reply: tuple) -> tuple:
        """A transfer's ``reply`` (status, count, bytes read), traced as :meth:`answer` traces
        it: also one the shim answered itself (``host.rig.hardware.busimage``)."""
        status, count, got = reply
        log = self.linklog()
        if isinstance(info.peripheral, BusPeripheral):  # (not a pin's bitstream)
            tx = self.transfer(t_us, info, op, address, n_read, data, status, count, got)
            if status != F.BUS_OK:
                self.last_failed = tx
            elif got if op != F.BUS_SPI_XFER else tx.reads:  # (Transaction.reads, its status OK)
                self._watch(plant, tx)
            if data:  # (a write: a chip may have a note)
                for text in plant.bus_notes(tx.bus):
                    self.say(t_us, text)
            if log is not NO_LOG:  # (a rig that traces: the record made only then)
                log.bus(t_us, h, op, address, data, reply, tx.record())
        elif log is not NO_LOG:
            log.bus(t_us, h, op, address, data, reply)
        return status, count, got

    def _watch(self, plant, tx: Transaction) -> None:
        answer = tx.read[1:] if tx.op == F.BUS_SPI_XFER else tx.read
        poll = self.polls.seen(tx.t_us, tx.bus, tx.address, tx.register, answer)
        if poll is not None:
            device = plant.bus_device(tx.bus, tx.address) if tx.op not in _PRIMITIVES else None
            text = poll_text(tx.t_us, tx.bus, tx.address, tx.register, answer, *poll, device)
            if tx.op in _PRIMITIVES:
                text += "; read through SoftI2C primitives: what was written before it is in trace.jsonl"
            if self.asking:  # (the reply asks the shim for the firmware's stack: said with it)
                self.held_poll = (tx.t_us, text)
            else:
                self.say(tx.t_us, text)

    def poll_stack(self, words: bytes) -> None:
        """The shim's stack for the poll held (a POLL of kind POLL_STACK): the note said with it."""
        stack = [line for line in words.decode(errors="replace").split("\n")[1:] if line]
        if self.held_poll is not None:
            t_us, text = self.held_poll
            self.held_poll = None
            self.say(t_us, text + ("; the firmware's stack, outermost first: " + " > ".join(stack) if stack else ""))

    def flush_poll(self) -> None:
        """A poll's note whose stack never came (the run ended first): said without it."""
        if self.held_poll is not None:
            self.say(*self.held_poll)
            self.held_poll = None

    def transfer(self, t_us, info, op, address, n_read, wrote, status, count, got) -> Transaction:
        tx = transaction(t_us, info.key, info.freq, op, address, n_read, wrote, status, count, got)
        hooks = self.hooks.get(tx.bus)
        if hooks:
            for call in hooks:
                call(tx)
        if self.recorder is not None:
            self.recorder.command(t_us, f"bus:{tx.bus}", describe(tx), role=ROLE_BUS, kind="text")
        if self.tap is not None:
            self.tap(tx)
        return tx


def failed_hint(bus_trace: "BusTrace | None", traceback: str) -> str:
    """For a firmware that ended on an OSError: the last bus transfer that failed, by
    address (the board's error, and so the loop's, is the errno alone)."""
    tx = bus_trace.last_failed if bus_trace is not None else None
    last = traceback.rstrip().splitlines()[-1] if traceback.strip() else ""
    if tx is None or not last.startswith("OSError"):
        return ""
    return (
        f"\n(the last bus transfer that failed: {tx.bus} {describe(tx)} at virtual t={tx.t_us / 1e6:.6f} s; "
        "a board's OSError names no address: docs/shim.md, 'Buses')"
    )

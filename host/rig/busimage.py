"""Bus reads the shim answers without an exchange (``docs/protocol.md``, BUS_IMAGE and
BUS_DONE; ``docs/clock.md``, "Bus reads inside the board").

With each STATE and each BUS_REPLY the host sends an image: for the I2C register reads the
firmware has made on its buses (an address, the register bytes written, the count read),
the bytes each would read now and the instant until which they stay the same. The shim
answers such a read inside that window itself and tells the host with its next message
(BUS_DONE, the image's entry and the instant); the host writes it to the trace as it writes
a transfer it answers, so the bus readings, budgets and notes are the same as when every
transfer is an exchange.

A read goes in the image only if it is **pure**: tried on a copy of the chip, it reads the
same bytes at the window's first and last instant and changes nothing of the chip but its
register pointer (no sample drawn from the plant's generator, no data-ready bit cleared,
no line that falls). Its window ends at the chip's next event in the plant (``next_us``:
a ranger's measurement, a data-ready line), its next output-data-rate tick (each
``DataReady``'s period, the IMU's samples) and its next self-clearing deadline; a chip
whose registers change otherwise (one that reads the plant at a transfer, ``take_in``,
or sets other parts' inputs, ``pass_on``, or has inputs of its own) is never imaged. The
image is taken with the plant at the firmware's instant, before the lookahead runs the
plant on.

The shim leaves itself as a BUS_REPLY would (its lookahead's changes dropped, the reply's
horizon: the image carries it) and the host, on BUS_DONE, does what a BUS frame at that
instant makes it do but reply: the plant brought to the instant, the transfer played on the
chips, traced; a reply other than the image's is a LinkError. So the firmware and the plant
go exactly as with an exchange, one round trip fewer. Images are sent only with
``MPY_FIL_BUS_IMAGES=1`` in the host's environment (today they cost more CPU than the
exchanges they save: docs/bench.md); without it every transfer is an exchange, the path the
images must match byte for byte (``host/tests/test_bus_image.py``).
"""

import copy
import os
import struct

from host.core.errors import LinkError
from host.link import frames as F
from sim_plant.buses import NEVER_US, BusDevice, BusSet, RegisterDevice, tick_after

ENV = "MPY_FIL_BUS_IMAGES"
MAX_READS = 6  # read shapes imaged a bus handle: the ones read last (the firmware's polls)
_POINTER = ("pointer", "pointed")
_BUS_SET = BusSet([])  # (its _xfer plays a transfer against the devices given)


def wanted() -> bool:
    """Images only when asked for (``MPY_FIL_BUS_IMAGES=1``): they save an exchange a pure
    read but cost more host and shim CPU than the exchange does today (docs/bench.md)."""
    return os.environ.get(ENV, "").strip() in ("1", "yes", "true")


def steady_until(device, t_us: int) -> int:
    """The first instant after ``t_us`` at which a read of ``device`` may answer otherwise
    (``t_us`` itself: the chip is never imaged)."""
    kind = type(device)
    if (
        not isinstance(device, RegisterDevice)
        or device.inputs
        or kind.take_in is not BusDevice.take_in
        or kind.pass_on is not BusDevice.pass_on
    ):
        return t_us
    until = getattr(device, "next_us", NEVER_US)
    periods = [getattr(device, bit.period)() for bit in device.DATA_READY]
    periods.append(device.period_us())
    for period in periods:
        if period:
            until = min(until, tick_after(t_us, period))
    for t_clear in device.clearing.values():
        until = min(until, t_clear)
    return until


def _trial(device, t_us: int, address: int, n_read: int, wrote: bytes, rng):
    """The read on a copy of ``device`` at ``t_us``: (bytes read, the copy) if it changed
    nothing but the pointer and drew nothing (from the plant's generator or its own), else None."""
    trial = copy.copy(device)
    for key, value in vars(device).items():
        if isinstance(value, (list, dict, set)):
            setattr(trial, key, value.copy())
    gens = {id(g): g for g in (rng, *vars(device).values()) if hasattr(g, "bit_generator")}
    states = {k: g.bit_generator.state for k, g in gens.items()}
    try:
        status, count, got = _BUS_SET._xfer(t_us, [trial], True, address, n_read, wrote)
    finally:
        drew = False
        for k, g in gens.items():
            if g.bit_generator.state != states[k]:
                g.bit_generator.state = states[k]
                drew = True
    if drew or status != F.BUS_OK or count != len(wrote):
        return None
    before, after = vars(device), vars(trial)
    if after.keys() != before.keys():
        return None
    try:
        if any(after[k] is not v and after[k] != v for k, v in before.items() if k not in _POINTER):
            return None
    except (TypeError, ValueError):  # (a value that does not compare as one truth: not imaged)
        return None
    return got, trial


class BusImages:
    """The reads the firmware makes on each bus handle, and the image last sent."""

    def __init__(self, plant, wiring, bus_trace):
        self.plant = plant
        self.wiring = wiring
        self.bus_trace = bus_trace
        self.on = wanted()
        self.reads: dict[int, list] = {}  # handle -> [(address, wrote, n_read)], read last at the end
        self.impure: set = set()  # (handle, address, wrote, n_read) found to change the chip: never imaged
        self.once: set = set()  # the same, read once so far (a read made once is not imaged)
        self.sent: list = []  # the last image's entries: (handle, address, wrote, n_read, got, horizon_us)
        self.local = 0  # transfers answered in the shim

    def forget(self) -> None:
        """The firmware restarted: its handles and reads are new."""
        self.reads, self.sent, self.impure, self.once = {}, [], set(), set()

    def seen(self, h: int, op: int, address: int, n_read: int, wrote: bytes, status: int) -> None:
        """A BUS frame's transfer: a register read to image from now on."""
        if not self.on or op != F.BUS_XFER or not wrote or not n_read or status != F.BUS_OK:
            return
        shape = (address, bytes(wrote), n_read)
        key = (h, *shape)
        if key in self.impure:
            return
        if key in self.once:  # (read again: a poll, or a read the firmware repeats)
            self._last(h, shape)
        else:
            self.once.add(key)

    def _last(self, h: int, shape: tuple) -> None:
        shapes = self.reads.setdefault(h, [])
        if shapes and shapes[-1] == shape:
            return
        if shape in shapes:
            shapes.remove(shape)
        shapes.append(shape)
        if len(shapes) > MAX_READS:
            del shapes[0]

    def image(self, t_us: int, horizon_us: int) -> bytes | None:
        """The BUS_IMAGE payload for the plant at ``t_us`` (None: nothing to image), whose
        reads leave the shim the horizon ``horizon_us`` (the lease a BUS_REPLY would carry:
        the plant's next event, or the run's end), valid no later than it."""
        self.sent = []
        if not self.reads or horizon_us <= t_us:
            return None
        rng = self.plant.rng
        entries = []
        for h, shapes in self.reads.items():
            info = self.wiring.handles[h]
            for address, wrote, n_read in list(shapes):
                device = self.plant.bus_device(info.key, address)
                if device is None:
                    continue
                until = min(steady_until(device, t_us), horizon_us)
                if until <= t_us:
                    continue
                first = _trial(device, t_us, address, n_read, wrote, rng)
                if first is None:
                    self.impure.add((h, address, wrote, n_read))  # (a sample read, a flag cleared: the host's)
                    self.reads[h] = [s for s in self.reads[h] if s != (address, wrote, n_read)]
                    continue
                last = _trial(device, until - 1, address, n_read, wrote, rng)
                if last is None or last[0] != first[0]:
                    continue
                self.sent.append((h, address, wrote, n_read, first[0], horizon_us))
                entries.append(F.pack_bus_image_entry(h, address, until, horizon_us, wrote, first[0]))
        if not entries:
            return None
        return struct.pack(F.BUS_IMAGE_FMT, t_us, len(entries)) + b"".join(entries)

    def done(self, rig, t_us: int, index: int) -> None:
        """BUS_DONE: the shim answered entry ``index`` of the last image at ``t_us``. The host
        does what a BUS frame at ``t_us`` makes it do (the plant brought to ``t_us``, the
        transfer played on the chips and traced) but send the reply, and checks that the
        reply is the one the shim took: the bytes and the horizon."""
        try:
            h, address, wrote, n_read, got, horizon_us = self.sent[index]
        except IndexError:
            raise LinkError(
                f"BUS_DONE names entry {index} of a bus image of {len(self.sent)} (link protocol error)"
            ) from None
        rig.clock.catch_up(t_us)
        info = self.wiring.handles[h]
        self.local += 1
        rig.stats.bus_local += 1
        reply = rig.bus_trace.answer(self.plant, info, h, t_us, F.BUS_XFER, address, n_read, wrote)
        lease = rig.clock.lease_us()
        if reply != (F.BUS_OK, len(wrote), got) or lease != horizon_us:
            raise LinkError(
                f"a bus read the shim answered from the host's image at t={t_us} us ({info.key} 0x{address:02x} "
                f"register {wrote.hex()}) reads {reply[2].hex()} with horizon {lease} us on the chips, expected "
                f"{got.hex()} with horizon {horizon_us} us as imaged (host.rig.busimage: the image was wrong)"
            )
        self._last(h, (address, wrote, n_read))

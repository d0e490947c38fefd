"""Bus reads the shim answers without an exchange (``docs/protocol.md``, BUS_IMAGE and
BUS_DONE; ``docs/clock.md``, "Bus reads inside the board").

With each STATE and each BUS_REPLY the host sends an image: for the I2C register reads the
firmware has made on its buses (an address, the register bytes written, the count read),
the bytes each would read and the window of instants in which it reads them. The shim
answers such a read inside its window itself and tells the host with its next message
(BUS_DONE, the image's entry and the instant); the host plays it on the chip and writes it
to the trace as it writes a transfer it answers, so the bus readings, budgets and notes
are the same as when every transfer is an exchange.

Two kinds of entries:

- a **pure** read's (tried on a copy of the chip, it reads the same bytes at the window's
  first and last instant and changes nothing of the chip but its register pointer: a
  status poll, an identity, a register between samples). Its window ends at the chip's
  next event in the plant (``next_us``: a ranger's measurement, a data-ready line), its
  next output-data-rate tick (each ``DataReady``'s period, the IMU's samples) and its next
  self-clearing deadline (:func:`steady_until`).
- a **stream**'s (:class:`Stream`): the reads of a chip that change it (a sample drawn
  from the plant's generator, data-ready bits cleared), played on copies over its next
  windows from the image's instant, as the firmware reads it in turn: in each window the
  reads that change nothing, the one that changes the chip, the reads after it. Each such
  entry carries the count of the stream's changing reads it needs answered before it and
  the count it leaves; the shim answers it only then, so a sample is answered only when
  every sample before it in the window was drawn as the host drew it (the generator at the
  same state, the chip the same), and any other read is an exchange. One stream an image
  draws from the plant's generator (two chips' draws interleave as the firmware reads them).

A chip whose registers change otherwise (one that reads the plant at a transfer,
``take_in``, or sets other parts' inputs, ``pass_on``, or has inputs of its own, or whose
reads a scenario's set-controls may set) is never imaged. The image is taken with the
plant at the firmware's instant, before the lookahead runs the plant on, and no entry
outlives the plant's next event (the horizon): no other part draws from the generator or
changes the body's motion before it.

The shim leaves itself as a BUS_REPLY would (its lookahead's changes dropped, the reply's
horizon: the image carries it) and the host, on BUS_DONE, does what a BUS frame at that
instant makes it do but reply: the plant brought to the instant, the transfer played on the
chip, traced; a reply other than the image's is a LinkError. So the firmware and the plant
go exactly as with an exchange, one round trip fewer. Images are sent in lockstep when
``MPY_FIL_BUS_IMAGES=1`` is in the host's environment; by default every transfer is an
exchange, the path the images must match byte for byte (``host/tests/test_bus_image.py``):
on a quiet machine that path is the faster one today (building the images costs the host
more than the round trips they save; docs/bench.md, "Bus images: off by default again").

What keeps them cheap: a pure read's entry is kept (``known``) while no BUS frame reaches
its chip and its steady window lasts, so an image mostly repeats entries it has, and a read
is tried again only after a transfer to its chip or past its window, and not while its next
read, at the pace the firmware reads it, falls after that window (an IMU's data-ready poll
is tried once a sample, at the new tick); a stream's windows are kept from image to image
while the chip and the generator are as one of them left them (a motion change, a write,
another part's draw: played anew), and tried at a window's start only where the chip's
class says its reads change at its declared instants alone (``READS_STEADY``); a trial
copies the chip's attributes once, and a window's reads that change nothing are made on one
copy (each leaves it as the chip is), compared in place; BUS_DONE of a stream's sample read
installs the chip and the generator its trial left instead of drawing it again; a kind
of message whose last images answered nothing gets one only now and then (``IDLE``,
``PROBE``); and the shim reads the payload in place at a transfer
(``_hilframe.bus_image_find``), decoding nothing when it arrives.
"""

import os

from host.core.errors import LinkError
from host.link import frames as F
from sim_plant.buses import NEVER_US, BusDevice, BusSet, RegisterDevice

ENV = "MPY_FIL_BUS_IMAGES"
MAX_READS = 6  # read shapes imaged a bus handle: the ones read last (the firmware's polls)
IDLE = 4  # images in a row with a kind of message that answered nothing: from then on,
PROBE = 16  # an image with every 16th message of that kind only
_BUS_SET = BusSet([])  # (its _xfer plays a transfer against the devices given)


def wanted() -> bool:
    """Images only when asked (``MPY_FIL_BUS_IMAGES=1``); by default every transfer is an
    exchange, the path the images are held to (docs/bench.md, "Bus images: off by default
    again")."""
    return os.environ.get(ENV, "").strip().lower() in ("1", "yes", "true", "on")


def _timeline(device) -> bool:
    """Whether a scenario's set-controls may set what ``device`` reads (its ``controls``, the
    plant's timeline, has entries: an MPU6050's axes set by a scenario): never imaged."""
    controls = device.__dict__.get("controls")
    return controls is not None and bool(getattr(controls, "entries", None))


def _self_contained(device) -> bool:
    """A register chip whose reads depend on its own registers, the instant and the plant's
    generator alone: no inputs, no ``take_in`` or ``pass_on`` of its own, no scenario
    setting what it reads."""
    kind = type(device)
    return (
        isinstance(device, RegisterDevice)
        and not device.inputs
        and kind.take_in is BusDevice.take_in
        and kind.pass_on is BusDevice.pass_on
        and not _timeline(device)
    )


def steady_until(device, t_us: int, contained: bool | None = None) -> int:
    """The first instant after ``t_us`` at which a read of ``device`` may answer otherwise
    (``t_us`` itself: the chip is never imaged); ``contained``: :func:`_self_contained`, found
    already (a stream's copies: the chip's)."""
    if not (_self_contained(device) if contained is None else contained):
        return t_us
    until = getattr(device, "next_us", NEVER_US)
    period = device.period_us()
    if period:
        until = min(until, (t_us // period + 1) * period)  # (tick_after)
    for bit in device.DATA_READY:
        other = getattr(device, bit.period)()
        if other and other != period:
            until = min(until, (t_us // other + 1) * other)
    for t_clear in device.clearing.values():
        if t_clear < until:
            until = t_clear
    return until


class _Draws(Exception):
    """A trial read drew from a generator (the tripwire in its place on the copy)."""


class _Tripwire:
    """A chip copy's generator during a trial: any use of it is a draw."""

    def __getattr__(self, name):
        raise _Draws(name)


_TRIPWIRE = _Tripwire()
_PLAIN = frozenset((int, float, bool, str, bytes, tuple, frozenset, type(None)))  # (neither copied nor a generator)


def _trials(device, instants: tuple, address: int, n_read: int, wrote: bytes, rng) -> list:
    """The read on one copy of ``device`` at each of ``instants`` in turn: the bytes read at
    each and the register pointer the read leaves (``pointer``, ``pointed``), up to the first
    read that changed anything of the chip but its pointer or drew from a generator (the
    plant's or its own): None there, and nothing after. The copy's
    generators are tripwires; the plant's, where the chip does not hold it, is checked by
    its state. A pure read leaves the copy as the chip is, so the next instant's read is
    tried on the same copy."""
    before = device.__dict__
    state = before.copy()
    held = []
    for key, value in state.items():
        if type(value) in _PLAIN:
            continue
        if isinstance(value, (list, dict, set)):
            state[key] = value.copy()
        elif hasattr(value, "bit_generator"):
            held.append(key)
    trial = object.__new__(type(device))
    trial.__dict__.update(state)
    state = trial.__dict__
    plant_rng = rng is not None and not any(before[k] is rng for k in held)
    out = []
    for t_us in instants:
        for key in held:
            state[key] = _TRIPWIRE
        saved = rng.bit_generator.state if plant_rng else None
        try:
            status, count, got = _BUS_SET._xfer(t_us, [trial], True, address, n_read, wrote)
        except _Draws:
            status = None
        finally:
            for key in held:
                state[key] = before[key]
        if plant_rng and rng.bit_generator.state != saved:
            rng.bit_generator.state = saved
            status = None
        if status != F.BUS_OK or count != len(wrote):
            out.append(None)
            return out
        left = (state["pointer"], state["pointed"])
        state["pointer"], state["pointed"] = before["pointer"], before["pointed"]
        try:
            same = state == before
        except (TypeError, ValueError):  # (a value that does not compare as one truth: not imaged)
            same = False
        out.append((got, left) if same else None)
        if not same:
            return out
    return out


WINDOW_MAX = 0xFFFFFFFF  # an entry's window ends at most this many us after the image's instant
STREAM_TICKS = 8  # a stream's windows imaged ahead at most (its chip's sample ticks)
STREAMS = 15  # streams an image holds at most (the shim's counts: a bytearray of 16)
MAX_IMAGE = 3000  # an image's payload at most, in bytes (a frame's is 4096)


def streamable(device, rng) -> bool:
    """Whether ``device``'s reads that change it (a sample drawn, a data-ready bit cleared)
    may be imaged as a stream: a register chip whose reads depend on nothing but its own
    state, the instant and the plant's generator (no inputs, no ``take_in`` or ``pass_on``,
    no generator of its own)."""
    if not _self_contained(device):
        return False
    return all(value is rng for value in device.__dict__.values() if hasattr(value, "bit_generator"))


_CONTAINERS: dict = {}  # a chip's class -> (its attributes' names, the names that hold a list, dict or
# set, the names that hold the plant's generator): found again where a chip's names differ


class _Watched:
    """The plant's generator as a trial's copy of a chip holds it: any use of it is a draw
    (noted in ``drew``), passed on to the generator."""

    __slots__ = ("rng", "drew")

    def __init__(self, rng):
        self.rng, self.drew = rng, False

    def __getattr__(self, name):
        self.drew = True
        return getattr(self.rng, name)


def _kinds(kind: type, state: dict) -> tuple:
    """The names of a chip's attributes that hold containers, and the generator (``state``:
    its attributes; the same names, the same kinds)."""
    kinds = _CONTAINERS.get(kind)
    if kinds is None or state.keys() != kinds[0]:
        containers = tuple(k for k, v in state.items() if isinstance(v, (list, dict, set)))
        generators = tuple(k for k, v in state.items() if isinstance(v, _Watched) or hasattr(v, "bit_generator"))
        kinds = _CONTAINERS[kind] = frozenset(state), containers, generators
    return kinds[1], kinds[2]


def _clone(device):
    """A copy of ``device`` whose containers are copies (a trial's)."""
    state = device.__dict__.copy()
    for name in _kinds(type(device), state)[0]:
        state[name] = state[name].copy()
    copy = object.__new__(type(device))
    copy.__dict__ = state
    return copy


def _same(device, chip) -> bool:
    """Whether ``device`` is as ``chip`` (a copy) is, its register pointer aside."""
    state, chip_state = device.__dict__, chip.__dict__
    left = state["pointer"], state["pointed"]
    state["pointer"], state["pointed"] = chip_state["pointer"], chip_state["pointed"]
    try:
        return state == chip_state
    except (TypeError, ValueError):  # (a value that does not compare as one truth)
        return False
    finally:
        state["pointer"], state["pointed"] = left


def _as(copy, chip) -> tuple | None:
    """Whether a trial's read left ``copy`` as ``chip`` is, its register pointer aside: then
    the pointer the read left, and ``copy`` is made ``chip``'s equal (to read on again); else
    None, ``copy`` as the read left it."""
    state, chip_state = copy.__dict__, chip.__dict__
    left = state["pointer"], state["pointed"]
    state["pointer"], state["pointed"] = chip_state["pointer"], chip_state["pointed"]
    try:
        same = state == chip_state
    except (TypeError, ValueError):  # (a value that does not compare as one truth: not imaged)
        same = False
    if same:
        return left
    state["pointer"], state["pointed"] = left
    return None


_AT = [None]  # the state the plant's generator was last set to or read at in a play (None: not known)


def _read(device, t_us: int, shape: tuple, rng, rng_state, copy=None, generators=None):
    """The read ``shape`` on a copy of ``device`` at ``t_us``, the plant's generator at
    ``rng_state``: (bytes read, the copy after it, the generator's state after it: the same
    object if the read drew nothing), or None. ``copy``: the copy to read on (``device``'s
    equal; made here if None); ``generators``: the names of its attributes that hold the
    plant's generator (found here if None). The generator is set only where a read before
    drew from it (its state read after a draw only: the copy's is watched); the copy holds
    the plant's generator again after the read."""
    address, wrote, n_read = shape
    if _AT[0] is not rng_state:
        rng.bit_generator.state = rng_state
        _AT[0] = rng_state
    if copy is None:
        copy = _clone(device)
    state = copy.__dict__
    if generators is None:
        generators = _kinds(type(copy), state)[1]
    watched = _Watched(rng)
    for name in generators:
        state[name] = watched
    try:
        if copy.address != address:
            return None
        status, count, got = _BUS_SET._play(t_us, copy, True, n_read, wrote)
    except (ArithmeticError, LookupError, TypeError, ValueError):
        _AT[0] = None
        return None
    finally:
        for name in generators:
            state[name] = rng
    after = rng_state
    if watched.drew:
        after = _AT[0] = rng.bit_generator.state
    if status != F.BUS_OK or count != len(wrote):
        return None
    return got, copy, after


class Window:
    """One steady window ``[a, b)`` of a stream's chip (no tick, event or deadline of its
    inside): the chip (``chip``, a copy) and the plant's generator's state (``rng``) as the
    stream left them at ``a`` (``count`` of its changing reads answered), the reads that
    change nothing then (``pure``: (shape, bytes, the register pointer it leaves) each), the
    one read that changes the chip (``change``: shape, bytes) and after it the chip and the
    generator's state (``after``) and the reads that change nothing (``again``). ``cut``:
    ``b`` is the horizon it was played to, not the chip's own end of the window."""

    __slots__ = (
        *("a", "b", "cut", "steady", "held", "count", "chip", "rng"),
        *("pure", "change", "draws", "after", "again"),
    )

    def reach(self, horizon_us: int) -> "Window":
        """The window cut at a nearer horizon, to ``horizon_us`` (no further than the chip's
        own end): its reads hold there too where its chip's do through a steady window
        (``held``: ``READS_STEADY``), so nothing is played again."""
        w = Window()
        for name in Window.__slots__:
            setattr(w, name, getattr(self, name))
        w.b, w.cut = min(self.steady, horizon_us), self.steady > horizon_us
        return w

    def end_state(self) -> tuple:
        """The chip (a copy, never changed) and the generator's state the next window starts from."""
        return self.after if self.change is not None else (self.chip, self.rng)


def _pure(chip, a: int, b: int, shape: tuple, rng, rng_state, first, generators=None):
    """The bytes ``shape`` reads on ``chip`` throughout ``[a, b)`` (tried at ``a`` and at
    ``b - 1``) changing nothing of it (the generator at ``rng_state``) and the register
    pointer it leaves, or None; ``first``: the read at ``a``, made already (its copy, if the
    read changed nothing of it, made ``chip``'s equal again: :func:`_as`)."""
    if first is None or first[2] is not rng_state:
        return None
    left = _as(first[1], chip)
    if left is None:
        return None
    if b - 1 > a:
        last = _read(chip, b - 1, shape, rng, rng_state, None, generators)
        if last is None or last[0] != first[0]:
            first[1].pointer, first[1].pointed = left  # (as the read left it)
            return None
    return first[0], left


def play(chip, rng_state, count: int, a: int, horizon_us: int, shapes: tuple, rng, n: int) -> list:
    """Up to ``n`` windows of a stream from ``a`` (:class:`Window`), no further than
    ``horizon_us``: ``chip`` (a copy, never changed) and the generator at ``rng_state`` as
    the firmware finds them at ``a``, ``count`` changing reads answered before. Each window
    tried on copies at its first and its last instant (a chip may read otherwise inside a
    window its declared instants do not end: the HMC5883L's RDY, clear for 250 us after each
    sample), at its first only where the chip's class says its reads change at those
    instants alone (``READS_STEADY``: its samples at its output data rate's ticks, its
    data-ready bits with them); the generator's state set back after. A read that changed
    nothing leaves its copy as the chip is, so the next read is made on the same copy (one
    copy a window: the one its changing read takes)."""
    real = _AT[0] = rng.bit_generator.state
    out = []
    ends = not getattr(chip, "READS_STEADY", False)
    spare = None  # a copy of chip as it is (a pure read's, made its equal again)
    generators = _kinds(type(chip), chip.__dict__)[1]
    contained = _self_contained(chip)
    try:
        for _ in range(n):
            steady = steady_until(chip, a, contained)
            b = min(steady, horizon_us)
            if b <= a or count >= 250:
                break
            end = b if ends else a + 1  # (tried at end - 1 too)
            w = Window()
            w.a, w.b, w.cut, w.count, w.chip, w.rng = a, b, steady > horizon_us, count, chip, rng_state
            w.steady, w.held = steady, not ends
            w.pure, w.change, w.draws, w.after, w.again = [], None, False, None, []
            for shape in shapes:
                first = _read(chip, a, shape, rng, rng_state, _clone(chip) if spare is None else spare, generators)
                spare = None
                if first is None:
                    continue
                got = _pure(chip, a, end, shape, rng, rng_state, first, generators)
                if got is not None:
                    spare = first[1]
                    w.pure.append((shape, *got))
                    continue
                if w.change is not None:
                    continue
                if getattr(first[1], "next_us", None) != getattr(chip, "next_us", None):  # (an event: the host's)
                    continue
                if end - 1 > a:
                    last = _read(chip, end - 1, shape, rng, rng_state, None, generators)
                    if last is None or last[0] != first[0] or last[2] != first[2] or not _same(last[1], first[1]):
                        continue
                w.change, w.after, w.draws = (shape, first[0]), (first[1], first[2]), first[2] is not rng_state
            if w.change is not None:
                chip, rng_after = w.after
                spare = None  # (a copy of the chip before it)
                for shape in shapes:  # (read again after it in the same window: not the sample itself)
                    if shape == w.change[0]:
                        continue
                    first = _read(chip, a, shape, rng, rng_after, _clone(chip) if spare is None else spare, generators)
                    spare = None
                    got = _pure(chip, a, end, shape, rng, rng_after, first, generators)
                    if got is not None:
                        spare = first[1]
                        w.again.append((shape, *got))
                rng_state, count = rng_after, count + 1
            out.append(w)
            a = b
    finally:
        if _AT[0] is not real:
            rng.bit_generator.state = real
        _AT[0] = None
    return out


class Stream:
    """A chip's stream as last played (its windows from the last image's instant on), kept
    for the next image: while the chip and the generator are as one of its windows left
    them, its windows from there on hold (the same bytes at the same instants)."""

    def __init__(self, shapes: tuple, windows: list):
        self.shapes, self.windows = shapes, windows
        self.played = 0  # windows played on copies (what the cache spared: the tests' counts)
        self.ticks = STREAM_TICKS  # windows played ahead at most (1: the firmware reads it slower than it samples)

    def entries(self, device, t_us: int, horizon_us: int, rng, may_draw: bool) -> list:
        """The stream's answers from ``t_us`` (:func:`stream`'s), its windows taken from the
        last image's where the chip and the generator are as one of them left them, played
        anew from the first that its horizon cut short, or from ``t_us`` where none is."""
        real = rng.bit_generator.state
        windows, base, after = None, 0, False
        for i, w in enumerate(self.windows):
            if w.a <= t_us < (w.steady if w.cut and w.held else w.b):  # (a held window reaches its chip's end)
                if real == w.rng and _same(device, w.chip):
                    windows, base = self.windows[i:], w.count
                elif w.change is not None and real == w.after[1] and _same(device, w.after[0]):
                    windows, base, after = self.windows[i:], w.count + 1, True
                break
        if windows is None:
            windows = self.windows = play(_clone(device), real, 0, t_us, horizon_us, self.shapes, rng, self.ticks)
            self.played += len(windows)
        else:
            for j, w in enumerate(windows):
                if w.a >= horizon_us:
                    windows = windows[:j]
                    break
                if w.cut and w.b < horizon_us:  # (played to a nearer horizon: on from there)
                    if w.held:
                        windows = [*windows[:j], w.reach(horizon_us)]
                    else:
                        more = play(w.chip, w.rng, w.count, w.a, horizon_us, self.shapes, rng, self.ticks - j)
                        self.played += len(more)
                        windows = windows[:j] + more
                    break
            if windows and len(windows) < self.ticks and not windows[-1].cut and windows[-1].b < horizon_us:
                last = windows[-1]
                chip, rng_state = last.end_state()
                count = last.count + (last.change is not None)
                n = self.ticks - len(windows)
                more = play(chip, rng_state, count, last.b, horizon_us, self.shapes, rng, n)
                self.played += len(more)
                windows = windows + more
            self.windows = windows
        return _answers(windows, t_us, horizon_us, base, after, may_draw)


def _answers(windows: list, t_us: int, horizon_us: int, base: int, after: bool, may_draw: bool) -> list:
    """The entries of ``windows`` from ``t_us`` to ``horizon_us`` (``Stream.entries``), the
    counts from ``base`` (``after``: the first window's changing read answered already)."""
    out = []
    for k, w in enumerate(windows):
        a, b, need = max(w.a, t_us), min(w.b, horizon_us), w.count - base
        if a >= b:
            break
        if not (k == 0 and after):
            out.extend((shape, a, b, need, need, got, left) for shape, got, left in w.pure)
            if w.change is None:
                continue
            if w.draws and not may_draw:
                break
            out.append((w.change[0], a, b, need, need + 1, w.change[1], w))
        out.extend((shape, a, b, need + 1, need + 1, got, left) for shape, got, left in w.again)
    return out


def stream(device, shapes: tuple, t_us: int, horizon_us: int, rng, may_draw: bool) -> list:
    """What ``device`` answers to each of ``shapes`` (address, written, count) over its next
    sample windows from ``t_us`` (its steady windows: :func:`steady_until`, no further than
    ``horizon_us``), as the firmware reads it in turn: in each window the reads that change
    nothing, then the one read that changes the chip (a sample drawn from the plant's
    generator, its data-ready bits cleared), then the reads that change nothing after it.
    Each answer is an entry (shape, from, until, the stream's count it needs, the count it
    leaves, bytes, what the read does to the chip: the register pointer it leaves, or, the
    read that changes it, its :class:`Window`): a read in that window answers so only if the reads answered before it
    were the ones the stream expects (the count), so the generator has drawn what it drew
    here and the chip is as it is here; any other read is the host's. Tried on copies with
    the generator's state saved and set back. ``may_draw``: whether a read may draw from the
    generator (one stream an image may: two chips' draws interleave as the firmware reads
    them; the stream stops before the first that draws)."""
    return Stream(shapes, []).entries(device, t_us, horizon_us, rng, may_draw)


_CONTAINER_TYPES = (list, dict, set)


def _install(device, w: "Window", rng) -> bool:
    """The changing read of window ``w`` answered by the shim: ``device`` made what the
    read left the window's copy (its containers updated in place, so what holds them sees
    it), the plant's generator set where the read drew; False (nothing done) where the chip
    or the generator is not as the window found them."""
    copy = w.after[0].__dict__
    state = device.__dict__
    if not state.keys() <= copy.keys() or not _same(device, w.chip):
        return False
    if w.draws:
        if rng.bit_generator.state != w.rng:
            return False
        rng.bit_generator.state = w.after[1]
    for name, value in copy.items():
        old = state.get(name)
        if old is value:
            continue
        kind = type(value)
        if kind in _CONTAINER_TYPES:
            if type(old) is kind:
                if old == value:
                    continue
                if kind is list:
                    old[:] = value
                else:
                    old.clear()
                    old.update(value)
            else:
                state[name] = value.copy()
        else:
            state[name] = value
    return True


class BusImages:
    """The reads the firmware makes on each bus handle, and the image last sent."""

    def __init__(self, plant, wiring, bus_trace):
        self.plant = plant
        self.wiring = wiring
        self.bus_trace = bus_trace
        self.on = wanted()
        self.reads: dict[int, list] = {}  # handle -> [(address, wrote, n_read)], read last at the end
        self.impure: set = set()  # (handle, address, wrote, n_read) found to change the chip: never imaged
        self.streaming: set = set()  # (bus, address): chips whose reads change them, imaged as streams
        self.streams: dict = {}  # (bus, address) -> its Stream as last played
        self.once: set = set()  # the same, read once so far (a read made once is not imaged)
        # the last image's entries by offset: (handle, address, wrote, n_read, got, horizon_us,
        # the register pointer the read leaves)
        self.sent: dict = {}
        self.local = 0  # transfers answered in the shim
        self.plain_buses: dict = {}  # bus -> no chip on it reads the plant at a transfer (_plain)
        # (handle, read shape) -> (version, t_us, steady_us, bytes read): a pure read tried at
        # t_us and at steady_us - 1, valid between them while no transfer reaches its chip
        # (bytes read None: one not imaged between them, its next read due after them)
        self.known: dict = {}
        self.versions: dict = {}  # (bus, address) or bus -> transfers played on it (the BUS frames')
        self.read_at: dict = {}  # (handle, read shape) -> the instants of its last two reads
        # What the images sent with each kind of message did (a STATE; a BUS_REPLY to a read
        # shape): kinds whose last IDLE images answered nothing get one every PROBE-th time
        self.sent_with = None  # the kind of message the last image went with
        self.used = False  # the shim answered a read from it
        self.idle: dict = {}  # kind -> images in a row that answered nothing
        self.passed: dict = {}  # kind -> messages without an image since the last

    def _plain(self, bus: str) -> bool:
        """No chip on ``bus`` reads the plant or sets its inputs at a transfer (``take_in``,
        ``pass_on``: every transfer on the bus calls them, whatever its address)."""
        plain = self.plain_buses.get(bus)
        if plain is None:
            kinds = [type(d) for d in self.plant.bus_devices() if d.bus == bus]
            plain = self.plain_buses[bus] = bool(kinds) and all(
                k.take_in is BusDevice.take_in and k.pass_on is BusDevice.pass_on for k in kinds
            )
        return plain

    def forget(self) -> None:
        """The firmware restarted: its handles and reads are new."""
        self.reads, self.sent, self.impure, self.once = {}, {}, set(), set()
        self.streaming, self.streams = set(), {}
        self.known, self.versions, self.read_at = {}, {}, {}
        self.sent_with, self.used, self.idle, self.passed = None, False, {}, {}

    def seen(self, t_us: int, h: int, op: int, address: int, n_read: int, wrote: bytes, status: int) -> None:
        """A BUS frame's transfer at ``t_us``: a register read to image from now on. What it
        reached of the chips is known no more (the chip at ``address``: an I2C transfer; else
        its bus's)."""
        if not self.on:
            return
        key = self.wiring.handles[h].key
        where = (key, address) if op in (F.BUS_XFER, F.BUS_XFER_NOSTOP) else key
        self.versions[where] = self.versions.get(where, 0) + 1
        if op != F.BUS_XFER or not wrote or not n_read or status != F.BUS_OK:
            return
        shape = (address, bytes(wrote), n_read)
        key = (h, *shape)
        if key in self.impure:
            return
        self._read_at(h, shape, t_us)
        if key in self.once:  # (read again: a poll, or a read the firmware repeats)
            self._last(h, shape)
        else:
            self.once.add(key)

    def _read_at(self, h: int, shape: tuple, t_us: int) -> None:
        last = self.read_at.get((h, shape))
        self.read_at[(h, shape)] = (t_us if last is None else last[1], t_us)

    def _last(self, h: int, shape: tuple) -> None:
        shapes = self.reads.setdefault(h, [])
        if shapes and shapes[-1] == shape:
            return
        if shape in shapes:
            shapes.remove(shape)
        shapes.append(shape)
        if len(shapes) > MAX_READS:
            del shapes[0]

    def image(self, t_us: int, horizon_us: int, kind=None) -> bytes | None:
        """The BUS_IMAGE payload for the plant at ``t_us`` (None: nothing to image), whose
        reads leave the shim the horizon ``horizon_us`` (the lease a BUS_REPLY would carry:
        the plant's next event, or the run's end), valid no later than it; ``kind``: the
        message it goes with (with a kind whose last IDLE images answered nothing, one is
        sent every PROBE-th time: after an IMU's sample read the firmware's callback returns
        and waits, and the image would be built for nothing)."""
        self.sent = {}
        if not self._worth(kind) or not self.reads or horizon_us <= t_us:
            return None
        entries, sent = [], []
        known, versions = self.known, self.versions
        streams: dict = {}  # (bus, address) -> [(handle, read shape)]: its reads imaged as a stream
        for h, shapes in self.reads.items():
            bus = self.wiring.handles[h].key
            on_bus = versions.get(bus, 0)
            for shape in list(shapes):
                address, wrote, n_read = shape
                if (bus, address) in self.streaming:
                    streams.setdefault((bus, address), []).append((h, shape))
                    continue
                version = (on_bus, versions.get((bus, address), 0))
                hit = known.get((h, shape))
                if hit is None or hit[0] != version or not hit[1] <= t_us < hit[2]:
                    hit = self._try(h, bus, shape, t_us, horizon_us, version)
                    if hit is None:
                        continue
                if hit[3] is None:  # (not imaged in this window)
                    continue
                until = min(hit[2], horizon_us)
                if until <= t_us:
                    continue
                got, left = hit[3]
                sent.append((h, address, wrote, n_read, got, horizon_us, left))
                entries.append((h, address, 0, min(until - t_us, WINDOW_MAX), 0, 0, 0, wrote, got))
        if streams:
            self._streams(streams, t_us, horizon_us, entries, sent)
        if not entries:
            return None
        self.sent = dict(zip(F.bus_image_offsets(entries), sent, strict=True))
        self.sent_with, self.used = kind, False
        return F.pack_bus_image(t_us, horizon_us, entries)

    def _streams(self, streams: dict, t_us: int, horizon_us: int, entries: list, sent: list) -> None:
        """The stream of each chip in ``streams`` (:class:`Stream`, kept from image to image)
        added to ``entries`` and ``sent``; one stream an image draws from the plant's
        generator; the payload kept under ``MAX_IMAGE``."""
        rng = self.plant.rng
        drawn = False
        size = F.BUS_IMAGE_LEN + sum(F.BUS_IMAGE_ENTRY_LEN + len(e[7]) + len(e[8]) for e in entries)
        for number, (key, pairs) in enumerate(streams.items(), 1):
            device = self.plant.bus_device(*key)
            if number > STREAMS or device is None:
                break
            shapes = tuple(dict.fromkeys(shape for _h, shape in pairs))
            kept = self.streams.get(key)
            if kept is None or kept.shapes != shapes:
                kept = self.streams[key] = Stream(shapes, [])
            kept.ticks = self._ticks(device, pairs)
            answers = kept.entries(device, t_us, horizon_us, rng, not drawn)
            drawn = drawn or any(w.draws for w in kept.windows)
            for shape, a, b, need, then, got, how in answers:
                address, wrote, n_read = shape
                for h, read in pairs:
                    if read != shape:
                        continue
                    size += F.BUS_IMAGE_ENTRY_LEN + len(wrote) + len(got)
                    if size > MAX_IMAGE:
                        return
                    sent.append((h, address, wrote, n_read, got, horizon_us, how))
                    entries.append((h, address, a - t_us, min(b - t_us, WINDOW_MAX), number, need, then, wrote, got))

    def _ticks(self, device, pairs: list) -> int:
        """How many windows of ``device``'s stream to play ahead: ``STREAM_TICKS``, or one
        where the firmware reads it more than twice as slowly as it samples (a gyro at
        1.66 kHz read at 208 Hz: a stream's later windows expect every sample read, so a
        read that lets ticks pass is the host's anyway, and only the window it is in counts)."""
        period = device.period_us() if hasattr(device, "period_us") else 0
        if not period:
            return STREAM_TICKS
        paces = [last - prev for prev, last in (self.read_at.get(pair, (0, 0)) for pair in pairs) if last > prev]
        return 1 if paces and min(paces) > 2 * period else STREAM_TICKS

    def _worth(self, kind) -> bool:
        """Whether to image with a message of ``kind``; the last image's outcome noted first
        (the shim drops an image at the next message it takes)."""
        last, self.sent_with = self.sent_with, None
        if last is not None:
            if self.used:
                self.idle.pop(last, None)
            else:
                self.idle[last] = self.idle.get(last, 0) + 1
        if self.idle.get(kind, 0) < IDLE:
            return True
        passed = self.passed.get(kind, 0) + 1
        self.passed[kind] = 0 if passed >= PROBE else passed
        return passed >= PROBE

    def _try(self, h: int, bus: str, shape: tuple, t_us: int, horizon_us: int, version: tuple):
        """A read tried on copies of its chip at ``t_us`` and at the end of its steady window
        (kept in ``known`` while no transfer reaches the chip), or, where the chip reads
        otherwise by then, at the horizon's (for this image alone); None: not imaged now."""
        address, wrote, n_read = shape
        self.known.pop((h, shape), None)
        device = self.plant.bus_device(bus, address)
        if device is None:
            return None
        steady = steady_until(device, t_us)
        until = min(steady, horizon_us)
        if until <= t_us:
            return None
        last = self.read_at.get((h, shape))
        if last is not None and last[1] > last[0] and 2 * last[1] - last[0] >= until:
            # (read at the firmware's pace, it comes next after the window: not tried until then)
            self.known[(h, shape)] = (version, t_us, until, None)
            return None
        rng = self.plant.rng
        first, *last = _trials(device, (t_us, steady - 1), address, n_read, wrote, rng)
        if first is None:
            if streamable(device, rng):  # (a sample read, a flag cleared: its chip's reads a stream from now on)
                self.streaming.add((bus, address))
                return None
            self.impure.add((h, *shape))  # (the host's)
            self.reads[h] = [s for s in self.reads[h] if s != shape]
            return None
        if last == [first]:
            hit = self.known[(h, shape)] = (version, t_us, steady, first)
            return hit
        if steady > horizon_us:  # (it reads otherwise before its next event: to the horizon, not kept)
            if _trials(device, (horizon_us - 1,), address, n_read, wrote, rng) == [first]:
                return (version, t_us, horizon_us, first)
        return None

    def done(self, rig, t_us: int, at: int) -> None:
        """BUS_DONE: the shim answered the entry at offset ``at`` of the last image at ``t_us``. The host
        does what a BUS frame at ``t_us`` makes it do (the plant brought to ``t_us``, the
        transfer played on the chips and traced) but send the reply, and checks that the
        reply is the one the shim took: the bytes and the horizon.

        A pure read (its trials changed nothing of the chip but its register pointer) is
        played on the chips by leaving the pointer where the trial's read left it, a stream's
        changing read by making the chip and the generator what its trial left
        (:func:`_install`; where they are not as its window found them, the read is played on
        the chip): the plant's transfer path (``bus_transfer``: its other chips' ``take_in``
        and ``pass_on``, the chip's registers byte by byte, the plant's schedule) runs only
        on a bus where a chip reads the plant at every transfer (``_plain``)."""
        try:
            h, address, wrote, n_read, got, horizon_us, left = self.sent[at]
        except KeyError:
            raise LinkError(
                f"BUS_DONE names an entry at offset {at} of a bus image whose entries are at "
                f"{sorted(self.sent)} (link protocol error)"
            ) from None
        rig.clock.catch_up(t_us)
        info = self.wiring.handles[h]
        self.local += 1
        self.used = True
        rig.stats.bus_local += 1
        trace = rig.bus_trace
        trace.asking = True  # (a poll named here is said with the firmware's stack: the next BUS_REPLY asks for it)
        try:
            device = self.plant.bus_device(info.key, address) if self._plain(info.key) else None
            if device is not None and type(left) is tuple:
                device.pointer, device.pointed = left
                reply = F.BUS_OK, len(wrote), got
                trace.replay(self.plant, info, h, t_us, F.BUS_XFER, address, n_read, wrote, reply)
            elif device is not None and left is not None and _install(device, left, self.plant.rng):
                reply = F.BUS_OK, len(wrote), got  # (a stream's changing read: the chip as its trial left it)
                trace.replay(self.plant, info, h, t_us, F.BUS_XFER, address, n_read, wrote, reply)
            elif device is not None:  # (a stream's read: played on its chip alone, which no other reads)
                next_us = device.next_us
                reply = _BUS_SET._xfer(t_us, [device], True, address, n_read, wrote)
                if device.next_us != next_us:
                    raise LinkError(
                        f"a bus read the shim answered from the host's image at t={t_us} us ({info.key} "
                        f"0x{address:02x} register {wrote.hex()}) moved its chip's next event to {device.next_us} "
                        "us (host.rig.hardware.busimage: the image was wrong)"
                    )
                trace.replay(self.plant, info, h, t_us, F.BUS_XFER, address, n_read, wrote, reply)
            else:
                reply = trace.answer(self.plant, info, h, t_us, F.BUS_XFER, address, n_read, wrote)
        finally:
            trace.asking = False
        lease = rig.clock.lease_us()
        if reply != (F.BUS_OK, len(wrote), got) or lease != horizon_us:
            raise LinkError(
                f"a bus read the shim answered from the host's image at t={t_us} us ({info.key} 0x{address:02x} "
                f"register {wrote.hex()}) reads {reply[2].hex()} with horizon {lease} us on the chips, expected "
                f"{got.hex()} with horizon {horizon_us} us as imaged (host.rig.hardware.busimage: the image was wrong)"
            )
        self._last(h, (address, wrote, n_read))
        self._read_at(h, (address, wrote, n_read), t_us)

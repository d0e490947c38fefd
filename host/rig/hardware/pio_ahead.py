"""PIO reads answered ahead (``docs/shim.md``, "PIO reads answered ahead"; PIO_AHEAD and
PIO_DONE in ``docs/protocol.md``).

A read of a state machine is often several frames, the later ones at instants the first
one's reply fixes: a decoder read as the SDK's ``quadrature_encoder_get_count`` reads it
(``rx_fifo()``, the words it gives taken, a ``get()`` that finds the FIFO empty and waits
the microsecond the reply names, a ``get()`` again), a request (``put()``, then a ``get()``
at the same instant, then again after the wait). With the reply to the first frame the
host sends the replies to the frames that follow it, each played on a copy of the blocks
(a twin) at its instant:

- a ``get`` or a ``put`` the FIFO did not serve whole is asked again after the wait its
  reply names (rp2.py's ``StateMachine.get``, ``put``);
- after a LEVELS that the firmware drained, or a ``put``, the frame that came next at that
  instant the last time (a ``get``), learned per state machine;
- after a ``get`` that took all it asked for, the LEVELS another state machine was asked
  for next at that instant the last time (a robot's second decoder, read right after the
  first; the first again, both read twice at one instant), learned per state machine and
  per the read's place in the run of reads at that instant (:attr:`ReadsAhead.hop`), its
  handle known from an exchange of its own.

Only while the pins are known to stay as they are (before the reply's horizon: the plant
changes nothing before it) and while no state machine of the block drives a pin (its frames
would give the plant something). The shim takes an answer for that very frame at that
very instant, while no frame went to the host since the reply (an output, a CFG, another
exchange: the plant may go otherwise), and tells the host with its next message
(PIO_DONE); the host traces the frame with that reply at its instant and takes the twin's
blocks once the shim has answered every frame sent ahead (the same frames on the same
blocks with the same pins: what the host's own blocks would do), or plays the frames it
answered on its own blocks when it next needs them. ``MPY_FIL_PIO_AHEAD=check`` plays each
one on the host's blocks at once and stops the run if it answers otherwise;
``MPY_FIL_PIO_AHEAD=0`` sends none (every frame an exchange: the path the answers ahead
match, ``host/tests/test_pio_ahead.py``).
"""

import os
import struct

from host.core.errors import LinkError
from host.link import frames as F
from host.rig.hardware.pio_out import driven_pins
from host.shim._hilpio import PIO_AHEAD_ENTRY_FMT, PIO_AHEAD_GOT_FMT, pack_pio_ahead

ENV = "MPY_FIL_PIO_AHEAD"
AHEAD_MAX = 12  # frames answered ahead after one reply (a robot's two decoders read twice at one instant: 11)
AHEAD_BYTES = 2048  # ... and no more bytes of them (a PIO_AHEAD stays well under a frame's payload)


class _Sent:
    """The answers ahead last sent: the frames and replies, the twin they were played on,
    the pins' changes the host had then, how many the shim took, how many the blocks had."""

    def __init__(self, handles: dict, entries: list, twin, n_pending: int, marks: dict, hops: list):
        self.handles, self.entries, self.twin, self.n_pending = handles, entries, twin, n_pending
        self.hops = hops  # entry index -> the hop of the read it belongs to (ReadsAhead.hop)
        self.marks = marks  # entry index -> the twin as it was before that entry (a LEVELS: a new read)
        self.used = 0
        self.played = 0


class _NoOutputs:
    """A twin's outputs: what it drives reaches no plant."""

    def after(self, block, t_us: int) -> None:
        pass


class ReadsAhead:
    """The answers ahead of one rig's PIO (``host.rig.hardware.pio.PioHost``)."""

    def __init__(self, host, learning: bool = True):
        self.host = host
        self.learning = learning  # (a twin's: it plays frames, it learns and sends nothing)
        way = os.environ.get(ENV, "").strip().lower()
        self.on = learning and way not in ("0", "no", "false")
        self.check = way == "check"  # (each frame answered ahead played again at once and compared)
        self.reset()

    def reset(self) -> None:
        self.follows: dict = {}  # (sm, op) -> (op, n_read, drained): the frame that came next at its instant
        self.then: dict = {}  # (sm, hop) -> (sm, n_read): the LEVELS asked next at the instant of a get that took all
        self.unsure: set = set()  # (sm, hop) whose `then` read the shim once did not make: the twin kept before it
        self.hop = 0  # the last read's place in a run of reads at one instant (0 its first; LEVELS frames)
        self.handles: dict = {}  # sm -> its handle (an exchange of its own told it)
        self.last = None  # (sm, op, t_us, RX words given, a get that took all): the last frame, for follows
        self.sent: _Sent | None = None
        self.local = 0  # frames the shim answered ahead

    # -- the host's frames ------------------------------------------------------------------
    def before(self, t_us: int, sm_id: int, op: int, address: int, n_read: int) -> None:
        """A frame reaches the blocks: the frames answered ahead before it first; a frame at
        the instant of the last, on the same state machine, is the one that follows that kind
        of frame (after a LEVELS: whether it took every word the LEVELS gave)."""
        if not self.learning:
            return
        if self.sent is not None:
            self.catch_up()
        last = self.last
        chained = False  # (a LEVELS at the instant of a get that took all: the next read of a run)
        if last is not None and last[0] == sm_id and last[2] == t_us and op == F.BUS_PIO_GET:
            popped = address >> 8
            drained = popped == last[3] if last[1] == F.BUS_PIO_LEVELS else not popped
            self.follows[(sm_id, last[1])] = (op, n_read, drained)
        elif last is not None and last[4] and last[2] == t_us and op == F.BUS_PIO_LEVELS and not address:
            self.then[(last[0], self.hop)] = (sm_id, n_read)
            chained = True
        elif last is not None and last[4]:
            self.then.pop((last[0], self.hop), None)
        if op == F.BUS_PIO_LEVELS:
            self.hop = self.hop + 1 if chained else 0
        self.last = None

    def after(self, t_us: int, sm_id: int, op: int, reply: tuple, n_read: int = 0) -> None:
        if self.learning:
            took_all = op == F.BUS_PIO_GET and reply[0] == F.BUS_OK and reply[1] == n_read
            self.last = (sm_id, op, t_us, reply[2][0] if op == F.BUS_PIO_LEVELS else 0, took_all)

    def catch_up(self) -> None:
        """The frames the shim answered ahead that the blocks have not had yet, played on them."""
        sent, self.sent = self.sent, None
        if sent is None:
            return
        mark = sent.marks.get(sent.used)
        if mark is not None and sent.played == 0:  # (the shim stopped before a read answered ahead:
            self._take(sent, *mark)  # the twin as it was then)
            return
        if 0 < sent.used < len(sent.entries) and sent.entries[sent.used][1] == F.BUS_PIO_LEVELS:
            self.unsure.add((sent.entries[sent.used - 1][9], sent.hops[sent.used - 1]))  # (the twin kept before)
        for t, op, address, n_read, data, *_reply, sm_id in sent.entries[sent.played : sent.used]:
            self.host.transfer(t, sm_id, op, address, n_read, data)

    # -- what goes to the shim --------------------------------------------------------------
    def answer(self, h: int, t_us: int, sm_id: int, frame: tuple, reply: tuple, lease: int) -> bytes | None:
        """The PIO_AHEAD for the reply to ``frame`` (op, address, n_read, data) at ``t_us``: the
        frames the shim's read makes next on this state machine, each answered on a twin at
        its instant, as long as the pins stay as they are (before ``lease``, the plant's next
        change) and no state machine of the block drives a pin; None: nothing to send."""
        self.catch_up()
        self.handles[sm_id] = h
        if not self.on:
            return None
        host = self.host
        twin = None
        entries = []
        marks: dict = {}
        hops: list = []
        hop, size = self.hop, 0
        t, (op, address, n_read, data) = t_us, frame
        drives = (_drives(host.blocks[0]), _drives(host.blocks[1]))  # (no init among the frames ahead: as they are)
        for _ in range(AHEAD_MAX):
            if drives[sm_id >> 2]:
                break
            nxt = self._next(sm_id, hop, t, op, address, n_read, data, reply)
            if nxt is None or nxt[0] >= lease:
                break
            if twin is None:
                twin = self._twin()
            t, sm_next, op, address, n_read, data = nxt
            if drives[sm_next >> 2]:
                break
            if op == F.BUS_PIO_LEVELS:  # (the next read of a run at one instant: only `then` gives one)
                if (sm_id, hop) in self.unsure:  # (a read the shim stopped before once: the twin kept before it)
                    marks[len(entries)] = self._mark(twin)
                hop += 1
            sm_id = sm_next
            reply = twin.transfer(t, sm_id, op, address, n_read, data)
            size += _ENTRY_BYTES + len(data) + len(reply[2])
            if size > AHEAD_BYTES:
                break
            entries.append((t, op, address, n_read, data, reply[0], reply[1], lease, reply[2], sm_id))
            hops.append(hop)
        if not entries:
            return None
        self.sent = _Sent(dict(self.handles), entries, twin, len(host.pending), marks, hops)
        return pack_pio_ahead(entries)

    def _next(self, sm_id, hop, t, op, address, n_read, data, reply):
        """The frame the shim makes next after ``op``'s ``reply`` in a read at place ``hop`` of
        its run (t, state machine, op, address, n_read, data), or None when it is not known."""
        status, count, got = reply
        if status != F.BUS_OK:
            return None
        wait = struct.unpack_from("<I", got, 0)[0] if op in (F.BUS_PIO_GET, F.BUS_PIO_PUT) else 0
        if op == F.BUS_PIO_GET and count < n_read and wait:  # (no wait named: the twin probed to its horizon)
            return t + wait, sm_id, op, 0, n_read - count, b""
        if op == F.BUS_PIO_PUT and count < len(data) // 4 and wait:
            return t + wait, sm_id, op, 0, 0, data[4 * count :]
        if op == F.BUS_PIO_GET and count == n_read:  # (another state machine's LEVELS next)
            then = self.then.get((sm_id, hop))
            if then is None or then[0] not in self.handles:
                return None
            return t, then[0], F.BUS_PIO_LEVELS, 0, then[1], b""
        follow = self.follows.get((sm_id, op))
        if follow is None or op not in (F.BUS_PIO_LEVELS, F.BUS_PIO_PUT) or not follow[2]:
            return None
        popped = got[0] if op == F.BUS_PIO_LEVELS else 0
        return t, sm_id, follow[0], popped << 8, follow[1], b""

    def _twin(self):
        """A copy of the host's PIO to play frames ahead on: its own blocks (a block that runs
        nothing, with no drive or raise to hand on, shared: time and frames do nothing to it),
        inputs and IRQ raises; it gives the plant nothing and learns nothing."""
        host = self.host
        twin = type(host).__new__(type(host))
        twin.__dict__.update(host.__dict__)
        twin.blocks = tuple(b if b.idle and not b.events and not b.irqs else b.fork() for b in host.blocks)
        twin.pending, twin.levels = list(host.pending), dict(host.levels)
        twin.raised = (list(host.raised[0]), list(host.raised[1]))
        twin.outputs = _NoOutputs()
        twin.ahead = _TWIN
        twin.probe_in_place = True  # (a FIFO's probe leaves the twin at the instant it names: where its next frame is)
        return twin

    def _take(self, sent: _Sent, blocks, pending: list, levels: dict, raised: tuple) -> None:
        """The host's PIO as the twin left it, with the changes the plant committed since the
        answers were sent (each after their instants: they were sent before the plant's next
        change, and the shim answers none after a frame of its own) still to come."""
        host = self.host
        host.blocks, host.levels, host.raised = blocks, levels, raised
        host.pending = pending + host.pending[sent.n_pending :]

    def _mark(self, twin) -> tuple:
        """The twin's blocks (a copy of each it runs), pins and raises as they are now."""
        host = self.host
        blocks = tuple(b if b is h else b.fork() for b, h in zip(twin.blocks, host.blocks))
        return blocks, list(twin.pending), dict(twin.levels), (list(twin.raised[0]), list(twin.raised[1]))

    # -- what the shim answered -------------------------------------------------------------
    def done(self, rig, t_us: int, sm_id: int, entry: int) -> None:
        """PIO_DONE: the shim answered entry ``entry`` of the last PIO_AHEAD at ``t_us``. The
        host does what that frame makes it do but reply: the plant brought to ``t_us``, the
        frame traced with the reply sent ahead, and played on the blocks (the twin's taken
        once the shim has answered every frame sent ahead, else each frame played when the
        host next needs its blocks: :meth:`catch_up`); the reply's horizon checked."""
        sent = self.sent
        if sent is None or sent.used != entry or entry >= len(sent.entries) or sent.entries[entry][9] != sm_id:
            raise LinkError(
                f"PIO_DONE names entry {entry} on state machine {sm_id}, not the next one answered ahead "
                f"({None if sent is None else (sent.used, [e[9] for e in sent.entries])}) (link protocol error)"
            )
        t, op, address, n_read, data, status, count, horizon_us, got, _sm = sent.entries[entry]
        if t != t_us:
            raise LinkError(f"PIO_DONE at t={t_us} us for a frame answered ahead at {t} us (link protocol error)")
        rig.clock.catch_up(t_us)
        self.local += 1
        self.after(t_us, sm_id, op, (status, count, got), n_read)  # (what follows it is learnt as after an exchange)
        h = sent.handles[sm_id]
        info = rig.wiring.handles[h]
        if self.check:  # (played on the host's blocks now: before() plays those before it first)
            reply = rig.bus_trace.answer(rig.plant, info, h, t_us, op, address, n_read, data)
            sent.used = sent.played = entry + 1
            self.sent = sent
        else:
            reply = rig.bus_trace.replay(rig.plant, info, h, t_us, op, address, n_read, data, (status, count, got))
            sent.used = entry + 1
            if sent.used == len(sent.entries):
                twin = sent.twin
                self._take(sent, twin.blocks, twin.pending, twin.levels, twin.raised)
                sent.played = sent.used
        if op == F.BUS_PIO_LEVELS:  # (its place in the run of reads, as the answers ahead counted it)
            self.hop = sent.hops[entry]
        lease = rig.clock.lease_us()
        if reply != (status, count, got) or lease != horizon_us:
            raise LinkError(
                f"a PIO frame the shim answered ahead at t={t_us} us (state machine {sm_id}, op {op}) answers "
                f"{reply} with horizon {lease} us on the host's blocks, expected {(status, count, got)} with "
                f"horizon {horizon_us} us as sent (host.rig.hardware.pio_ahead: the answer ahead was wrong)"
            )


def _drives(block) -> bool:
    """A state machine of ``block`` drives a pin (its frames would give the plant something)."""
    return any(driven_pins(run.sm) for run in block.running.values())


_ENTRY_BYTES = struct.calcsize(PIO_AHEAD_ENTRY_FMT) + struct.calcsize(PIO_AHEAD_GOT_FMT)
_TWIN = ReadsAhead(None, learning=False)  # (a twin's: it learns and sends nothing)

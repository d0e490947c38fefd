"""The host side of ``rp2.StateMachine`` (``docs/shim.md``, "PIO"): the two PIO blocks run
here, beside the plant (:mod:`sim_plant.pio`), not in the firmware.

A state machine is a handle of kind ``CFG_PIO``; what the firmware does with it is a BUS
frame (``BUS_PIO_*``: init, active, put, get, FIFO levels, exec, restart), answered at the
frame's instant like a bus transfer (``host.rig.loop.messages.on_bus``: the plant is at that instant). The
pins the PIO reads are the plant's outputs wired to the board's pins: their changes reach
:class:`PioHost` as committed change hooks (never one a rewind takes back), in time order,
and each block is run to the frame's instant over them. The firmware sees none of those
edges, only what the program pushes: a PIO quadrature decoder counts every edge on the
host and costs the firmware one exchange per ``get()``.

A ``put`` to a full TX FIFO or a ``get`` from an empty RX FIFO blocks the firmware, as on
a board: the reply says how long the state machine needs, the pins staying as they are
(:meth:`PioBlock.probe`), and the shim waits that long in virtual time and asks again.

A read is often several frames: a decoder read as the SDK's ``quadrature_encoder_get_count``
reads it (``rx_fifo()``, the words it gives taken, then a ``get()`` that waits for a fresh
one), a request (``put()`` then ``get()``). With the reply to a read's first frame the host
sends the replies to the frames that follow it (PIO_AHEAD, :mod:`host.rig.hardware.pio_ahead`:
docs/shim.md, "PIO reads answered ahead"), each played on a copy of the blocks at its
instant; the shim answers those frames itself and tells the host (PIO_DONE), whose blocks
then go as with an exchange a frame.
"""

import functools
import struct

from host.core.errors import LinkError
from host.link import frames as F
from host.rig.hardware.peripherals import Peripheral, register
from host.rig.hardware.pio_ahead import ReadsAhead
from host.rig.hardware.pio_out import PioOutputs
from sim_plant.pio import PioBlock, PioConfig

PROBE_US = 100_000  # how far ahead a blocked FIFO is looked at (the shim asks again after)
_INIT = struct.Struct("<IIIII")
_MEMORY = struct.Struct("<32H")


def gpio_of(key: str) -> int | None:
    """A pin as the shim names it (``5``, ``GP5``) as its GPIO number."""
    text = key[2:] if key.upper().startswith("GP") else key
    return int(text) if text.isdigit() else None


class PioHost:
    """PIO0 and PIO1 of one rig, their inputs the plant's committed changes."""

    def __init__(self, plant, wiring, change_hooks: dict):
        self.plant = plant
        self.wiring = wiring
        self.change_hooks = change_hooks
        self.levels: dict[int, int] = {}  # gpio -> its level up to the last change given to the blocks
        self.pending: list[tuple] = []  # (t_us, gpio, level) committed, not yet given to the blocks
        self.tracked = False
        self.raised: tuple = ([], [])  # per block: (t_us, flag) raised with a handler armed, not yet told
        self.outputs = PioOutputs(plant, wiring)
        self.ahead = ReadsAhead(self)
        self.probe_in_place = False  # (a twin's blocks are probed in place: host.rig.hardware.pio_ahead)
        self.reset()

    def reset(self) -> None:
        """A new interpreter run: the PIO blocks are reset (the pins keep their levels)."""
        self.blocks = (PioBlock(0), PioBlock(1))
        for block in self.blocks:  # (what their state machines drive reaches the plant through a look-ahead
            block.record_events = False  # on a copy, host/rig/hardware/pio_out.py: the changes here are dropped)
        self.raised = ([], [])
        self.outputs.clear()
        self.ahead.reset()
        for block in self.blocks:
            for gpio, level in self.levels.items():
                block.set_input(gpio, level)

    @property
    def steps(self) -> int:
        return sum(b.steps for b in self.blocks)

    # -- inputs ------------------------------------------------------------------------
    def track(self) -> None:
        """From the first state machine on: every board pin wired to a plant output is a
        PIO input, its level now and each committed change after."""
        if self.tracked:
            return
        self.tracked = True
        for key, name in self.wiring.pin_names.items():
            signal, gpio = self.wiring.wiring.get(name), gpio_of(key)
            if gpio is None or signal not in self.plant.outputs:
                continue
            value = self.plant.output(signal)
            self._set(gpio, 1 if value else 0)
            self.change_hooks.setdefault(signal, []).append(functools.partial(self._changed, gpio))

    def _changed(self, gpio: int, t_us: int, value) -> None:
        self.pending.append((t_us, gpio, 1 if value else 0))

    def _set(self, gpio: int, level: int) -> None:
        self.levels[gpio] = level
        for block in self.blocks:
            block.set_input(gpio, level)

    def advance(self, t_us: int) -> None:
        """Both blocks to ``t_us``, over the changes committed up to it (a block with no
        state machine running only takes the levels)."""
        pending, upto = self.pending, 0
        if not pending or pending[0][0] > t_us:  # (no change to take: each block's machines to t_us)
            for block in self.blocks:
                block._run_all(t_us)
                self._handed(block)
            return
        while upto < len(pending) and pending[upto][0] <= t_us:
            upto += 1
        changes, self.pending = pending[:upto], pending[upto:]
        live = [block for block in self.blocks if not block.idle]
        for block in live:
            block.advance(t_us, changes)
        levels = self.levels
        for _t, gpio, level in changes:
            levels[gpio] = level
        changed = {gpio for _t, gpio, _level in changes}
        for block in self.blocks:
            if block not in live:  # (a block that runs nothing needs only the levels now)
                for gpio in changed:
                    block.set_input(gpio, levels[gpio])
            self._handed(block)

    def _handed(self, block) -> None:
        """What ``block`` did in its run handed on: its IRQ raises the firmware handles kept."""
        block.events.clear()  # (the levels the PIO drives are not yet given to the plant)
        if block.irqs:
            if block.irq_clears:
                self.raised[block.block_id].extend((t, f) for t, f, _sm in block.irqs if block.irq_clears >> f & 1)
            block.irqs.clear()

    # -- the firmware's frames -----------------------------------------------------------
    def transfer(self, t_us: int, sm_id: int, op: int, address: int, n_read: int, data: bytes) -> tuple:
        """A BUS_PIO_* frame at ``t_us`` on state machine ``sm_id``: (status, count, bytes)."""
        if not self.tracked:
            self.track()
        self.ahead.before(t_us, sm_id, op, address, n_read)
        block, local = self.blocks[sm_id >> 2], sm_id & 3
        popped, address = address >> 8, address & 0xFF
        if popped and local in block.running:  # (words the firmware took at the last frame's instant)
            rx = block.sm(local).rx
            for _ in range(min(popped, len(rx))):
                rx.popleft()
            block.touch_sm(local)
        self.advance(t_us)
        if op == F.BUS_PIO_INIT:
            return self._init(block, local, t_us, data)
        if local not in block.running:
            raise LinkError(f"BUS op {op} on state machine {sm_id} before its init (link protocol error)")
        handler = _OPS.get(op)
        if handler is None:
            raise LinkError(f"BUS op {op} on state machine {sm_id}, which is no PIO op (link protocol error)")
        if op == F.BUS_PIO_IRQ:  # (the block's flags: every state machine's next steps)
            block.touch()
        else:  # (its own FIFOs, an exec, its start: the others go on as they were)
            block.touch_sm(local)
        reply = handler(self, block, local, t_us, address, n_read, data)
        if op != F.BUS_PIO_LEVELS:
            self.outputs.after(block, t_us)
        self.ahead.after(t_us, sm_id, op, reply, n_read)
        return reply

    def _init(self, block, local, t_us, data) -> tuple:
        execctrl, shiftctrl, pinctrl, div256, pc = _INIT.unpack_from(data, 0)
        block.load(list(_MEMORY.unpack_from(data, _INIT.size)))
        block.init(local, PioConfig(execctrl, shiftctrl, pinctrl, div256, pc), t_us)
        pins = data[_INIT.size + _MEMORY.size :]
        block._now_us = float(t_us)
        for i in range(0, len(pins) - 2, 3):
            gpio, out, level = pins[i : i + 3]
            block.drive(gpio, out, dirs=True)
            if out:
                block.drive(gpio, level)
        block.events.clear()
        return F.BUS_OK, 0, b""

    def _active(self, block, local, t_us, address, n_read, data) -> tuple:
        block.set_active(local, bool(address), t_us)
        return F.BUS_OK, 0, b""

    def _put(self, block, local, t_us, address, n_read, data) -> tuple:
        sm = block.sm(local)
        words = struct.unpack(f"<{len(data) // 4}I", data)
        room = max(0, sm.tx_depth - len(sm.tx))
        sm.tx.extend(words[:room])
        wait_us = 0
        if room < len(words):
            wait_us = self._probe(block, local, t_us, lambda s: len(s.tx) < s.tx_depth)
        return F.BUS_OK, min(room, len(words)), struct.pack("<I", wait_us)

    def _get(self, block, local, t_us, address, n_read, data) -> tuple:
        sm = block.sm(local)
        got = [sm.rx.popleft() for _ in range(min(n_read, len(sm.rx)))]
        wait_us = 0
        if len(got) < n_read:
            wait_us = self._probe(block, local, t_us, lambda s: bool(s.rx))
        return F.BUS_OK, len(got), struct.pack(f"<I{len(got)}I", wait_us, *got)

    def _probe(self, block, local, t_us, want) -> int:
        if not block.running[local].active:
            return 0
        t_ready = block.probe(local, t_us, PROBE_US, want, self.probe_in_place)
        return 0 if t_ready is None else max(1, int(t_ready - t_us))

    def _levels(self, block, local, t_us, address, n_read, data) -> tuple:
        """(rx, tx) levels, then the RX words (the shim serves gets at this instant from them)."""
        sm = block.sm(local)
        return F.BUS_OK, 2, bytes((len(sm.rx), len(sm.tx))) + struct.pack(f"<{len(sm.rx)}I", *sm.rx)

    def _exec(self, block, local, t_us, address, n_read, data) -> tuple:
        (word,) = struct.unpack_from("<H", data, 0)
        sm = block.sm(local)
        sm.pending_exec = word
        if not block.running[local].active:  # (pio_sm_exec runs it at once, also when stopped)
            block._now_us = float(t_us)
            sm.step()
        return F.BUS_OK, 0, b""

    def _irq(self, block, local, t_us, address, n_read, data) -> tuple:
        """The firmware's IRQ handlers poll (``docs/shim.md``, "PIO", IRQs): ``address``
        the block's flags 0..3 with a handler (their interrupt enabled: cleared as raised,
        a flag already up fires at once); the reply: the raises since the last poll."""
        armed = address & 0xF
        pending = block.irq_flags & armed & ~block.irq_clears
        block.irq_clears = armed
        raised = self.raised[block.block_id]
        for flag in range(4):
            if pending >> flag & 1:
                raised.append((float(t_us), flag))
        block.irq_flags &= ~armed
        mine = [(t, f) for t, f in raised if armed >> f & 1]
        raised.clear()
        times = [min(int(t), t_us) for t, _f in mine]
        return F.BUS_OK, len(mine), struct.pack(f"<{len(mine)}I", *times) + bytes(f for _t, f in mine)

    def _restart(self, block, local, t_us, address, n_read, data) -> tuple:
        block.sm(local).restart()
        return F.BUS_OK, 0, b""


_OPS = {
    F.BUS_PIO_ACTIVE: PioHost._active,
    F.BUS_PIO_PUT: PioHost._put,
    F.BUS_PIO_GET: PioHost._get,
    F.BUS_PIO_LEVELS: PioHost._levels,
    F.BUS_PIO_EXEC: PioHost._exec,
    F.BUS_PIO_RESTART: PioHost._restart,
    F.BUS_PIO_IRQ: PioHost._irq,
}


class PioPeripheral(Peripheral):
    """``rp2.StateMachine``: a handle named ``sm<id>``; no inputs, no outputs of its own:
    its frames go to the rig's :class:`PioHost` (``wiring.pio``)."""

    kind = F.CFG_PIO
    name = "pio"

    def configure(self, wiring, h, mode, pull, key, param):
        info = super().configure(wiring, h, mode, pull, key, param)
        info.pio = wiring.pio
        return info

    def transfer(self, plant, info, op: int, address: int, n_read: int, data: bytes) -> tuple:
        return info.pio.transfer(plant.t_us, int(info.key[2:]), op, address, n_read, data)


register(PioPeripheral())

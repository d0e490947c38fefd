# rp2 module for RP2040 firmware in the loop (docs/shim.md, "PIO"): asm_pio assembles as the
# port does (_pioasm.py); a StateMachine's program runs on the host, beside the plant, in
# virtual time (sim_plant/pio): its pins are the plant's, and the firmware sees what a board's
# CPU sees of it, its FIFOs (put, get, rx_fifo, tx_fifo), each access one BUS exchange but
# those the host answered ahead (PIO_AHEAD: the frames a read makes after its first, answered
# with the first's reply; docs/shim.md, "PIO reads answered ahead").
# Only an rp2 board has it: elsewhere `import rp2` fails, as on an ESP32.
import sys

if sys.platform != "rp2":
    raise ImportError(
        "no module named 'rp2': the loop has it for an RP2040 board only; name a board rpi_pico* "
        'or set [board] family = "rpi_pico" in the rig file (docs/rig-file.md, docs/shim.md)'
    )

import struct

import _hil
import _hilframe as F
import _hilpio
from _hilbuf import rbuf, typecode, wbuf
from _pioasm import PIOASMError, asm_pio, asm_pio_encode  # noqa: F401  (the port's names)

_SYS_HZ = 125_000_000
_ENOMEM = 12
_RETRY_US = 1000  # a FIFO the pins as they are never serve: look again this much later


def _put_words(value):
    """The words StateMachine.put takes from a buffer (rp2_state_machine_put)."""
    try:
        view = memoryview(value)
    except TypeError:
        raise TypeError("can't convert %s to int" % type(value).__name__) from None  # (mp_obj_get_int_truncated)
    code = typecode(view)
    size = 1 if code in (1, 0x42) else 2 if code == 0x48 else 4 if code == 0x49 else 0  # 1, 'B', 'H', 'I'
    data = rbuf(value)
    if not data:
        return []
    if not size:
        raise ValueError("unsupported buffer type")
    return list(struct.unpack(_fmt(len(data) // size, size), data))


_FMTS = {}  # (n, item size) -> the struct format of n little-endian items of that size


def _fmt(n, size=4):
    """struct's format for ``n`` items of ``size`` bytes ('B', 'H', 'I'), made once: a str
    made anew costs the interpreter a look-up among every interned name."""
    key = n << 3 | size
    f = _FMTS.get(key)
    if f is None:
        f = _FMTS[key] = "<%d%s" % (n, "BHxI"[size - 1])
    return f


def _get_items(buf):
    """A writable view of StateMachine.get's buffer and its item's size, 0 for a typecode the
    port refuses (rp2_state_machine_get: lower-cased, 'b', 'h' or 'i')."""
    view = wbuf(buf)  # (TypeError for bytes, str, anything not a writable buffer)
    code = typecode(memoryview(buf))
    if code != 1:
        code |= 0x20
    return view, 1 if code in (1, 0x62) else 2 if code == 0x68 else 4 if code == 0x69 else 0


class _Memory:
    """A PIO's 32 instruction slots; a program goes at the highest offset it fits (the
    SDK's pio_add_program, as the port calls it), its jumps moved by its offset."""

    def __init__(self):
        self.words = [0] * 32
        self.used = 0
        self.programs = []

    def add(self, pio_id, prog):
        if prog[1 + pio_id] >= 0:
            return prog[1 + pio_id]
        code = prog[0]
        n = len(code)
        mask = (1 << n) - 1
        for offset in range(32 - n, -1, -1):
            if not self.used & (mask << offset):
                break
        else:
            raise OSError(_ENOMEM)
        for i in range(n):
            word = code[i]
            self.words[offset + i] = word + offset if word >> 13 == 0 else word
        self.used |= mask << offset
        prog[1 + pio_id] = offset
        self.programs.append(prog)
        return offset

    def remove(self, pio_id, prog=None):
        for p in list(self.programs):
            if prog is None or p is prog:
                self.used &= ~(((1 << len(p[0])) - 1) << p[1 + pio_id])
                p[1 + pio_id] = -1
                self.programs.remove(p)


_MEMORY = (_Memory(), _Memory())


class PIO:
    IN_LOW = 0
    IN_HIGH = 1
    OUT_LOW = 2
    OUT_HIGH = 3
    SHIFT_LEFT = 0
    SHIFT_RIGHT = 1
    JOIN_NONE = 0
    JOIN_TX = 1
    JOIN_RX = 2
    IRQ_SM0 = 0x100
    IRQ_SM1 = 0x200
    IRQ_SM2 = 0x400
    IRQ_SM3 = 0x800

    def __init__(self, id):
        if id not in (0, 1):
            raise ValueError("invalid PIO")
        self._id = id

    def add_program(self, program):
        _MEMORY[self._id].add(self._id, program)

    def remove_program(self, program=None):
        _MEMORY[self._id].remove(self._id, program)

    def state_machine(self, id, program=None, *args, **kw):
        if not 0 <= id < 4:
            raise ValueError("invalid StateMachine")
        sm = StateMachine(self._id * 4 + id)
        if program is not None:
            sm.init(program, *args, **kw)
        return sm

    def irq(self, handler=None, trigger=0xF00, hard=False):
        """PIO(n).irq(handler, trigger): ``handler(pio)`` for each raise of the flags 0..3 in
        ``trigger`` (IRQ_SM0..IRQ_SM3); ``irq().flags()`` the raise's. Soft, as the port's
        handler with hard=False: scheduled after the raise (at the next poll, docs/shim.md)."""
        irq = _Irq.of(self)
        if handler is not None or trigger != 0xF00 or hard:
            irq._set(handler, (trigger >> 8) & 0xF if handler is not None else 0)
        return irq


def _pin(pin):
    """A pin argument (a Pin, a number, "GP5") as its GPIO number."""
    if pin is None:
        return None
    pid = getattr(pin, "_id", pin)
    if isinstance(pid, str):
        pid = int(pid[2:] if pid.upper().startswith("GP") else pid)
    return pid


def _unwire(pin):
    """A Pin object given to the PIO (``in_base=Pin(2)``) that the firmware does not watch
    (no IRQ, no counter): its handle no longer takes the pin's changes, so they cost the
    link nothing (the PIO reads the pin on the host). Its next read or IRQ wires it again
    (``Pin._cfg``), as the firmware made it."""
    if not hasattr(pin, "_cfg") or pin._handler is not None or pin._counters is not None or not pin._cfg:
        return
    if pin._mode != pin.IN:
        return
    pin._cfg = False
    _hil.configure(pin._handle, F.CFG_PIN, "pio:%s" % pin._id, F.PIN_IN, F.PULL_NONE, -1)


def _count(init):
    if init is None:
        return 0
    return 1 if isinstance(init, int) else len(init)


def _levels(init, base):
    """What a program's out_init/set_init/sideset_init sets: (gpio, is_output, level)."""
    if init is None or base is None:
        return []
    init = (init,) if isinstance(init, int) else init
    return [(base + i, v >> 1, v & 1) for i, v in enumerate(init)]


_SMS = {}
_KEEP = object()  # (irq() with no argument: the IRQ object as it is)
_POPPED = []  # state machines with words taken from their RX FIFO the host is not yet told of
# The host's answers to the next PIO frames (PIO_AHEAD), in order, each naming its state
# machine (the whole list while some are left); _hil._Link.frames when they came (they hold
# while no frame went out since); the answers taken (the next one's index in the list).
_AHEAD = [None, -1, 0]


def _instant():
    """The firmware's instant at a frame or a level read: with MCU time (or a print's time
    owed), after the compute before it, as at a clock read (docs/mcu-time.md, "How it
    works", 3). The levels a LEVELS reply gave hold at its instant only (a level read after
    40 us of compute is read 40 us later, on the host's PIO too: host/tests/test_pio_mcu_time.py),
    and the words taken from its RX words reach the host before a frame of another state
    machine at a later instant: both compare with this instant, not with the clock before
    the compute is paid. (A get those words serve takes the FIFO's oldest word, which it still
    is after any compute: it moves no time, its compute charged at the next clock read as a C
    call's is.)"""
    if _hil._Console.cpu is not None or _hil._Console.debt_ns >= 1000:
        _hil.pay_console()
    return _hil.now()


class StateMachine:
    """One of the eight state machines (0..3 in PIO0, 4..7 in PIO1); its program runs on the
    host, against the plant's pins, from active(1) on."""

    def __new__(cls, id, *args, **kw):
        if not 0 <= id < 8:
            raise ValueError("invalid StateMachine")
        sm = _SMS.get(id)
        if sm is None:
            sm = _SMS[id] = object.__new__(cls)
            sm._id = id
            sm._active = 0
            sm._handle = None
            sm._side = (0, 0)
            sm._rx = []  # the RX words the host last gave, at instant _at (a get at that instant takes them)
            sm._tx_level = 0
            sm._at = -1
            sm._popped = 0  # words taken from _rx the host is told with the next frame
        return sm

    def __init__(self, id, program=None, *args, **kw):
        if program is not None:
            self.init(program, *args, **kw)

    def _hil_apply(self, kind, value, extra):
        pass  # (the host answers its FIFOs; nothing comes unasked)

    def init(
        self,
        program,
        freq=-1,
        *,
        in_base=None,
        out_base=None,
        set_base=None,
        jmp_pin=None,
        sideset_base=None,
        in_shiftdir=None,
        out_shiftdir=None,
        push_thresh=None,
        pull_thresh=None,
    ):
        pio = self._id >> 2
        div256 = 256
        if freq == 0:
            div256 = 65536 * 256  # (clkdiv 0: the slowest, as the port sets it)
        elif freq > 0:
            div256 = _SYS_HZ * 256 // freq
            if not 256 <= div256 <= 65536 * 256:
                raise ValueError("freq out of range")
        offset = _MEMORY[pio].add(pio, program)
        execctrl = program[3] + (offset << 12 | offset << 7)
        side_en = execctrl >> 30 & 1
        execctrl |= (_pin(jmp_pin) or 0) << 24
        shiftctrl = program[4]
        for value, bit, width in (
            (in_shiftdir, 18, 1),
            (out_shiftdir, 19, 1),
            (push_thresh, 20, 5),
            (pull_thresh, 25, 5),
        ):
            if value is not None:
                mask = ((1 << width) - 1) << bit
                shiftctrl = (shiftctrl & ~mask) | ((value << bit) & mask)
        # as the port: a group of pins (and its count) only when its base is given
        ins, outs, sets, sides = _pin(in_base) or 0, _pin(out_base), _pin(set_base), _pin(sideset_base)
        _unwire(in_base)
        _unwire(jmp_pin)
        side_count = _count(program[7]) + side_en if sides is not None else 0
        pinctrl = side_count << 29 | ins << 15 | (sides or 0) << 10
        if sets is not None:
            pinctrl |= _count(program[6]) << 26 | sets << 5
        if outs is not None:
            pinctrl |= _count(program[5]) << 20 | outs
        self._side = (side_count, side_en)
        pins = _levels(program[5], outs) + _levels(program[6], sets) + _levels(program[7], sides)
        if self._handle is None:
            self._handle = _hil.register(self)
            _hil.configure(self._handle, F.CFG_PIO, "sm%d" % self._id, param=div256)
        data = struct.pack("<IIIII", execctrl, shiftctrl & 0xFFFFFFFF, pinctrl, div256, offset)
        data += struct.pack("<32H", *_MEMORY[pio].words)
        for gpio, out, level in pins:
            data += struct.pack("<BBB", gpio, out, level)
        self._call(F.BUS_PIO_INIT, 0, 0, data)
        self._active = 0

    def _call(self, op, address=0, n_read=0, data=b""):
        if self._handle is None:
            raise OSError("StateMachine(%d) has no program: init() it first" % self._id)
        now = _instant()
        popped, self._popped = self._popped, 0
        if self in _POPPED:  # (first: another machine's exchange below must not come back to this one)
            _POPPED.remove(self)
        if _POPPED:
            for other in list(_POPPED):  # (the host runs the PIO on only after it knows what was taken)
                if other in _POPPED and other._at != now:
                    other._call(F.BUS_PIO_LEVELS, 0, 2)
        address |= popped << 8
        reply = _AHEAD[0] and self._answered(op, address, n_read, data)
        if reply:
            count, got, t = reply
        else:
            status, count, got, t = _hil.transfer(self._handle, op, address, n_read, data)
            ahead, _hil._Link.pio = _hil._Link.pio, None
            _AHEAD[0] = ahead and _hilpio.unpack_pio_ahead(ahead)
            _AHEAD[1], _AHEAD[2] = _hil._Link.frames, 0
        self._at = -1
        if op == F.BUS_PIO_LEVELS:  # the levels and the RX words: gets at this instant need no exchange
            self._rx = list(struct.unpack_from(_fmt(got[0]), got, 2))
            self._tx_level = got[1]
            self._at = t
        return count, got

    def _answered(self, op, address, n_read, data):
        """The frame answered from the host's PIO_AHEAD, as its exchange would answer it:
        (count, bytes, instant), or None (then it is an exchange, and the answers left are
        dropped). An answer holds at its instant, for that very frame, while nothing went to
        the host since the reply it came with (an output, a CFG, another exchange: the plant
        may go otherwise); the host, told with the next message (PIO_DONE), plays the frame
        on its PIO and stops the run if it answers otherwise."""
        if _hil._Console.cpu is not None:
            _hil._charge_cpu()
        if _hil._Console.debt_ns >= 1000:  # (as _hil.transfer: a print before has returned)
            _hil.pay_console()
        t = _hil.now()
        ahead = _AHEAD[0]
        i = _AHEAD[2]
        entry = ahead[i]
        _AHEAD[0] = None
        if (
            _hil._Link.frames != _AHEAD[1]
            or entry[9] != self._id
            or entry[0] != t
            or entry[1] != op
            or entry[2] != address
            or entry[3] != n_read
            or entry[4] != data  # (bytes: each caller's)
        ):
            return None
        depth = _hil.heap_release()
        try:
            if _hil._Link.held:  # (as a BUS_REPLY leaves the shim: its lookahead void, its horizon)
                _hil._drop_held()
            _hil._Link.ahead = False
            _hil._Link.image = _hil._NO_IMAGE
            _hil._Link.done = 0
            _hil._horizon = entry[7]
            _hil._wrote = True
            _hil.send(F.PIO_DONE, _hilpio.pack_pio_done(t, self._id, i))
        finally:
            _hil.heap_restore(depth)
        if i + 1 < len(ahead):  # (the entries left: the list kept, its next index; no copy made)
            _AHEAD[0] = ahead
        _AHEAD[1], _AHEAD[2] = _hil._Link.frames, i + 1
        return entry[6], entry[8], t

    def active(self, value=None):
        if value is None:
            return self._active
        self._active = 1 if value else 0
        self._call(F.BUS_PIO_ACTIVE, self._active)
        return self._active

    def restart(self):
        self._call(F.BUS_PIO_RESTART)

    def exec(self, instr):
        if isinstance(instr, str):
            instr = asm_pio_encode(instr, self._side[0], self._side[1])
        self._call(F.BUS_PIO_EXEC, 0, 0, struct.pack("<H", instr))

    def put(self, value, shift=0):
        # ports/rp2/rp2_pio.c, rp2_state_machine_put: an int, or a buffer read item by item
        # as its typecode says (bytes, str, bytearray, 'B', 'H', 'I'; any other typecode
        # raises ValueError at its first item); anything else must convert to an int.
        if isinstance(value, int):
            words = [(value << shift) & 0xFFFFFFFF]
        else:
            words = _put_words(value)  # (words of 32 bits at most: as they are when not shifted)
            if shift:
                words = [(w << shift) & 0xFFFFFFFF for w in words]
        while words:
            count, got = self._call(F.BUS_PIO_PUT, 0, 0, struct.pack(_fmt(len(words)), *words))
            words = words[count:]
            if words:
                self._wait(got)

    def get(self, buf=None, shift=0):
        # ports/rp2/rp2_pio.c, rp2_state_machine_get: a writable buffer is filled item by item
        # as its typecode says, without regard to sign (bytearray, 'b', 'h', 'i'); another
        # typecode raises ValueError once the first word is taken; it returns the buffer.
        if buf is None and self._rx and self._at == _hil.now():  # (a word the last LEVELS gave: as below)
            return self._take() >> shift
        n = 1
        if buf is not None:
            view, size = _get_items(buf)
            if not view:
                return buf
            n = len(view) // size if size else 1
        out = []
        while len(out) < n:
            if self._rx and self._at == _hil.now():  # (the oldest word: no instant needed, _instant)
                out.append(self._take())
                continue
            count, got = self._call(F.BUS_PIO_GET, 0, n - len(out))
            out += struct.unpack_from(_fmt(count), got, 4)
            if len(out) < n:
                self._wait(got)
        if buf is None:
            return out[0] >> shift
        if not size:
            raise ValueError("unsupported buffer type")
        mask = (1 << (8 * size)) - 1
        struct.pack_into(_fmt(n, size), view, 0, *[(w >> shift) & mask for w in out])
        return buf

    def _take(self):
        """The oldest word the last LEVELS gave, taken (the host told of it with the next frame)."""
        self._popped += 1
        if self not in _POPPED:
            _POPPED.append(self)
        return self._rx.pop(0)

    def _wait(self, reply):
        """The FIFO is not ready: the board's CPU blocks; so does virtual time, until the
        state machine may have moved it (the host says when, with the pins as they are)."""
        wait_us = struct.unpack_from("<I", reply, 0)[0] or _RETRY_US
        _hil.run_until(_hil.now() + wait_us)

    def rx_fifo(self):
        if self._at == _instant():
            return len(self._rx)
        return self._call(F.BUS_PIO_LEVELS, 0, 2)[1][0]

    def tx_fifo(self):
        if self._at == _instant():
            return self._tx_level
        return self._call(F.BUS_PIO_LEVELS, 0, 2)[1][1]

    def irq(self, handler=_KEEP, trigger=1, hard=False):
        """``handler(sm)`` when the program raises its own IRQ flag (``irq(rel(0))``: flag
        ``id % 4`` of its block), as the port's soft handler (docs/shim.md, "PIO", IRQs);
        ``irq()`` the IRQ object as it is."""
        irq = _Irq.of(self)
        if handler is not _KEEP or trigger != 1 or hard:
            handler = None if handler is _KEEP else handler
            irq._set(handler, 1 << (self._id & 3) if handler is not None and trigger else 0)
        return irq


POLL_US = 1000  # while a PIO IRQ handler is armed, the shim asks for raised flags this often


class _Irq:
    """The IRQ of a StateMachine or a PIO: its handler and the flags (0..3 of the block)
    it watches. The host clears a watched flag as it is raised (the port's interrupt
    handler does) and keeps the raise; a soft timer polls for them every POLL_US."""

    _all = {}  # owner -> its _Irq
    _timer = None

    @classmethod
    def of(cls, owner):
        key = (isinstance(owner, PIO), owner._id)  # (PIO(0) is one block however often made)
        irq = cls._all.get(key)
        if irq is None:
            irq = cls._all[key] = object.__new__(cls)
            irq._owner, irq._handler, irq._mask, irq._flags = owner, None, 0, 0
        return irq

    def flags(self):
        return self._flags

    def trigger(self):
        return self._mask << 8 if isinstance(self._owner, PIO) else (1 if self._mask else 0)

    def _set(self, handler, mask):
        self._handler, self._mask = handler, mask
        _Irq._arm()

    @staticmethod
    def _block(owner):
        return owner._id if isinstance(owner, PIO) else owner._id >> 2

    @classmethod
    def _armed(cls, block):
        mask = 0
        for irq in cls._all.values():
            if irq._handler is not None and cls._block(irq._owner) == block:
                mask |= irq._mask
        return mask

    @classmethod
    def _arm(cls):
        import machine

        for block in (0, 1):
            sm = _Irq._sm_of(block)
            if sm is not None:
                sm._call(F.BUS_PIO_IRQ, cls._armed(block))
        live = any(irq._handler is not None and irq._mask for irq in cls._all.values())
        if live and cls._timer is None:
            cls._timer = machine.Timer(-1)
            cls._timer.init(period=POLL_US, tick_hz=1_000_000, callback=cls._poll)
        elif not live and cls._timer is not None:
            cls._timer.deinit()
            cls._timer = None

    @staticmethod
    def _sm_of(block):
        for sm_id in range(block * 4, block * 4 + 4):
            sm = _SMS.get(sm_id)
            if sm is not None and sm._handle is not None:
                return sm
        return None

    @classmethod
    def _poll(cls, _timer=None):
        for block in (0, 1):
            mask = cls._armed(block)
            sm = cls._sm_of(block)
            if not mask or sm is None:
                continue
            count, got = sm._call(F.BUS_PIO_IRQ, mask)
            for flag in got[4 * count : 5 * count]:
                cls._fire(block, flag)

    @classmethod
    def _fire(cls, block, flag):
        for irq in list(cls._all.values()):
            if irq._handler is None or not irq._mask >> flag & 1 or cls._block(irq._owner) != block:
                continue
            irq._flags = 0x100 << flag if isinstance(irq._owner, PIO) else 1
            irq._handler(irq._owner)


class DMA:
    def __init__(self, *args, **kw):
        raise NotImplementedError(
            "rp2.DMA is not in the loop: feed a StateMachine with put() and read it with get() (docs/shim.md, 'PIO')"
        )


class Flash:
    def __init__(self, *args, **kw):
        raise NotImplementedError("rp2.Flash is not in the loop: the board's filesystem is (docs/shim.md)")


def bootsel_button():
    """1 while the BOOTSEL button is held. ports/rp2/modrp2.c, bootsel_button: QSPI_SS let
    float for MICROPY_HW_BOOTSEL_DELAY_US (8 us, interrupts off), the button pulls it low.
    The rig file wires it as the board's pin BOOTSEL (docs/rig-file.md); unwired, it is
    never pressed."""
    import machine

    line = machine._board_line("BOOTSEL")
    _hil.bus_time(_hil.now() + 8)
    return 0 if line.value() else 1


def country(code=None):
    return "XX"


from _hildht import dht_readinto  # noqa: E402, F401  (the port's name: the dht module reads with it)

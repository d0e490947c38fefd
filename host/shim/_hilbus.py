# machine.I2C, SoftI2C, SPI and SoftSPI in the loop (docs/shim.md, "Buses").
#
# Imported by machine at the first use of one of them: a firmware with no bus runs none of
# this. Each bus is a handle (CFG_I2C, CFG_SPI); each transfer is one BUS frame the host
# answers from the devices on that bus as the plant is at the transfer's instant
# (_hil.transfer), then the clock moves on by the transfer's time at the bus clock: I2C 9
# clocks a byte (8 bits and the acknowledge) plus a clock for each start and stop; SPI 8 a
# byte. Errors are the OSError the board family raises (ports/esp32/machine_i2c.c,
# ports/rp2/machine_i2c.c, extmod/machine_i2c.c): a board's message is the errno alone.
# Buffers are taken as the C's mp_get_buffer_raise takes them (_hilbuf: bytes, bytearray,
# str to write, array of any typecode and memoryview, by their bytes).
import machine
import struct

import _hil
import _hilframe as F
from _hilbuf import fill, rbuf, wbuf

ENODEV = 19
EIO = 5
ETIMEDOUT = 110
_RP2_PINS = {0: ("GP5", "GP4"), 1: ("GP7", "GP6")}  # the Pico's default I2C pins (scl, sda)
_ESP32_PINS = {0: (18, 19), 1: (25, 26)}


def _key(pin):
    """A pin as the shim names it (a Pin, a number or a name)."""
    return str(pin._id if isinstance(pin, machine.Pin) else pin)


def _rp2():
    return machine._platform() == "rp2"


def _reverse(data):
    """Each byte's bits in the other order (an SPI set to LSB first against an MSB-first chip)."""
    out = bytearray(len(data))
    for i, b in enumerate(data):
        r = 0
        for _ in range(8):
            r = (r << 1) | (b & 1)
            b >>= 1
        out[i] = r
    return bytes(out)


def _handle_of(made, key, obj):
    """The handle of peripheral ``key`` (one per key, as on a board), now ``obj``'s."""
    handle = made.get(key)
    if handle is None:
        handle = made[key] = _hil.register(obj)
    else:
        _hil._handles[handle] = obj
    return handle


class _Bus:
    _made = {}  # bus name -> its handle (one per bus, as on a board)

    def _open(self, kind, key, clock_hz):
        self._key = key
        self._handle = handle = _handle_of(_Bus._made, key, self)
        _hil.configure(handle, kind, key, param=clock_hz)

    def _hil_apply(self, kind, value, extra):
        pass  # (a bus takes no input changes: the host answers its transfers)

    def _clocks(self, n_clocks, clock_hz):
        return (n_clocks * 1_000_000 + clock_hz - 1) // clock_hz


class SoftI2C(_Bus):
    """Bit-banged I2C on any two pins: an address not acknowledged raises ENODEV; a data
    byte not acknowledged ends the write (writeto returns the acks so far)."""

    _hard = False

    def __init__(self, scl, sda, *, freq=400000, timeout=50000):
        self.init(scl, sda, freq=freq, timeout=timeout)

    def init(self, scl, sda, *, freq=400000, timeout=50000):
        self._scl, self._sda = _key(scl), _key(sda)
        self._setup(freq, timeout, "i2c:%s,%s" % (self._scl, self._sda))

    def _setup(self, freq, timeout, key):
        if freq <= 0:
            raise ValueError("freq must be positive")
        self._freq = freq
        self._timeout_us = timeout
        self._open(F.CFG_I2C, key, freq)

    def __repr__(self):
        return "SoftI2C(scl=%s, sda=%s, freq=%d)" % (self._scl, self._sda, self._freq)

    # -- transfers ------------------------------------------------------------------

    def _xfer(self, addr, data, n_read, stop=True):
        op = F.BUS_XFER if stop else F.BUS_XFER_NOSTOP
        status, count, got, t = _hil.transfer(self._handle, op, addr, n_read, bytes(data))
        wrote = len(data)
        if status == F.BUS_STUCK:
            _hil.bus_time(t + self._timeout_us)
            raise OSError(ETIMEDOUT)
        if status == F.BUS_NACK_ADDRESS:
            _hil.bus_time(t + self._clocks(9 + 2, self._freq))
            raise OSError(self._nack_errno(data, n_read))
        on_wire = 1 + (count if status == F.BUS_NACK_DATA else wrote)
        clocks = 9 * on_wire + 1 + (1 if stop else 0)
        if n_read and wrote:
            clocks += 9 * (1 + n_read) + 1  # the repeated start, the address again, the bytes
        elif n_read:
            clocks += 9 * n_read
        _hil.bus_time(t + self._clocks(clocks, self._freq))
        if status == F.BUS_NACK_DATA and self._hard:
            raise OSError(EIO if _rp2() else ENODEV)  # (SoftI2C stops there and returns the acks)
        return count, got

    def _nack_errno(self, data, n_read):
        if self._hard and _rp2() and (data or n_read):
            return EIO  # (the RP2040's hardware; its zero-length write goes through SoftI2C)
        return ENODEV

    def scan(self):
        status, _count, got, t = _hil.transfer(self._handle, F.BUS_SCAN, 0, 0, b"")
        _hil.bus_time(t + self._clocks((0x78 - 0x08) * (9 + 2), self._freq))
        if status == F.BUS_STUCK:
            return []
        return list(got)

    def readfrom(self, addr, nbytes, stop=True):
        return self._xfer(addr, b"", nbytes, stop)[1]

    def readfrom_into(self, addr, buf, stop=True):  # (extmod/machine_i2c.c, machine_i2c_readfrom_into)
        view = wbuf(buf)
        fill(view, self._xfer(addr, b"", len(view), stop)[1])

    def writeto(self, addr, buf, stop=True):  # (machine_i2c_writeto)
        buf = rbuf(buf)
        acks = self._xfer(addr, buf, 0, stop)[0]
        return len(buf) if self._hard else acks

    def writevto(self, addr, vector, stop=True):  # (machine_i2c_writevto: mp_obj_get_array)
        if not isinstance(vector, (tuple, list)):
            raise TypeError("object '%s' isn't a tuple or list" % type(vector).__name__)
        data = b"".join([rbuf(b) for b in vector])
        acks = self._xfer(addr, data, 0, stop)[0]
        return len(data) if self._hard else acks

    def _memaddr(self, memaddr, addrsize):
        if addrsize == 8:  # (the common case, without the generator below)
            return bytes((memaddr & 0xFF,))
        if addrsize not in (16, 24, 32):
            raise ValueError("invalid addrsize")
        return bytes((memaddr >> s) & 0xFF for s in range(addrsize - 8, -1, -8))

    def readfrom_mem(self, addr, memaddr, nbytes, *, addrsize=8):
        return self._xfer(addr, self._memaddr(memaddr, addrsize), nbytes)[1]

    def readfrom_mem_into(self, addr, memaddr, buf, *, addrsize=8):  # (machine_i2c_readfrom_mem_into)
        view = wbuf(buf)
        fill(view, self._xfer(addr, self._memaddr(memaddr, addrsize), len(view))[1])

    def writeto_mem(self, addr, memaddr, buf, *, addrsize=8):  # (machine_i2c_writeto_mem)
        buf = rbuf(buf)
        self._xfer(addr, self._memaddr(memaddr, addrsize) + bytes(buf), 0)

    # -- primitives (SoftI2C's; a hardware I2C has none) -------------------------------

    def _primitive(self, op, data=b"", n_read=0):
        if self._hard:
            raise OSError("I2C operation not supported")
        status, count, got, t = _hil.transfer(self._handle, op, 0, n_read, data)
        if status == F.BUS_STUCK:
            _hil.bus_time(t + self._timeout_us)
            raise OSError(ETIMEDOUT)
        _hil.bus_time(t + self._clocks(9 * (len(data) + n_read) or 1, self._freq))
        return count, got

    def start(self):
        self._primitive(F.BUS_START)

    def stop(self):
        self._primitive(F.BUS_STOP)

    def write(self, buf):  # (machine_i2c_write)
        return self._primitive(F.BUS_WRITE, bytes(rbuf(buf)))[0]

    def readinto(self, buf, nack=True):  # (machine_i2c_readinto)
        view = wbuf(buf)
        fill(view, self._primitive(F.BUS_READ if nack else F.BUS_READ_ACK, b"", len(view))[1])


class I2C(SoftI2C):
    """The hardware I2C controller: I2C(id, *, scl, sda, freq=400000, timeout=50000) as on an
    ESP32 (id 0 by default); on an RP2040, I2C(id, freq, scl, sda) too. A NACK raises
    ENODEV (ESP32) or EIO (RP2040); a held bus ETIMEDOUT."""

    _hard = True

    def __init__(self, id=0, freq=400000, scl=None, sda=None, *, timeout=50000):
        self.init(id, freq, scl, sda, timeout=timeout)

    def init(self, id=0, freq=400000, scl=None, sda=None, *, timeout=50000):
        if id == -1:
            raise ValueError("I2C(-1) is SoftI2C on a board: use SoftI2C(scl, sda)")
        pins = _RP2_PINS if _rp2() else _ESP32_PINS
        if id not in pins:
            raise ValueError("I2C(%d) doesn't exist" % id)
        self._id = id
        self._scl = _key(scl) if scl is not None else str(pins[id][0])
        self._sda = _key(sda) if sda is not None else str(pins[id][1])
        self._setup(freq, timeout, "i2c%d" % id)

    def __repr__(self):
        return "I2C(%d, scl=%s, sda=%s, freq=%d)" % (self._id, self._scl, self._sda, self._freq)


class SoftSPI(_Bus):
    """Bit-banged SPI: the bytes written go out on MOSI, as many come in on MISO from the
    device whose chip select (a Pin the firmware drives) is low; 0xFF when none is."""

    MSB = 0
    LSB = 1

    def __init__(self, baudrate=500000, *, polarity=0, phase=0, bits=8, firstbit=0, sck=None, mosi=None, miso=None):
        self.init(baudrate, polarity=polarity, phase=phase, bits=bits, firstbit=firstbit, sck=sck, mosi=mosi, miso=miso)

    def init(self, baudrate=500000, *, polarity=0, phase=0, bits=8, firstbit=0, sck=None, mosi=None, miso=None):
        if sck is None or mosi is None or miso is None:
            raise TypeError("SoftSPI needs sck, mosi and miso pins")
        self._pins = (_key(sck), _key(mosi), _key(miso))
        self._setup(baudrate, polarity, phase, bits, firstbit, "spi:%s,%s,%s" % self._pins)

    def _setup(self, baudrate, polarity, phase, bits, firstbit, key):
        if baudrate <= 0:
            raise ValueError("baudrate must be positive")
        self._baud = baudrate
        self._polarity, self._phase, self._bits, self._firstbit = polarity, phase, bits, firstbit
        self._open(F.CFG_SPI, key, baudrate)

    def __repr__(self):  # (as extmod's soft SPI prints itself)
        return "SoftSPI(baudrate=%d, polarity=%d, phase=%d, sck=%s, mosi=%s, miso=%s)" % (
            (self._baud, self._polarity, self._phase) + self._pins
        )

    def _xfer(self, data):
        if self._firstbit == self.LSB:
            data = _reverse(data)
        data = bytes(data)
        got = None
        for i in range(0, len(data) or 1, _SPI_PIECE):  # (a display's frame: a BUS frame holds _SPI_PIECE bytes)
            _status, _count, part, t = _hil.transfer(self._handle, F.BUS_SPI_XFER, 0, 0, data[i : i + _SPI_PIECE])
            _hil.bus_time(t + self._clocks(8 * min(_SPI_PIECE, len(data) - i), self._baud))
            got = part if got is None else got + part
        return _reverse(got) if self._firstbit == self.LSB else got

    def read(self, nbytes, write=0x00):
        return self._xfer(bytes((write,)) * nbytes)

    def readinto(self, buf, write=0x00):  # (extmod/machine_spi.c, mp_machine_spi_readinto)
        view = wbuf(buf)
        fill(view, self._xfer(bytes((write & 0xFF,)) * len(view)))

    def write(self, buf):  # (mp_machine_spi_write)
        self._xfer(rbuf(buf))

    def write_readinto(self, write_buf, read_buf):  # (mp_machine_spi_write_readinto)
        data = rbuf(write_buf)
        view = wbuf(read_buf)
        if len(data) != len(view):
            raise ValueError("buffers must be the same length")
        fill(view, self._xfer(data))

    def deinit(self):  # (extmod/machine_spi.c, machine_spi_deinit; I2C and SoftI2C have none on rp2 and esp32)
        pass


class SPI(SoftSPI):
    """The hardware SPI controller: SPI(id, baudrate, *, polarity, phase, bits, firstbit,
    sck, mosi, miso); ids 1 and 2 on an ESP32, 0 and 1 on an RP2040."""

    def __init__(
        self, id, baudrate=1000000, *, polarity=0, phase=0, bits=8, firstbit=0, sck=None, mosi=None, miso=None
    ):
        self._id = id
        self.init(baudrate, polarity=polarity, phase=phase, bits=bits, firstbit=firstbit, sck=sck, mosi=mosi, miso=miso)

    def init(self, baudrate=1000000, *, polarity=0, phase=0, bits=8, firstbit=0, sck=None, mosi=None, miso=None):
        ids = (0, 1) if _rp2() else (1, 2)
        if self._id not in ids:
            raise ValueError("SPI(%s) doesn't exist" % (self._id,))
        self._pins = tuple(_key(p) if p is not None else "-1" for p in (sck, mosi, miso))
        self._setup(baudrate, polarity, phase, bits, firstbit, "spi%d" % self._id)
        if _rp2():  # ports/rp2/machine_spi.c, machine_spi_make_new: gpio_set_function(sck/mosi/miso, GPIO_FUNC_SPI)
            for p in (sck, mosi, miso):  # (the pins given; the board's default pins, which the port
                if p is not None:  # also muxes when one is not given, are not modelled)
                    pin = p if isinstance(p, machine.Pin) else machine.Pin(p)
                    if isinstance(pin._id, int):
                        pin._give(machine.Pin.ALT_SPI)

    def __repr__(self):  # (as each port prints its SPI: drivers and tests parse the baudrate)
        settings = (self._baud, self._polarity, self._phase, self._bits)
        if _rp2():
            return "SPI(%d, baudrate=%d, polarity=%d, phase=%d, bits=%d, sck=%s, mosi=%s, miso=%s)" % (
                (self._id,) + settings + self._pins
            )
        return "SPI(id=%d, baudrate=%d, polarity=%d, phase=%d, bits=%d, firstbit=%d, sck=%s, mosi=%s, miso=%s)" % (
            (self._id,) + settings + (self._firstbit,) + self._pins
        )


# -- machine.bitstream (docs/shim.md, "Buses": NeoPixels) --------------------------------


def _ones(data):
    n = 0
    for b in data:
        while b:
            n += b & 1
            b >>= 1
    return n


def bitstream(pin, encoding, timing, data):
    """machine.bitstream (extmod/machine_bitstream.c): encoding 0 sends each bit, MSB
    first, as a high then a low of the timing's (high_0, low_0, high_1, low_1) ns. One BUS
    frame on the pin's handle carries the timing and the bytes; the firmware is blocked for
    the stream's time (a board sends it with interrupts off), the pin low after it."""
    if not isinstance(pin, machine.Pin):
        pin = machine.Pin(pin, machine.Pin.OUT)
    data = bytes(rbuf(data))  # (mp_get_buffer_raise, MP_BUFFER_READ: before the encoding)
    if encoding != 0:
        raise ValueError("encoding")
    if len(timing) != 4:
        raise ValueError("tuple/list has wrong length")
    ns = [int(t) for t in timing]
    ones = _ones(data)
    total_ns = ones * (ns[2] + ns[3]) + (8 * len(data) - ones) * (ns[0] + ns[1])
    payload = struct.pack("<4I", *[t & 0xFFFFFFFF for t in ns]) + data
    _status, _count, _got, t = _hil.transfer(pin._handle, F.BUS_BITSTREAM, 0, 0, payload)
    _hil.bus_time(t + (total_ns + 999) // 1000)


# machine.I2CTarget (MicroPython 1.26+: extmod/machine_i2c_target.c, with
# ports/rp2/machine_i2c_target.c and ports/esp32/machine_i2c_target.c; offered on every
# version). A controller's transaction (another board's I2C on the wire to this one:
# docs/multi-board.md) arrives as one change at its instant; the target runs the C's state
# machine over it, byte by byte, calling the handler as the C calls it (a hard one at once, a
# soft one scheduled), and tells the host what the controller read (I2CT_DONE).
_IRQ_ADDR_MATCH_READ = 1
_IRQ_ADDR_MATCH_WRITE = 2
_IRQ_READ_REQ = 4
_IRQ_WRITE_REQ = 8
_IRQ_END_READ = 16
_IRQ_END_WRITE = 32
_IRQ_MEM_ADDR_MATCH = 64  # (the C's internal event: memaddr)
_IRQ_ALL_HARD = _IRQ_ADDR_MATCH_READ | _IRQ_ADDR_MATCH_WRITE | _IRQ_READ_REQ | _IRQ_WRITE_REQ
_IDLE, _MATCH_READ, _MATCH_WRITE, _MEM_ADDR_SELECT, _READING, _WRITING, _INACTIVE = range(7)
_SPI_PIECE = F.MAX_PAYLOAD - max(F.BUS_LEN, F.BUS_REPLY_LEN)  # an SPI transfer's bytes in one BUS frame
_TX_FIFO = 16  # the RP2040's I2C TX FIFO (datasheet 4.3.1: 16 entries); what write() can buffer


class _TargetIRQ:
    """The object I2CTarget.irq() returns (shared/runtime/mpirq.c's: flags(), trigger())."""

    def __init__(self, target):
        self._target = target

    def flags(self):
        return self._target._flags

    def trigger(self, new=None):
        t = self._target
        if new is not None:
            t._trigger, t._flags = new, 0
        return t._trigger


class I2CTarget:
    """machine.I2CTarget: this board as a target at ``addr`` on its I2C ``id``, a memory
    device (``mem``) or one served by its IRQ handler (readinto, write). The ESP32 family's
    has no hard IRQ and only the END events (its mpconfigport.h sets no
    MICROPY_PY_MACHINE_I2C_TARGET_HARD_IRQ)."""

    IRQ_END_READ = _IRQ_END_READ
    IRQ_END_WRITE = _IRQ_END_WRITE
    _made = {}  # id -> handle (one peripheral per id)

    def __init__(self, id=None, addr=None, *, addrsize=7, mem=None, mem_addrsize=8, scl=None, sda=None):
        if addr is None:  # (the ports' make_new: id may be left out where it has a default, addr never)
            if id is None:
                raise TypeError("'addr' argument required")
            id, addr = None, id
        if id is None:
            if _rp2():
                raise TypeError("'id' argument required")  # (no PICO_DEFAULT_I2C on the boards the loop names)
            id = 0
        if not 0 <= id <= 1:
            raise ValueError("I2CTarget(%d) doesn't exist" % id)
        if mem is not None:
            if mem_addrsize < 0 or mem_addrsize > 32 or mem_addrsize % 8:
                raise ValueError("mem_addrsize must be 0, 8, 16, 24 or 32")
            self._mem_obj = mem  # (held, as the C's root pointer holds it)
            mem = wbuf(mem)
        self._id, self._addr, self._mem = id, int(addr), mem
        self._mem_addrsize = mem_addrsize // 8
        self._state = _IDLE
        self._mem_addr = self._mem_addr_last = self._mem_addr_count = 0
        self._handler, self._trigger, self._hard, self._flags = None, 0, False, 0
        self._rx = b""  # the byte the controller wrote, for readinto (WRITE_REQ)
        self._tx = bytearray()  # what write() gave, for the controller's reads (READ_REQ)
        self._key = key = "i2ct%d" % id
        self._handle = handle = _handle_of(I2CTarget._made, id, self)
        _hil.configure(handle, F.CFG_I2CT, key, param=self._addr)

    @property
    def memaddr(self):
        return self._mem_addr_last

    def deinit(self):
        if self._state != _INACTIVE:
            self._state = _INACTIVE
            self._handler = None
            _hil.configure(self._handle, F.CFG_I2CT, self._key, param=-1)

    def readinto(self, buf):
        depth = _hil.heap_release()  # (from a hard handler, the heap locked: the port's FIFO read allocates nothing)
        try:
            view = wbuf(buf)
            n = min(len(view), len(self._rx))
            view[:n] = self._rx[:n]
            self._rx = self._rx[n:]
        finally:
            _hil.heap_restore(depth)
        return n

    def write(self, buf):
        depth = _hil.heap_release()  # (as readinto)
        try:
            data = rbuf(buf)
            n = min(len(data), _TX_FIFO - len(self._tx))
            self._tx += data[:n]
        finally:
            _hil.heap_restore(depth)
        return n

    def irq(self, handler=None, trigger=_IRQ_END_READ | _IRQ_END_WRITE, hard=False):
        if handler is not None or trigger != _IRQ_END_READ | _IRQ_END_WRITE or hard:
            if _rp2():
                if trigger & _IRQ_ALL_HARD and not hard:
                    raise ValueError("hard IRQ required")
            elif hard:
                raise ValueError("hard IRQ unsupported")
            self._hard, self._flags = bool(hard) and handler is not None, 0
            self._handler = _hil.hard_handler(handler) if self._hard else handler  # (the heap locked around it)
            self._trigger = trigger if handler is not None else 0
        irq = getattr(self, "_irq", None)  # (one a target, as the port's: a hard handler's irq() allocates nothing)
        if irq is None:
            irq = self._irq = _TargetIRQ(self)
        return irq

    # -- the controller's transaction (the C's state machine) ------------------------

    def _event(self, trigger):
        if trigger & _IRQ_MEM_ADDR_MATCH:
            self._mem_addr_last = self._mem_addr
        if self._handler is None or not trigger & self._trigger:
            return False
        self._flags = trigger & self._trigger
        if self._hard:
            _hil.run_hard_now(self._handler, self)
        else:
            _hil.schedule(self._handler, self)
        return True

    def _reset(self):
        if self._state == _READING:
            self._event(_IRQ_END_READ)
        elif self._state == _MATCH_WRITE or self._state == _WRITING:
            self._event(_IRQ_END_WRITE)
        self._state = _IDLE

    def _addr_match(self, read):
        self._reset()
        self._event(_IRQ_ADDR_MATCH_READ if read else _IRQ_ADDR_MATCH_WRITE)
        self._state = _MATCH_READ if read else _MATCH_WRITE

    def _read_request(self):
        handled = self._event(_IRQ_READ_REQ) if not self._tx else True
        mem = self._mem
        if mem is None:
            self._state = _READING
            if not self._tx:
                if handled:
                    return 0xFF  # (a handler that wrote nothing: the bus reads released, high)
                return 0  # ("No data source, just write out a zero")
            b = self._tx[0]
            self._tx = self._tx[1:]
            return b
        if self._state == _MEM_ADDR_SELECT:
            self._mem_addr %= len(mem)
            self._event(_IRQ_MEM_ADDR_MATCH)
        self._state = _READING
        b = mem[self._mem_addr]
        self._mem_addr = (self._mem_addr + 1) % len(mem)
        return b

    def _write_request(self, byte):
        self._rx += bytes((byte,))
        handled = self._event(_IRQ_WRITE_REQ)
        mem = self._mem
        if mem is None:
            self._state = _WRITING
            if not handled:
                self._rx = b""  # ("No data sink, just read and discard the incoming byte")
            return
        self._rx = b""
        if self._state == _MATCH_WRITE:
            self._state = _MEM_ADDR_SELECT
            self._mem_addr = 0
            self._mem_addr_count = self._mem_addrsize
        if self._state == _MEM_ADDR_SELECT and self._mem_addr_count > 0:
            self._mem_addr = self._mem_addr << 8 | byte
            self._mem_addr_count -= 1
            if self._mem_addr_count == 0:
                self._mem_addr %= len(mem)
                self._event(_IRQ_MEM_ADDR_MATCH)
        else:
            if self._state == _MEM_ADDR_SELECT:
                self._state = _WRITING
            mem[self._mem_addr] = byte
            self._mem_addr = (self._mem_addr + 1) % len(mem)

    def _hil_apply(self, kind, value, extra):
        """A controller's transaction at this instant (CH_BYTES, F.I2CT_XACT_FMT): XFER's
        phases as the port's I2C interrupt sees them (ports/rp2/machine_i2c_target.c,
        i2c_target_handler: an address match at the first byte of each direction, a request
        per byte, the end at the stop); the bytes read go back to the host."""
        op, n_read = struct.unpack_from(F.I2CT_XACT_FMT, extra, 0)
        data = extra[struct.calcsize(F.I2CT_XACT_FMT) :]
        got = bytearray()
        if self._state == _INACTIVE:
            _hil.send(F.I2CT_DONE, struct.pack(F.I2CT_DONE_FMT, _hil.now(), self._handle, F.BUS_NACK_ADDRESS, 0))
            return
        if data or not n_read:
            self._addr_match(False)
            for byte in data:
                self._write_request(byte)
        if n_read:
            self._addr_match(True)
            for _ in range(n_read):
                got.append(self._read_request())
            self._tx = bytearray()  # (what the controller did not read is dropped at its NACK)
        if op == F.BUS_XFER:
            self._reset()  # the stop
        head = struct.pack(F.I2CT_DONE_FMT, _hil.now(), self._handle, F.BUS_OK, len(data))
        _hil.send(F.I2CT_DONE, head + bytes(got))


if _rp2():  # (MICROPY_PY_MACHINE_I2C_TARGET_HARD_IRQ: the rp2's, not the ESP32's)
    I2CTarget.IRQ_ADDR_MATCH_READ = _IRQ_ADDR_MATCH_READ
    I2CTarget.IRQ_ADDR_MATCH_WRITE = _IRQ_ADDR_MATCH_WRITE
    I2CTarget.IRQ_READ_REQ = _IRQ_READ_REQ
    I2CTarget.IRQ_WRITE_REQ = _IRQ_WRITE_REQ

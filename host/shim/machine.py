# machine module for firmware running in the loop, shadowing the unix port's own.
# API after MicroPython's docs (docs/library/machine.*.rst); constants as on the ESP32
# port. Every pin, ADC, PWM and UART is a handle the host wires to a plant signal.
import _hil
import _hilframe as _F

_pending = _hil._pending  # callbacks due (the one list, never rebound)
_DEPTH = _hil._Link.depth  # the scheduler's queue (_hil.schedule)
_RISING, _FALLING = _F.IRQ_RISING, _F.IRQ_FALLING

_UNIQUE_ID = b"\x24\x0a\xc4\x00\xf1\x1e"
PWRON_RESET = 1
HARD_RESET = 2
WDT_RESET = 3
DEEPSLEEP_RESET = 4
SOFT_RESET = 5
_reset_cause = PWRON_RESET
_UNSET = object()


def _subclass(cls, id, obj=None):
    """A Python subclass of Pin, ADC or UART (py/objtype.c, mp_obj_instance_make_new): an
    object of its own (``obj``, or a new one: the one made before if it is of that class,
    Led(25) is Led(25)), bound to its peripheral when the call names it, or when the
    subclass's __init__ passes it to super().__init__() (native_base_init_wrapper), as
    ``class Remote(Pin): def __init__(self): super().__init__(5, Pin.IN)`` does; the state
    of one made before goes with it (its handle then names it). Called with few arguments:
    with MCU time the firmware's call of __new__ is charged the callee's frame when it is
    too large for the C stack (py/objfun.c, fun_bc_call), which moved the charged time of
    every firmware that makes an ADC."""
    base = Pin if issubclass(cls, Pin) else ADC if issubclass(cls, ADC) else UART
    key = _pin_id(id) if base is Pin else _adc_key(id) if base is ADC else id
    old = base._made.get(key)
    if obj is None:
        if isinstance(old, cls):
            return old
        obj = object.__new__(cls)
    if old is not obj:
        if old is not None:
            for name, value in old.__dict__.items():
                setattr(obj, name, value)
            _hil._handles[old._handle] = obj
        base._made[key] = obj
        if old is None:
            (_set_up if base is Pin else _adc_set_up if base is ADC else UART._set_up)(obj, key)
    return obj


def _platform():
    import sys

    return getattr(sys.modules.get("sys", sys), "platform", "")


def _mcu():
    import sys

    return getattr(getattr(sys.modules.get("sys", sys), "implementation", None), "_machine", "")


_RP2 = _platform() == "rp2"  # (machine is imported once the host has named the board's family)
_RP2350 = _RP2 and "RP2350" in _mcu()
_ESP32 = _platform() == "esp32"  # (no family named: neither)
_REG = None
if _RP2 and not _RP2350:
    import _hilreg as _REG  # the RP2040's registers behind mem32 (PWM, IO_BANK0, SIO)


class _Names:
    """Pin.board and Pin.cpu: the port's names for its pins, each the pin itself."""

    def __init__(self, kind, names):
        self._kind = kind
        self._names = names

    def __getattr__(self, name):
        gpio = self._names.get(name)
        if gpio is None:  # (as the port's type object board or cpu says it)
            raise AttributeError("type object '%s' has no attribute '%s'" % (self._kind, name))
        return Pin(gpio)


if _RP2:
    # ports/rp2/boards/RPI_PICO/pins.csv (RPI_PICO2's is the same): GP0..GP22, GP25..GP28, LED;
    # the cpu names are GPIO0..GPIO29 (NUM_BANK0_GPIOS: 30 on an RP2040 and an RP2350A)
    _BOARD_NAMES = {"GP%d" % n: n for n in tuple(range(23)) + (25, 26, 27, 28)}
    _BOARD_NAMES["LED"] = 25
    _CPU_NAMES = {"GPIO%d" % n: n for n in range(30)}
    if not _mcu().startswith("Raspberry Pi Pico"):  # a kit's board: its own pins.csv (_hilboards.py)
        import _hilboards

        _named = _hilboards.board(_mcu())
        if _named:
            _BOARD_NAMES = _named[1]
            _CPU_NAMES = {"GPIO%d" % n: n for n in range(_named[0])}
else:
    _BOARD_NAMES = {}  # ports/esp32: a generic ESP32 has no pins.csv, its Pin.board is empty
    _CPU_NAMES = None  # (and it has no Pin.cpu)


_ALT_SIO = 5  # GPIO_FUNC_SIO, the rp2 port's default alt=
_ALT = 3  # MACHINE_PIN_MODE_ALT (ports/rp2/machine_pin.h)


def _rp2_afs(gpio):
    """The functions a GPIO has, as GPIO_FUNC_* values (ports/rp2/boards/rp2_af.csv: SPI,
    UART, I2C, PWM, SIO, PIO0, PIO1 and USB on every GPIO, GPCK on GP20..GP25)."""
    gpck, usb = (9, 10) if _RP2350 else (8, 9)
    afs = (1, 2, 3, 4, 5, 6, 7, usb)
    return afs + (gpck,) if isinstance(gpio, int) and 20 <= gpio <= 25 else afs


def _pin_id(id):
    """A pin's id as the port finds it (machine_pin_find): a number, a Pin, or on a port
    with named pins (rp2) a board name, then a cpu name; an unknown name is a ValueError.
    A Pin is its own pin (ports/rp2/machine_pin.c machine_pin_find, ports/esp32/
    machine_pin.c machine_pin_get_id: Pin(Pin.board.X, Pin.OUT) is pin X)."""
    if isinstance(id, Pin):
        return id._id
    if isinstance(id, str) and _RP2:  # ports/rp2/machine_pin.c, machine_pin_find
        gpio = _BOARD_NAMES.get(id, _CPU_NAMES.get(id))
        if gpio is None:
            raise ValueError('unknown named pin "%s"' % id)
        return gpio
    if isinstance(id, str) and _platform() == "esp32":  # ports/esp32/machine_pin.c: Pin.board is empty
        raise ValueError("invalid pin")
    return id


class Pin:
    if _RP2:  # ports/rp2/machine_pin.h (MACHINE_PIN_MODE_*), machine_pin.c (GPIO_PULL_*, GPIO_IRQ_EDGE_*)
        IN = 0
        OUT = 1
        OPEN_DRAIN = 2
        ALT = 3
        PULL_UP = 1
        PULL_DOWN = 2
        IRQ_RISING = 8
        IRQ_FALLING = 4
        # the alternate functions (pico-sdk's GPIO_FUNC_*; ports/rp2/boards/rp2_af.csv's columns)
        ALT_SPI = 1
        ALT_UART = 2
        ALT_I2C = 3
        ALT_PWM = 4
        ALT_SIO = 5
        ALT_PIO0 = 6
        ALT_PIO1 = 7
        if _RP2350:  # (pico-sdk's RP2350 numbering; 1.25 has no ALT_PIO2)
            ALT_GPCK = 9
            ALT_USB = 10
        else:
            ALT_GPCK = 8
            ALT_USB = 9
        board = _Names("board", _BOARD_NAMES)
        cpu = _Names("cpu", _CPU_NAMES)
    else:  # ports/esp32/machine_pin.c: GPIO_MODE_*, GPIO_PULL_*, GPIO_INTR_*; no ALT, no alt=
        IN = 1
        OUT = 3
        OPEN_DRAIN = 7
        PULL_UP = 2
        PULL_DOWN = 1
        IRQ_RISING = _F.IRQ_RISING  # (the wire's trigger codes are the ESP32 port's values)
        IRQ_FALLING = _F.IRQ_FALLING
        board = _Names("board", _BOARD_NAMES)
    _MODES = {IN: _F.PIN_IN, OUT: _F.PIN_OUT, OPEN_DRAIN: _F.PIN_OPEN_DRAIN}  # as CFG_PIN says them
    _PULLS = {None: _F.PULL_NONE, PULL_UP: _F.PULL_UP, PULL_DOWN: _F.PULL_DOWN}
    _made = {}  # pin id -> its Pin: one object per pin, as on a board (Pin(4) is Pin(4))

    def __new__(cls, id=_UNSET, *args, **kw):
        if cls is not Pin:
            return object.__new__(cls) if id is _UNSET else _subclass(cls, id)
        if id is _UNSET:
            raise TypeError("function missing 1 required positional arguments")  # (py/argcheck.c)
        return _make(_pin_id(id), cls)

    def __init__(self, id, *args, **kw):
        if type(self) is not Pin:  # (a subclass's: its id given to super().__init__)
            _subclass(type(self), id, self)
        if _RP2 and not args and not kw:
            return  # (mp_pin_make_new: Pin(n) alone configures nothing)
        self.init(*args, **kw)

    if _RP2:

        def init(self, mode=-1, pull=None, *, value=None, alt=_ALT_SIO, **extra):
            # ports/rp2/machine_pin.c, machine_pin_obj_init_helper: a mode other than IN,
            # OUT and OPEN_DRAIN hands the pin to the function `alt` (which the pin must
            # have); the pulls are set every time (None: none)
            if extra:
                raise TypeError("extra keyword arguments given")  # (py/argcheck.c, mp_arg_parse_all)
            if mode is None:
                mode = -1
            if mode != -1 and mode not in self._MODES:
                if not (isinstance(alt, int) and alt in _rp2_afs(self._id)):
                    raise ValueError("invalid pin af: %d" % (alt,))
            if mode == self.OPEN_DRAIN and value is None:
                value = 1  # (mp_hal_pin_open_drain_with_value(id, value == -1 ? 1 : value): released)
            if not self._as_it_is(mode, pull, value, alt):
                self._init(mode, pull, value, alt)

    else:

        def init(self, mode=-1, pull=-1, *, value=None, drive=None, hold=None, **extra):
            # ports/esp32/machine_pin.c: init(mode, pull, *, value, drive, hold); no alt
            if extra:
                raise TypeError("extra keyword arguments given")  # (py/argcheck.c, mp_arg_parse_all)
            if mode != -1 and mode not in self._MODES:
                raise ValueError("invalid pin mode %r" % (mode,))
            if not self._as_it_is(mode, pull, value, _ALT_SIO):
                self._init(mode, pull, value, _ALT_SIO)

    def _as_it_is(self, mode, pull, value, alt):
        """The pin made anew as it is (a driver's ``Pin(n, Pin.IN)`` at each read): an input
        or an output in SIO's hands, the same mode, pull and level, and nothing else (a PWM,
        an ADC, a bus) configured on the pin since its CFG. Nothing changes for the host (the
        level is known, the line neither taken nor let go): no CFG, and no sync (docs/shim.md,
        "Pins")."""
        return (
            self._cfg
            and (mode == -1 or mode == self._mode)
            and (self._mode == Pin.IN or self._mode == Pin.OUT or self._mode == Pin.OPEN_DRAIN)
            and (pull == -1 or self._pull_of(pull) == self._pull)
            and (value is None or (1 if value else 0) == self._out)
            and _hil.cfg_last.get(self._id) == self._handle
        )

    def _pull_of(self, pull):
        """The pull a ``pull`` argument sets, as both ports take it: any int, its PULL_UP and
        PULL_DOWN bits (0 or None: no pull; ports/esp32/machine_pin.c, ``mode & GPIO_PULL_UP``;
        ports/rp2/machine_pin.c, ``gpio_set_pulls(id, pull & GPIO_PULL_UP, pull & GPIO_PULL_DOWN)``):
        ``Pin(5, Pin.OUT, 0)`` is an output with no pull. Both bits: the pull-up, to this model."""
        if pull is None:
            return None
        if not isinstance(pull, int):
            raise TypeError("can't convert %s to int" % type(pull).__name__)  # (mp_obj_get_int)
        if pull & self.PULL_UP:
            return self.PULL_UP
        if pull & self.PULL_DOWN:
            return self.PULL_DOWN
        return None

    def _init(self, mode, pull, value, alt):
        if mode != -1:
            if mode in self._MODES:
                self._mode, self._alt = mode, _ALT_SIO
            elif alt != _ALT_SIO:
                self._mode, self._alt = _ALT, alt
            elif self._mode not in (Pin.IN, Pin.OUT):  # (ALT with alt=ALT_SIO: SIO's again, its direction kept)
                self._mode, self._alt = Pin.IN, _ALT_SIO
        if pull != -1:
            self._pull = self._pull_of(pull)
        if value is not None:
            self._out = 1 if value else 0
        self._cfg = True
        drives = self._mode == Pin.OUT or self._mode == Pin.OPEN_DRAIN
        # A pin in ALT mode is the peripheral's: SIO drives it no more (an input to the
        # loop, its pad still read by value(); PIN_ALT tells the host its function, which
        # decides whether an SPI transfer clocks the chip on it); what value(x) writes waits
        # in SIO's output latch until the pin is OUT again (docs/shim.md, "Pins").
        if drives:
            mode_, param = self._MODES[self._mode], self._out
        elif _RP2 and self._mode == _ALT:
            mode_, param = _F.PIN_ALT, self._alt
        else:
            mode_, param = _F.PIN_IN, -1
        _hil.configure(self._handle, _F.CFG_PIN, self._id, mode_, self._PULLS[self._pull], param, sync=not drives)
        if drives:
            _hil.send_out(self._handle, _F.OUT_LEVEL, self._out)
        if _REG is not None and isinstance(self._id, int) and 0 <= self._id < _REG.N_GPIO:
            _REG.pin_state(self._id, self._mode == _ALT, self._alt, self._mode == Pin.OUT, self._out)

    def _give(self, func):
        """The pin handed to the function ``func`` (GPIO_FUNC_*) by what the port does for
        the firmware (SPI(..., sck=) muxing its pins, machine_spi.c's gpio_set_function; a
        FUNCSEL written through mem32): the loop told as Pin.init(mode=ALT, alt=func) tells
        it, SIO's OE and OUT left as they are (gpio_set_function changes FUNCSEL alone)."""
        self._mode, self._alt, self._cfg = _ALT, func, True
        _hil.configure(self._handle, _F.CFG_PIN, self._id, _F.PIN_ALT, self._PULLS[self._pull], func, sync=True)
        if _REG is not None and 0 <= self._id < _REG.N_GPIO:
            _REG.set_funcsel(self._id, func)

    def _from_registers(self, oe, out):
        """SIO's OE and OUT (or a GPIO's overrides) as mem32 set them: drive or let go."""
        mode = Pin.OUT if oe else Pin.IN
        if self._mode != mode or not self._cfg or (oe and out != self._out):
            self._init(mode, -1, out, _ALT_SIO)
        else:
            self._out = out

    def _hil_apply(self, kind, value, extra):
        old = self._level
        if old == value:
            return
        self._level = value
        if self._counters is not None:
            for unit in self._counters:
                unit._hil_edge(self, value)
        if self._handler is not None:
            edge = _RISING if value else _FALLING
            if self._trigger & edge:
                self._flags = edge
                if self._hard or len(_pending) < _DEPTH or _hil.room():  # (_hil.schedule, on the hot path)
                    _pending.append((self._handler, self))
                else:
                    _hil._lost(self._handler)

    def value(self, x=None):
        if x is None:
            if self._mode == _OUT:
                return self._out
            if not self._cfg:
                self.init()
            if _hil._dispatching:  # (a handler's first reads move no time: _hil._callback_read)
                _hil._callback_read()
                return self._level
            _hil.observe()
            level = self._level
            if level == self._pv:  # the same answer again: a count down to a look (_hilpoll)
                self._pn -= 1
                if not self._pn:
                    _polled(self)
            else:
                self._pv = level  # (one by one: a tuple of four would allocate, under heap_lock too)
                self._pn = _POLL_READS - 1
                self._pr = 0
                self._pt = _hil._now
            return level
        x = 1 if x else 0
        if x != self._out:
            self._out = x
            if _REG is not None and isinstance(self._id, int):
                _REG.pin_out(self._id, x)
            if self._mode == _OUT or self._mode == Pin.OPEN_DRAIN:  # (ALT: the latch only)
                _hil.send_out(self._handle, _F.OUT_LEVEL, x)

    __call__ = value

    def on(self):
        self.value(1)

    def off(self):
        self.value(0)

    def high(self):
        self.value(1)

    def low(self):
        self.value(0)

    def toggle(self):
        self.value(1 - self._out)

    def mode(self, mode=None):
        if mode is None:
            return self._mode
        self.init(mode)

    def pull(self, pull=-1):
        if pull == -1:
            return self._pull
        self.init(pull=pull)

    def irq(self, handler=_UNSET, trigger=IRQ_FALLING | IRQ_RISING, *more, hard=_UNSET, wake=_UNSET):
        # (no **kw: a call would allocate its dict, and pin.irq().flags() runs in hard handlers,
        # the heap locked; a keyword neither port takes is the VM's TypeError)
        plain = handler is _UNSET and not more and hard is _UNSET and wake is _UNSET
        if plain and trigger == self.IRQ_FALLING | self.IRQ_RISING:
            return self._irq_object()  # pin.irq(): the IRQ object as it is (its flags: the last edge)
        hard = _pin_irq_hard(more, hard, wake)
        handler = None if handler is _UNSET else handler
        if not self._cfg:
            self.init()
        # hard=True: ports/rp2/machine_pin.c (machine_pin_irq, mp_hal_pin_interrupt) runs the
        # handler in the interrupt (shared/runtime/mpirq.c, mp_irq_handler: the heap locked
        # around it, _hil.hard_handler); without it, scheduled
        self._hard = bool(hard) and handler is not None
        self._handler = _hil.hard_handler(handler) if self._hard else handler
        self._trigger = _wire_edges(trigger) if handler is not None else 0
        _hil.configure(self._handle, _F.CFG_IRQ, self._id, self._trigger)
        return self._irq_object()

    def _irq_object(self):
        # one a pin, made at its first irq() (ports/rp2/machine_pin.c machine_pin_irq keeps it
        # in MP_STATE_PORT; the ESP32's are static): a hard handler's pin.irq().flags() allocates nothing
        irq = self._irq
        if irq is None:
            irq = self._irq = _PinIRQ(self)
        return irq

    def __repr__(self):
        if _RP2 and isinstance(self._id, int):  # ports/rp2/machine_pin.c, machine_pin_print (its mode and alt)
            if self._mode == _ALT:
                mode = "ALT"
            else:
                mode = {Pin.IN: "IN", Pin.OUT: "OUT", Pin.OPEN_DRAIN: "OPEN_DRAIN"}[self._mode]
            pull = {None: "", Pin.PULL_UP: ", pull=PULL_UP", Pin.PULL_DOWN: ", pull=PULL_DOWN"}[self._pull]
            alt = ", alt=%d" % self._alt if self._mode == _ALT else ""
            return "Pin(GPIO%d, mode=%s%s%s)" % (self._id, mode, pull, alt)
        return "Pin(%r)" % (self._id,)


def _make(id, cls=Pin):
    pin = Pin._made.get(id)
    if pin is None:  # (made again, a driver's habit: the same pin, its level and IRQ)
        pin = Pin._made[id] = object.__new__(cls)
        _set_up(pin, id)
    return pin


def _set_up(pin, id):
    pin._id = id
    pin._mode = Pin.IN
    pin._pull = None
    pin._alt = _ALT_SIO
    pin._level = 0
    pin._out = 0
    pin._handler = None
    pin._irq = None  # its IRQ object (_irq_object)
    pin._hard = False  # its handler runs at the edge, even inside a C call (_hil.dispatch)
    pin._trigger = 0
    pin._flags = 0
    pin._counters = None  # Counter and Encoder units counting this pin's edges
    pin._cfg = False  # configured as its mode says (rp2's in_base=Pin(2) unwires it until it is read)
    pin._pv = None  # value() reads in a row with one answer (a poll that may never end, _hilpoll):
    pin._pn = pin._pr = pin._pt = 0  # the answer, reads left to the next look, reads before it, since
    pin._handle = _hil.register(pin)
    if _hil._Link.roomy is not None:  # (its 17 members fill their table: room, for its methods' lookups)
        _hil._Link.roomy(pin)


def _board_line(name):
    """A line of the board that is no GPIO (rp2's BOOTSEL, on QSPI_SS), read as an input
    on its pull-up: the rig file wires it by that name (docs/rig-file.md)."""
    pin = _make(name)
    if not pin._cfg:
        pin._pull = Pin.PULL_UP
        pin._init(Pin.IN, -1, None, _ALT_SIO)
    return pin


_hil._Link.pin = Pin  # (its changes are applied in C when the shim has _hilfast)
_OUT = Pin.OUT
_POLL_READS = _F.POLL_READS
if _hil._Link.fast is not None and _hil._Link.pin_value is not None:  # (a board's Pin.value is C too)
    Pin._value_py = Pin.value  # (what the C one hands on to: below its own cases, the same steps)
    if _hil._Link.c is not None:  # (this build's: an input's read in the main program in C too)
        _hil._Link.pin_setup(Pin._value_py, _OUT, _hil._Link.ctx[0], _POLL_READS)
    else:
        _hil._Link.pin_setup(Pin._value_py, _OUT, _hil._Link.ctx[0])
    Pin.value = _hil._Link.pin_value


def _polled(obj, addr=None, run=None, register=False):
    """A pin (or memory address) gave one answer to POLL_READS reads in a row: the rare
    path, which names a poll that never ends (host/shim/_hilpoll.py)."""
    depth = _hil.heap_release()  # (a poll under micropython.heap_lock() is named too)
    try:
        try:
            import _hilpoll
        except MemoryError:  # (a firmware that left no room: the reserve is the shim's for this)
            _hil.spend_reserve()
            import _hilpoll

        _hilpoll.look(obj, addr, run, register)
    finally:
        _hil.heap_restore(depth)


def _wire_edges(trigger):
    """The port's IRQ_RISING/IRQ_FALLING bits as the wire's (the ESP32 port's values)."""
    return (_RISING if trigger & Pin.IRQ_RISING else 0) | (_FALLING if trigger & Pin.IRQ_FALLING else 0)


def _port_edges(edges):
    return (Pin.IRQ_RISING if edges & _RISING else 0) | (Pin.IRQ_FALLING if edges & _FALLING else 0)


# What each port's Pin.irq takes after handler and trigger (its machine_pin_irq, parsed by
# py/argcheck.c mp_arg_parse_all: a keyword it does not name, or a positional too many, is a
# TypeError): ports/rp2/machine_pin.c, hard; ports/esp32/machine_pin.c, wake (an ESP32's pin
# handler is always scheduled: machine_pin_isr_handler, mp_sched_schedule). No family: both.
_PIN_IRQ_MORE = ("wake",) if _ESP32 else ("hard",) if _RP2 else ("hard", "wake")


def _pin_irq_hard(more, hard, wake):
    """Pin.irq's arguments past handler and trigger, checked as the port's are; its hard."""
    if len(more) > 1:
        raise TypeError("extra positional arguments given")
    kw = {}
    if hard is not _UNSET:
        kw["hard"] = hard
    if wake is not _UNSET:
        kw["wake"] = wake
    if more:
        if _PIN_IRQ_MORE[0] in kw:  # (given by position, its keyword is left over)
            raise TypeError("extra keyword arguments given")
        kw[_PIN_IRQ_MORE[0]] = more[0]
    for name in kw:
        if name not in _PIN_IRQ_MORE:
            raise TypeError("extra keyword arguments given")
    return bool(kw.get("hard", False))


class _PinIRQ:
    def __init__(self, pin):
        self._pin = pin

    def trigger(self):
        return _port_edges(self._pin._trigger)

    def flags(self):
        return _port_edges(self._pin._flags)


class PinBase:
    """A pin of Python: a subclass gives value([x]); Signal and time_pulse_us take it."""

    def value(self, x=None):
        raise NotImplementedError


class Signal:
    def __init__(self, pin, *args, invert=False, **kw):
        self._pin = pin if isinstance(pin, (Pin, PinBase)) else Pin(pin, *args, **kw)
        self._invert = 1 if invert else 0

    def value(self, x=None):
        if x is None:
            return self._pin.value() ^ self._invert
        self._pin.value((1 if x else 0) ^ self._invert)

    __call__ = value

    def on(self):
        self.value(1)

    def off(self):
        self.value(0)


class ADC:
    ATTN_0DB = 0
    ATTN_2_5DB = 1
    ATTN_6DB = 2
    ATTN_11DB = 3
    if _ESP32:  # ports/esp32/machine_adc.c: the ESP32's SAR ADC widths, 9 to 12 bits
        WIDTH_9BIT = 9
        WIDTH_10BIT = 10
        WIDTH_11BIT = 11
    WIDTH_12BIT = 12

    _made = {}  # pin id -> its ADC, one object per input as Pin's
    _bits = {1: 12, 2: 12}  # the ESP32's two ADC units' widths (a unit's read() width; 12 at boot)

    def __new__(cls, id=_UNSET, *args, **kw):
        if cls is not ADC:
            return object.__new__(cls) if id is _UNSET else _subclass(cls, id)
        if id is _UNSET:
            raise TypeError("function missing 1 required positional arguments")  # (py/argcheck.c)
        key = _adc_key(id)
        adc = ADC._made.get(key)
        if adc is None:
            adc = ADC._made[key] = object.__new__(cls)
            adc._id = key
            adc._value = adc._sample = adc._seen = 0
            adc._handle = _hil.register(adc)
        return adc

    def __init__(self, id, *, atten=None, **_kw):
        if type(self) is not ADC:  # (a subclass's: its id given to super().__init__)
            _subclass(type(self), id, self)
        _hil.configure(self._handle, _F.CFG_ADC, self._id, param=atten or 0, sync=True)

    def _hil_apply(self, kind, value, extra):
        self._value = value
        self._sample = extra

    def read_u16(self):
        _hil.observe()
        if self._sample != self._seen:  # first read of a new sample: report it
            self._seen = self._sample
            _hil.send(_F.SEEN, _F.pack_seen(_hil.now(), self._handle, self._sample))
        return self._value

    def _unit(self):
        """The ESP32's ADC unit of the pin: ADC1 on GPIO 32..39, ADC2 on the others
        (ports/esp32/adc.c, madc_obj)."""
        return 1 if isinstance(self._id, int) and 32 <= self._id <= 39 else 2

    def read(self):
        """The raw reading at the unit's width (ports/esp32/machine_adc.c,
        mp_machine_adc_read: madcblock_read_helper), 12 bits unless width() set it."""
        return self.read_u16() >> (16 - ADC._bits[self._unit()])

    def read_uv(self):
        return self.read_u16() * 3_300_000 // 65535

    def atten(self, atten):
        pass

    def width(self, bits):
        # ports/esp32/machine_adc.c, mp_machine_adc_width_set: the whole unit's width
        # (machine_adc_block.c), which read() then returns: ADC.WIDTH_10BIT reads 0..1023
        if not 9 <= bits <= 12:  # (1.25: adc.c, madcblock_bits_helper; 1.26+: machine_adc.c)
            raise ValueError("invalid bits" if _MPY < (1, 26) else "invalid bit-width")
        ADC._bits[self._unit()] = bits


# rp2's temperature sensor: ADC.CORE_TEMP, 4 (ports/rp2/machine_adc.c:
# MICROPY_PY_MACHINE_ADC_CLASS_CONSTANTS, ADC_TEMPERATURE_CHANNEL_NUM on an RP2040 and an
# RP2350A), read as the board's line CORE_TEMP.
if _RP2:
    ADC.CORE_TEMP = 4


def _adc_key(id):
    """The input an ADC(id) reads. rp2 (ports/rp2/machine_adc.c, mp_machine_adc_make_new):
    an int below NUM_ADC_CHANNELS is a channel, n < 4 the GPIO 26 + n (board files name the
    GPIO), 4 the temperature sensor (ADC_TEMPERATURE_CHANNEL_NUM, ADC.CORE_TEMP): the
    board's line CORE_TEMP, which a rig file may wire by that name (docs/rig-file.md)."""
    if isinstance(id, Pin):  # (its GPIO, never a channel number)
        return id._id
    if _RP2 and isinstance(id, int) and 0 <= id <= 4:
        return id + 26 if id < 4 else "CORE_TEMP"
    return id


def _adc_set_up(adc, key):
    adc._id = key
    adc._value = adc._sample = adc._seen = 0
    adc._handle = _hil.register(adc)


class PWM:
    _made = {}  # pin id -> its PWM: one channel per pin (a PWM made per call reuses it)

    def __new__(cls, dest, *args, **kw):
        pin = dest if isinstance(dest, Pin) else Pin(dest, Pin.OUT)
        pwm = PWM._made.get(pin._id)
        if pwm is None:
            pwm = PWM._made[pin._id] = object.__new__(cls)
            pwm._pin = pin
            pwm._handle = _hil.register(pwm)
            pwm._freq = 5000
            pwm._duty = 0
            pwm._invert = False
            pwm._active = True
        return pwm

    @classmethod
    def _from_registers(cls, gpio):
        """A pin given to the PWM function by mem32 (IO_BANK0's FUNCSEL): its PWM, no
        register written (they say its duty and freq). Its Pin is made as Pin(n) makes it
        on the rp2 port (machine_pin.c, mp_pin_make_new: no mode, nothing configured): a Pin
        made OUT would put FUNCSEL back to SIO (gpio_set_function), which the firmware set."""
        pwm = cls.__new__(cls, Pin(gpio))
        _hil.configure(pwm._handle, _F.CFG_PWM, pwm._pin._id, param=pwm._freq)
        return pwm

    def _drive(self, freq, duty, invert):
        """The slice's registers, written through mem32, as the plant sees them."""
        if freq != self._freq:
            self._freq = freq
            _hil.send_out(self._handle, _F.OUT_FREQ, freq)
        if duty != self._duty or invert != self._invert:
            self._duty, self._invert = duty, invert
            _hil.send_out(self._handle, _F.OUT_DUTY, 65535 - duty if invert else duty)

    def __init__(self, dest, freq=None, duty=None, *, duty_u16=None, duty_ns=None, invert=False, **_kw):
        self._active = True  # (a PWM made again after deinit: a channel of its own again)
        _hil.configure(self._handle, _F.CFG_PWM, self._pin._id, param=self._freq)
        self._invert = bool(invert)  # the line is high for the rest of each period
        if self._reg():
            _REG.set_funcsel(self._pin._id, _REG.FUNC_PWM)  # (machine_pwm.c: gpio_set_function)
        self._set_freq(self._freq if freq is None else freq, True)
        self.init(duty=duty, duty_u16=duty_u16, duty_ns=duty_ns)

    def init(self, *, freq=None, duty=None, duty_u16=None, duty_ns=None, **_kw):
        self._active = True  # (init after deinit: the port's init_helper takes a channel again)
        if freq is not None:
            self.freq(freq)
        if duty_u16 is not None:
            self.duty_u16(duty_u16)
        elif duty_ns is not None:
            self.duty_ns(duty_ns)
        elif duty is not None:
            self.duty(duty)

    def _is_active(self):
        """A deinit ESP32 PWM refuses its duty and frequency, read or set, until init() or
        PWM() makes it again (ports/esp32/machine_pwm.c, pwm_is_active: 1.25 "PWM inactive",
        from 1.26 "PWM is inactive"). The rp2 port has no such check."""
        if not self._active and _ESP32:
            raise RuntimeError("PWM inactive" if _MPY < (1, 26) else "PWM is inactive")

    def duty(self, value=None):
        """The ESP32 port's 10-bit duty, 0..1023, as ports/esp32/machine_pwm.c scales it:
        ``duty << 6`` to 16 bits (1023: 65472 in 1.25; from 1.26 the whole period, 65535 read
        back: check_duty_u10, get_duty_u16), and ``duty_u16 >> 6`` read back (get_duty_u10)."""
        self._is_active()
        if value is None:
            return self._duty >> 6
        value = int(value)
        if not 0 <= value <= 1023:
            raise ValueError("duty must be from 0 to 1023")  # (set_duty_u10, check_duty_u10)
        self.duty_u16(65535 if value == 1023 and _MPY >= (1, 26) else value << 6)

    def _reg(self):
        return _REG is not None and isinstance(self._pin._id, int) and 0 <= self._pin._id < _REG.N_GPIO

    def freq(self, value=None):
        self._is_active()
        if value is None:
            if self._reg():  # ports/rp2/machine_pwm.c, mp_machine_pwm_freq_get: from DIV and TOP
                return _REG.pwm_freq(_REG._slice_of(self._pin._id))
            return self._freq
        self._set_freq(value, False)

    def _set_freq(self, value, made):
        if not 0 < value <= 40_000_000:
            raise ValueError("freq %r out of range" % (value,))
        if self._reg():  # (mp_machine_pwm_freq_set: DIV and TOP, then the duty again)
            _REG.pwm_set_freq(self._pin._id, int(value))
            _REG.pwm_set_duty_u16(self._pin._id, self._duty, self._invert)
        # The same frequency again (a driver that sets it at each motor command, as Kitronik's
        # motorOn does) writes the same DIV and TOP: the waveform goes on, so the host is told
        # nothing, as for the same duty; a PWM being made tells its frequency as ever
        if made or int(value) != self._freq:
            self._freq = int(value)
            _hil.send_out(self._handle, _F.OUT_FREQ, self._freq)

    def duty_u16(self, value=None):
        self._is_active()
        if value is None:
            if self._reg():  # ports/rp2/machine_pwm.c, mp_machine_pwm_duty_get_u16: from CC and TOP
                return _REG.pwm_duty_u16(self._pin._id)
            return self._duty
        value = int(value)
        if _RP2 and value > 65535:  # ports/rp2/machine_pwm.c, mp_machine_pwm_duty_set_u16: "Limit duty_u16 to 65535"
            value = 65535
        elif not 0 <= value <= 65535:  # ports/esp32/machine_pwm.c, set_duty_u16 (a negative one: on rp2 too)
            raise ValueError("duty_u16 must be from 0 to 65535")
        if self._reg():
            _REG.pwm_set_duty_u16(self._pin._id, value, self._invert)
        if value != self._duty:
            self._duty = value
            _hil.send_out(self._handle, _F.OUT_DUTY, 65535 - value if self._invert else value)

    def duty_ns(self, value=None):
        self._is_active()
        period_ns = 1_000_000_000 // self._freq
        if value is None:
            return self._duty * period_ns // 65535
        self.duty_u16(min(65535, int(value) * 65535 // period_ns))

    def deinit(self):
        self._duty = 0
        self._active = False
        if self._reg():  # (machine_pwm.c, mp_machine_pwm_deinit: pwm_set_enabled(slice, false))
            _REG.pwm_stop(self._pin._id)
        _hil.send_out(self._handle, _F.OUT_DEINIT, 0)


def _mpy():
    import sys

    return tuple(sys.implementation.version[:2])  # (the interpreter's own: each version is built, docs/versions.md)


_MPY = _mpy()  # the MicroPython release the board runs, as (major, minor)
# Timer(hard=) as each port's machine_timer_init_helper takes it (an unknown keyword is
# py/argcheck.c's TypeError "extra keyword arguments given"): ports/rp2/machine_timer.c from
# 1.26 (ARG_hard, alarm_callback runs a hard callback in the alarm's IRQ); ports/esp32/
# machine_timer.c from 1.27, where hard=True is a ValueError (machine_timer_isr_handler only
# schedules). No family: as rp2.
_TIMER_HARD = (1, 27) if _ESP32 else (1, 26)


class Timer:
    """A virtual timer in virtual time. A callback is scheduled at its due time (soft, as
    py/scheduler.c queues it); with hard=True (rp2 1.26+) it runs at its due time even
    inside a C call or another callback, as a Pin IRQ's with hard=True does (_hil._is_hard:
    the Timer is the callback's argument, its _hard says so)."""

    ONE_SHOT = 0
    PERIODIC = 1

    _made = {}  # id -> its Timer: a hardware timer is one object (Timer(-1): a new soft one)

    def __new__(cls, id=-1, *args, **kw):
        timer = Timer._made.get(id) if id != -1 else None
        if timer is None:
            timer = object.__new__(cls)
            timer._id = id
            timer._callback = None
            timer._period_us = 0
            timer._due = _F.FOREVER_US
            timer._hard = False  # its callback runs at its due time, even inside a C call (_hil.dispatch)
            if id != -1:
                Timer._made[id] = timer
        return timer

    def __init__(self, id=-1, *args, **kw):
        if args or kw:
            self.init(*args, **kw)

    def init(self, *args, mode=PERIODIC, freq=-1, period=-1, tick_hz=1000, callback=None, **kw):
        if _ESP32:  # (ports/esp32/machine_timer.c, machine_timer_init_helper: disabled before its arguments are read)
            self.deinit()
        if args:  # (all keyword-only: py/argcheck.c, mp_arg_parse_all)
            raise TypeError("extra positional arguments given")
        hard = kw.pop("hard", False) if _MPY >= _TIMER_HARD else False
        if kw:
            raise TypeError("extra keyword arguments given")
        if hard and _ESP32:
            raise ValueError("hard Timers are not implemented")
        if freq > 0:
            period_us = 1_000_000 // freq
        elif period > 0:
            period_us = period * 1_000_000 // tick_hz
        else:
            raise ValueError("Timer needs a period or a freq")
        self._hard = bool(hard) and callback is not None
        self._callback = _hil.hard_handler(callback) if self._hard else callback  # (the heap locked around it)
        self._period_us = period_us if mode == self.PERIODIC else 0
        self._due = _hil.now() + period_us
        if callback is None:
            _hil.remove_timer(self)
        else:
            _hil.add_timer(self)

    def deinit(self):
        self._due = _F.FOREVER_US
        _hil.remove_timer(self)


class UART:
    """A UART in virtual time: bytes written take their time on the line at the baud
    rate (flush() waits for the last; IRQ_TXIDLE fires then); bytes received fire IRQ_RX,
    and IRQ_RXIDLE two character times after the last one. No breaks (no IRQ_BREAK)."""

    IRQ_RX = 1
    IRQ_RXIDLE = 2
    IRQ_TXIDLE = 4
    _made = {}  # UART id -> its UART: one peripheral per id (UART(1) is UART(1))

    def __new__(cls, id=_UNSET, *args, **kw):
        if cls is not UART:
            return object.__new__(cls) if id is _UNSET else _subclass(cls, id)
        if id is _UNSET:
            raise TypeError("function missing 1 required positional arguments")  # (py/argcheck.c)
        uart = UART._made.get(id)
        if uart is None:
            uart = UART._made[id] = object.__new__(cls)
            uart._set_up(id)
        return uart

    def _set_up(self, id):
        self._id = id
        self._rx = b""
        self._lines = 0  # complete lines the firmware has taken (the host's samples)
        self._handle = _hil.register(self)
        self._tx_end = 0
        self._handler = None
        self._trigger = 0
        self._flags = 0
        self._timer = None
        self._baud = 9600
        self._char_bits = 10
        self._timeout = 0
        self._timeout_char = 0

    def __init__(self, id, baudrate=None, *args, **kw):
        if type(self) is not UART:  # (a subclass's: its id given to super().__init__)
            _subclass(type(self), id, self)
        self.init(baudrate, *args, **kw)

    def init(self, baudrate=None, bits=8, parity=None, stop=1, *, timeout=None, timeout_char=None, **kw):
        """baudrate, bits, parity, stop; timeout: ms a read waits for its first byte (0: none);
        timeout_char: ms it waits for each next one (read and readinto: _port_read)."""
        if baudrate is not None:
            self._baud = int(baudrate)
        if timeout is not None:
            self._timeout = int(timeout)
        if timeout_char is not None:
            self._timeout_char = int(timeout_char)
        self._char_bits = 1 + bits + (0 if parity is None else 1) + stop
        _hil.configure(self._handle, _F.CFG_UART, "uart%s" % (self._id,), param=self._baud)

    def _wait_for(self, enough):
        """A read with a timeout waits in virtual time until ``enough()`` or the timeout."""
        if self._timeout <= 0 or enough():
            return
        _hil.blocking()
        deadline = _hil.now() + self._timeout * 1000
        if not _ESP32:  # ports/rp2/machine_uart.c, mp_machine_uart_read: mp_event_handle_nowait while it waits
            self._wait_rx(enough, deadline)
        else:  # ports/esp32/machine_uart.c, mp_machine_uart_read: ESP-IDF's uart_read_bytes blocks
            prev = _hil.c_begin(_hil.now())
            try:
                self._wait_rx(enough, deadline)
            finally:
                _hil.c_end(prev)

    def _wait_rx(self, enough, deadline):
        while not enough() and _hil.now() < deadline:
            _hil.run_until(deadline, [self._handle])

    def _until(self, enough, deadline):
        """Wait until enough() or the deadline (_wait_for's way: an ESP32's read is a C call)."""
        if enough() or _hil.now() >= deadline:
            return
        _hil.blocking()
        if not _ESP32:
            self._wait_rx(enough, deadline)
            return
        prev = _hil.c_begin(_hil.now())
        try:
            self._wait_rx(enough, deadline)
        finally:
            _hil.c_end(prev)

    def _port_read(self, want, taken):
        """One call of the port's read (mp_machine_uart_read) for the bytes past ``taken`` up to
        ``want``, returning when the port's does; False when it got none (MP_EAGAIN).
        ports/rp2/machine_uart.c: the first byte within timeout, each next within timeout_char
        of the one before (at least 13 bits' time, rounded up to the ms: machine_uart_init_helper).
        ports/esp32/machine_uart.c: ESP-IDF's uart_read_bytes, before 1.27 for all of them within
        timeout; from 1.27 for the first within timeout, then for the rest within timeout_char
        (0 by default: what has come; with it 0 the port sets the RX FIFO's threshold to one
        byte, so each byte is there as it comes, as here). Times to the us (the rp2 compares ms
        ticks, elapsed > timeout: up to 1 ms more; the ESP32 waits in FreeRTOS ticks)."""
        rx = self  # (the closures read rx._rx: it is rebound as bytes arrive)
        now = _hil.now()
        if _ESP32 and _MPY < (1, 27):
            self._until(lambda: len(rx._rx) >= want, now + self._timeout * 1000)
            return len(self._rx) > taken
        self._until(lambda: len(rx._rx) > taken, now + self._timeout * 1000)
        if len(self._rx) <= taken:
            return False
        if _ESP32:
            self._until(lambda: len(rx._rx) >= want, _hil.now() + self._timeout_char * 1000)
            return True
        gap_us = max(self._timeout_char, 13000 // self._baud + 1) * 1000
        while len(self._rx) < want:
            n = len(self._rx)
            self._until(lambda n=n: len(rx._rx) > n, _hil.now() + gap_us)
            if len(self._rx) == n:
                break
        return True

    def deinit(self):
        self.irq(None)

    def _line_us(self, nbytes):
        return nbytes * self._char_bits * 1_000_000 // self._baud

    def _hil_apply(self, kind, value, extra):
        self._rx += extra
        if self._trigger & self.IRQ_RX:
            self._fire(self.IRQ_RX)
        if self._trigger & self.IRQ_RXIDLE:
            self._at(_hil.now() + self._line_us(2), self.IRQ_RXIDLE)

    def _fire(self, flag):
        self._flags = flag
        _hil.schedule(self._handler, self)

    def _at(self, t_us, flag):
        """Fire ``flag``'s handler at t_us (one pending at a time: a later one replaces it)."""
        tm = self._timer
        if tm is None:
            tm = self._timer = Timer(-1)
        tm._callback = self._timer_fired
        tm._period_us = 0
        tm._due = t_us
        tm._flag = flag
        _hil.add_timer(tm)

    def _timer_fired(self, tm):
        self._flags = tm._flag
        if self._handler is not None:
            self._handler(self)

    def irq(self, handler=_UNSET, trigger=0, hard=False):
        if handler is _UNSET:
            return _UartIRQ(self)  # uart.irq(): the IRQ object, to read its flags
        self._handler = handler
        self._trigger = trigger if handler is not None else 0
        if self._timer is not None:
            _hil.remove_timer(self._timer)
        rx = _F.IRQ_RX if self._trigger & self.IRQ_RX else 0  # (RXIDLE, TXIDLE: timed here, in the shim)
        _hil.configure(self._handle, _F.CFG_IRQ, "uart%s" % (self._id,), rx)
        return _UartIRQ(self)

    def any(self):
        _hil.observe()
        return len(self._rx)

    def read(self, nbytes=-1):
        _hil.observe()
        if nbytes is None or nbytes < 0:
            self._wait_for(lambda: len(self._rx) >= 1)
        elif self._timeout > 0:  # (with none, what has come: the shim's, not the ports' timeout_char)
            self._read_calls(nbytes)
        if not self._rx:
            return None
        if nbytes is None or nbytes < 0:
            nbytes = len(self._rx)
        data, self._rx = self._rx[:nbytes], self._rx[nbytes:]
        n = data.count(b"\n")
        while n:  # the first read of a line's last byte: report it, as ADC samples are
            n -= 1
            self._lines += 1
            _hil.send(_F.SEEN, _F.pack_seen(_hil.now(), self._handle, self._lines))
        return data

    def _read_calls(self, want):
        """read(n) and readinto: the port's read called as py/stream.c calls it. Before 1.27
        they were mp_stream_read and mp_stream_readinto, whose loop (mp_stream_rw) calls the
        port again after a short read, until one gets nothing (its first byte's timeout
        again) or the buffer is full. From 1.27 (extmod/machine_uart.c: mp_stream_read1_obj,
        mp_stream_readinto1_obj, MP_STREAM_RW_ONCE) a read returns after the first call."""
        taken = 0
        while taken < want and self._port_read(want, taken) and _MPY < (1, 27):
            taken = len(self._rx)

    def readinto(self, buf, nbytes=-1):  # (py/stream.c, stream_readinto: at most the buffer's bytes)
        view = buf if type(buf) is bytearray else _buffers().wbuf(buf)
        size = len(view)
        data = self.read(size if nbytes < 0 or nbytes > size else nbytes)
        if not data:
            return None
        view[: len(data)] = data
        return len(data)

    def readline(self):
        _hil.observe()
        self._wait_for(lambda: b"\n" in self._rx)
        i = self._rx.find(b"\n")
        if i < 0:
            return self.read() if self._rx else None
        return self.read(i + 1)

    def write(self, buf):  # (py/stream.c, stream_write_method: any buffer, a str's bytes)
        kind = type(buf)
        data = buf if kind is bytes else bytes(buf if kind is bytearray else _buffers().rbuf(buf))
        _hil.pay_console()
        now = _hil.now()
        self._tx_end = max(now, self._tx_end) + self._line_us(len(data))
        _hil.send_output(_F.UART_TX, _F.pack_uart_tx(now, self._handle, data))
        if self._trigger & self.IRQ_TXIDLE:
            self._at(self._tx_end, self.IRQ_TXIDLE)
        return len(data)

    def _poll_ready(self, mask):
        return len(self._rx) > 0

    def flush(self):
        """Wait until the last byte written has left."""
        if self._tx_end > _hil.now():
            _hil.blocking()
            if not _ESP32:  # ports/rp2/machine_uart.c, mp_machine_uart_ioctl (MP_STREAM_FLUSH): mp_event_handle_nowait
                _hil.run_until(self._tx_end)
            else:  # ports/esp32/machine_uart.c, mp_machine_uart_ioctl: ESP-IDF's uart_wait_tx_done blocks
                prev = _hil.c_begin(_hil.now())
                try:
                    _hil.run_until(self._tx_end)
                finally:
                    _hil.c_end(prev)

    def txdone(self):
        _hil.observe()
        return _hil.now() >= self._tx_end


class _UartIRQ:
    def __init__(self, uart):
        self._uart = uart

    def flags(self):
        return self._uart._flags

    def trigger(self, value=None):
        return self._uart._trigger


def time_pulse_us(pin, pulse_level, timeout_us=1_000_000):
    """Length of a pulse in us; -2 if it never started, -1 if it never ended. A busy loop
    in C on a board (extmod/machine_pulse.c, machine_time_pulse_us): soft callbacks due
    meanwhile run when it returns (_hil.c_begin), hard IRQs' handlers at their edges. The
    level is any object, true or not (machine_time_pulse_us_: mp_obj_is_true(args[1])):
    time_pulse_us(echo, Pin.on) waits for a high, as on a board."""
    pulse_level = 1 if pulse_level else 0
    if not isinstance(pin, Pin):  # a PinBase: read it in a loop, as the C function does
        return _pulse_by_reads(pin, pulse_level, timeout_us)
    _hil.blocking()
    prev = _hil.c_begin(_hil.now())
    try:
        return _pulse(pin, pulse_level, timeout_us)
    finally:
        _hil.c_end(prev)


def _pulse(pin, pulse_level, timeout_us):
    watch = [pin._handle]
    if pin.value() != pulse_level:
        deadline = _hil.now() + timeout_us
        while pin._level != pulse_level:
            if not _hil.run_until(deadline, watch) and pin._level != pulse_level:
                return -2
    t0 = _hil.now()
    deadline = t0 + timeout_us
    while pin._level == pulse_level:
        if not _hil.run_until(deadline, watch) and pin._level == pulse_level:
            return -1
    return _hil.now() - t0


def _pulse_by_reads(pin, level, timeout_us):
    t0 = _hil.now()
    while pin.value() != level:
        _hil.observe()
        if _hil.now() - t0 >= timeout_us:
            return -2
    t0 = _hil.now()
    while pin.value() == level:
        _hil.observe()
        if _hil.now() - t0 >= timeout_us:
            return -1
    return _hil.now() - t0


def disable_irq():
    return _hil.disable_irq()


def enable_irq(state=0):
    _hil.enable_irq(state)


def idle():
    """Wait for the next interrupt or the next 1 ms system tick, as a board does."""
    _hil.blocking()
    t = _hil.now()
    _hil.run_until(t - t % 1000 + 1000)


def lightsleep(time_ms=None):
    """Sleep time_ms, or without it until a wake source: a pin's IRQ or a Timer (its
    handler has run when this returns)."""
    _hil.blocking()
    if time_ms is not None:
        _hil.run_until(_hil.now() + time_ms * 1000)
    else:
        _hil.run_until_woken()


DEEPSLEEP_WAKE = 1  # the reset's code to the host: a wake, not a crash (no reboot storm)


def deepsleep(time_ms=None):
    """The board sleeps (nothing runs: no IRQ handler, no Timer, no watchdog), then wakes
    through a reset (the firmware starts again): after time_ms, or without it when a pin
    with an IRQ changes (the wake pin; with none, never)."""
    _hil.blocking()
    _hil.disable_irq()
    if time_ms is not None:
        _hil.run_until(_hil.now() + time_ms * 1000)
    else:
        _hil.run_until_woken([p._handle for p in Pin._made.values() if p._trigger] or None)
    raise _hil.ResetRequest(DEEPSLEEP_WAKE)


class WDT:
    """The watchdog: not fed for ``timeout`` ms, it resets the board. One per board."""

    _one = None

    def __new__(cls, *args, **kw):
        if WDT._one is None:
            wdt = WDT._one = object.__new__(cls)
            wdt._timer = Timer(-1)
            wdt._timer._callback = wdt._expired
            wdt._timer._period_us = 0
            wdt._timer._hard = True  # (the hardware resets the board: never queued behind callbacks)
        return WDT._one

    def __init__(self, id=0, timeout=5000):
        self._timeout_us = int(timeout) * 1000
        self.feed()

    def feed(self):
        self._timer._due = _hil.now() + self._timeout_us
        _hil.add_timer(self._timer)

    def _expired(self, _tm):
        raise _hil.ResetRequest()


def unique_id():
    return _UNIQUE_ID


if _RP2:
    _freq_hz = 150_000_000 if _RP2350 else 125_000_000  # pico-sdk's SYS_CLK_HZ for the chip (MicroPython 1.25)
else:
    _freq_hz = (
        160_000_000  # a generic ESP32: ESP-IDF's CONFIG_ESP_DEFAULT_CPU_FREQ_MHZ (boards/sdkconfig.base keeps it)
    )


def _rp2_clock_ok(khz):
    """pico-sdk's check_sys_clock_khz: a 12 MHz crystal, REFDIV 1, FBDIV 16..320 with the VCO
    at 750..1600 MHz, POSTDIV1 1..7, POSTDIV2 1..POSTDIV1, and the frequency exact."""
    for fbdiv in range(320, 15, -1):
        vco_khz = fbdiv * 12_000
        if vco_khz < 750_000 or vco_khz > 1_600_000:
            continue
        for pd1 in range(7, 0, -1):
            for pd2 in range(pd1, 0, -1):
                if vco_khz % (pd1 * pd2) == 0 and vco_khz // (pd1 * pd2) == khz:
                    return True
    return False


def freq(*args):
    """The CPU's clock: what the port reports and accepts (extmod/modmachine.c, machine_freq;
    ports/rp2/modmachine.c and ports/esp32/modmachine.c, mp_machine_set_freq). The loop's time
    is virtual: a new clock changes what freq() says, not how long code takes."""
    global _freq_hz
    if len(args) > (2 if _RP2 else 1):
        raise TypeError("function expected at most %d arguments, got %d" % (2 if _RP2 else 1, len(args)))
    if not args:
        return _freq_hz
    hz = args[0]
    if not isinstance(hz, int):
        raise TypeError("can't convert %s to int" % type(hz).__name__)
    if _RP2:
        if not (hz >= 0 and _rp2_clock_ok(hz // 1000)):
            raise ValueError("cannot change frequency")  # set_sys_clock_khz(freq / 1000, false) failed
        _freq_hz = hz // 1000 * 1000  # (set before the peripheral clock is looked at, as the C does)
        if len(args) > 1:
            peri = args[1]
            if not isinstance(peri, int):
                raise TypeError("can't convert %s to int" % type(peri).__name__)
            if peri != 48_000_000 and peri != hz:
                raise ValueError("peripheral freq must be 48_000_000 or the same as the MCU freq")
        return None
    mhz = int(hz / 1_000_000)  # (mp_int_t / 1000000: C's division, toward zero)
    if mhz not in (20, 40, 80, 160, 240):
        raise ValueError("frequency must be 20MHz, 40MHz, 80Mhz, 160MHz or 240MHz")
    _freq_hz = mhz * 1_000_000
    return None


def reset():
    raise _hil.ResetRequest()


def soft_reset():
    raise _hil.ResetRequest()


def reset_cause():
    return _reset_cause


def _buffers():
    """_hilbuf, imported at the first buffer that is not bytes or a bytearray."""
    import _hilbuf

    return _hilbuf


class _Mem:
    """machine.mem8/16/32: a sparse memory of its own. What was written reads back, the
    rest reads 0; no peripheral registers lie behind it (docs/shim.md). On an RP2040,
    _hilreg.mems puts the registers over it."""

    _bytes = {}

    def __init__(self, bits):
        self._bits = bits
        self._size = bits // 8

    def _addr(self, addr):
        if not isinstance(addr, int):
            raise TypeError("memory address must be an integer")
        if addr % self._size:
            raise ValueError("memory address must be aligned to %d bytes" % self._size)
        return addr

    def __getitem__(self, addr):
        addr = self._addr(addr)
        _hil.observe()  # (a read of the board's memory: a busy wait on it moves time)
        get = _Mem._bytes.get
        value = get(addr, 0)
        for i in range(1, self._size):
            value |= get(addr + i, 0) << (8 * i)
        return self._seen(addr, value, False)

    _runs = {}  # address -> [answer, reads left to the next look, reads before it, since t_us]

    def _seen(self, addr, value, register):
        """A read's answer (register: a register of the board's model lies there), counted
        as Pin.value counts its own: the same answer POLL_READS times names the poll."""
        runs = _Mem._runs
        run = runs.get(addr)
        if run is not None and run[0] == value:
            run[1] -= 1
            if not run[1]:
                _polled(self, addr, run, register)
        else:
            if len(runs) >= 8:  # (a poll reads one or two addresses: the rest is a copy's)
                runs.clear()
            runs[addr] = [value, _POLL_READS - 1, 0, _hil._now]
        return value

    def __setitem__(self, addr, value):
        addr = self._addr(addr)
        for i in range(self._size):
            _Mem._bytes[addr + i] = (value >> (8 * i)) & 0xFF

    def __repr__(self):
        return "<%d-bit memory>" % self._bits


if _REG is not None:  # an RP2040: its PWM, IO_BANK0 and SIO registers (host/shim/_hilreg.py)
    mem8, mem16, mem32 = _REG.mems(_Mem)
else:
    mem8 = _Mem(8)
    mem16 = _Mem(16)
    mem32 = _Mem(32)


class RTC:
    """The board's real-time clock: set, it moves time.time() and localtime() too; it
    runs in virtual time."""

    def __init__(self, id=0, *args, **kw):
        if args or kw:
            self.init(*args, **kw)

    def init(self, datetime=None):
        if datetime is not None:
            self.datetime(datetime)

    def datetime(self, datetimetuple=None):
        import time

        if datetimetuple is None:
            us = time._rtc_us()
            y, mo, d, h, mi, sec, wd = time.gmtime(us // 1_000_000)[:7]
            return (y, mo, d, wd, h, mi, sec, us % 1_000_000)
        y, mo, d, _wd, h, mi, sec, sub = (tuple(datetimetuple) + (0,) * 8)[:8]
        time._set_rtc_us(time.mktime((y, mo, d, h, mi, sec, 0, 0)) * 1_000_000 + sub)

    def memory(self, data=None):
        if data is None:
            return getattr(RTC, "_memory", b"")
        RTC._memory = bytes(_buffers().rbuf(data))  # (ports/esp32/machine_rtc.c: a buffer)


def _attach(pin, unit):
    pin = _hil._handles[pin._handle]  # the pin's newest object gets its edges
    if not pin._cfg:
        pin.init()
    if pin._counters is None:
        pin._counters = []
    pin._counters.append(unit)
    return pin


def _detach(pin, unit):
    pin = _hil._handles[pin._handle]
    if pin._counters and unit in pin._counters:
        pin._counters.remove(unit)
        if not pin._counters:
            pin._counters = None


def _input(pin):
    return pin if isinstance(pin, Pin) else Pin(pin, Pin.IN)


class _Unit:
    """A hardware counter unit (the ESP32's PCNT): every edge of its pins counts, in the
    pin's own time, with no handler run and no time moved. One object per id."""

    _units = None

    def __new__(cls, id, *args, **kw):
        units = cls._units
        if units is None:
            units = cls._units = {}
        unit = units.get(id)
        if unit is None:  # one unit per id: Counter(0) again is the same, still counting
            unit = units[id] = object.__new__(cls)
            unit._id = id
            unit._pins = ()
            unit._count = 0
        return unit

    def __init__(self, id, *args, **kw):
        if args or kw:
            self.init(*args, **kw)

    def _attach(self, *pins):
        _hil.observe()  # edges from before init (a write just made) are not counted
        self.deinit()
        self._pins = tuple(_attach(_input(p), self) for p in pins)
        self._count = 0

    def deinit(self):
        for pin in self._pins:
            _detach(pin, self)
        self._pins = ()

    def value(self, value=None):
        _hil.observe()  # every edge up to now has arrived
        old = self._count
        if value is not None:
            self._count = int(value)
        return old


class Counter(_Unit):
    RISING = 1
    FALLING = 2
    UP = 1
    DOWN = -1

    def init(self, src, *, edge=RISING, direction=UP, filter_ns=0, **_kw):
        if edge not in (self.RISING, self.FALLING, self.RISING | self.FALLING):
            raise ValueError("edge must be Counter.RISING or Counter.FALLING")
        self._edge = edge
        self._dir_pin = direction if isinstance(direction, Pin) else None
        self._dir = -1 if direction == self.DOWN else 1
        self._attach(src)

    def _hil_edge(self, pin, level):
        if self._edge & (self.RISING if level else self.FALLING):
            if self._dir_pin is not None:  # a direction pin: low counts up, high down
                self._count += -1 if self._dir_pin._level else 1
            else:
                self._count += self._dir


class Encoder(_Unit):
    """Quadrature decoding. Forward is A leading B: (A, B) = 11, 01, 00, 10, 11. With
    4 phases every edge counts; 2: every edge of A; 1: the edges of A while B is high."""

    def init(self, phase_a, phase_b, *, phases=1, filter_ns=0, **_kw):
        if phases not in (1, 2, 4):
            raise ValueError("phases must be 1, 2 or 4")
        self._phases = phases
        self._attach(phase_a, phase_b)

    def _hil_edge(self, pin, level):
        a, b = self._pins
        if pin._handle == a._handle:
            b_level = _hil._handles[b._handle]._level
            step = 1 if (level == 0) == (b_level == 1) else -1
            if self._phases > 1 or b_level:
                self._count += step
        elif self._phases == 4:
            a_level = _hil._handles[a._handle]._level
            self._count += 1 if (level == 1) == (a_level == 1) else -1


_BUSES = ("I2C", "SoftI2C", "SPI", "SoftSPI", "bitstream", "I2CTarget")  # in _hilbus, imported at their first use only
_NOT_IN_THE_LOOP = ("I2S", "CAN", "SDCard", "TouchPad", "DAC")
_NOT_IN_THE_LOOP += ("ADCBlock", "USBDevice", "dht_readinto", "wake_reason")


def __getattr__(name):
    # a board's class the loop has not got: an ImportError that says so (also for
    # `from machine import I2S`, which a bare "can't import name" would leave unexplained)
    if name in _BUSES:
        import _hilbus

        cls = getattr(_hilbus, name)
        globals()[name] = cls  # (found directly from now on)
        return cls
    if name in _NOT_IN_THE_LOOP:
        raise ImportError(
            "machine.%s is not in the loop; it has Pin, Signal, PinBase, ADC, PWM, Timer, UART, I2C, SoftI2C, "
            "SPI, SoftSPI, I2CTarget, Counter, Encoder, RTC, WDT, time_pulse_us, bitstream, mem8/16/32 and the "
            "board functions (docs/shim.md)" % name
        )
    raise AttributeError("'module' object has no attribute '%s'" % name)

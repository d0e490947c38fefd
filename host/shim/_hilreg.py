# The RP2040's registers behind machine.mem32/mem16/mem8 (docs/shim.md, "Registers"): the
# PWM block, IO_BANK0's GPIO control registers and SIO's GPIO registers, as the RP2040
# datasheet lays them out (2.3.1.7 SIO's registers, 2.19.6.1 IO_BANK0's, 4.5.4 PWM's;
# the same offsets and fields as the SVD's pico-sdk hardware/regs/pwm.h, io_bank0.h and
# sio.h, and ports/rp2/machine_pwm.c's use of pwm_hw). What they do reaches the plant as the
# machine.PWM and machine.Pin the port would drive: a duty written to a slice's CC moves
# a motor as PWM.duty_u16 does. Any other address is memory of its own, named once on the
# console as a note of the harness's.
import sys

import _hil

PWM_BASE = 0x40050000  # 8 slices, 0x14 apart: CSR, DIV, CTR, CC, TOP; then EN at +0xa0
PWM_EN = PWM_BASE + 0xA0
IO_BANK0 = 0x40014000  # GPIOn_STATUS at 8n, GPIOn_CTRL at 8n + 4
SIO = 0xD0000000
N_GPIO = 30
SYS_HZ = 125_000_000  # clk_sys, as machine.freq() starts (machine_pwm.c reads clock_get_hz)
TOP_MAX = 65534  # ports/rp2/machine_pwm.c
FUNC_PWM = 4
FUNC_SIO = 5
FUNC_NULL = 0x1F  # GPIOn_CTRL's FUNCSEL at reset

_CSR, _DIV, _CTR, _CC, _TOP = 0, 4, 8, 12, 16
_regs = {}  # word address -> 32-bit value: the PWM slices' registers and the GPIOs' CTRL
_mem = {}  # any other byte address -> its byte (memory of its own)
_noted = set()
_unmade = set()  # GPIOs whose control mem32 wrote before any Pin of theirs was made
_sio = {"out": 0, "oe": 0}


def _machine():
    return sys.modules["machine"]


UNMODELLED = (
    "no register of the simulated RP2040 there (PWM, IO_BANK0 GPIO control and SIO GPIO are); "
    "it is plain memory: what was written reads back, the rest 0"
)


def _note(addr, what):
    if addr in _noted:
        return
    _noted.add(addr)
    sys.stdout.write("[mpy-fil: note: %s 0x%08x: %s]\n" % (what, addr, UNMODELLED))
    _hil.said()


def register_text(addr):
    """What a register read gives and what changes it (a poll of it named: _hilpoll)."""
    word = addr & ~3 & ~0x3000 if 0x40000000 <= addr < 0x40070000 else addr & ~3
    if PWM_BASE <= word < PWM_BASE + 0xA0:
        sl, off = divmod(word - PWM_BASE, 0x14)
        name = ("CSR", "DIV", "CTR", "CC", "TOP")[off // 4]
        more = " (the counter is not run: CTR reads what was written)" if off == _CTR else ""
        return "the simulated RP2040's PWM slice %d %s: only a write changes it%s" % (sl, name, more)
    if word == PWM_EN:
        return "the simulated RP2040's PWM EN: only a write (or PWM()) changes it"
    if IO_BANK0 <= word < IO_BANK0 + 8 * N_GPIO:
        gpio = (word - IO_BANK0) // 8
        if word & 4:
            return "the simulated RP2040's GPIO%d_CTRL: only a write (or Pin.init) changes it" % gpio
        return "the simulated RP2040's GPIO%d_STATUS: its INFROMPAD is the pad's level, which the plant drives" % gpio
    if word == SIO + 0x04:
        return "the simulated RP2040's SIO GPIO_IN: the pads' levels, which the plant drives through the rig's wiring"
    return "the simulated RP2040's SIO GPIO_OUT/GPIO_OE: only a write (or Pin) changes it"


_applying = False  # (the pins following SIO's registers: their Pin.init leaves OE and OUT be)


def pin_state(gpio, alt_mode, alt, oe, out):
    """Pin.init chose a pin's function and direction (as the port's gpio_set_function,
    gpio_set_dir and gpio_put): IO_BANK0's FUNCSEL, SIO's OE and OUT say so."""
    set_funcsel(gpio, alt if alt_mode else FUNC_SIO)
    if not _applying:
        bit = 1 << gpio
        _sio["oe"] = (_sio["oe"] | bit) if oe else (_sio["oe"] & ~bit)
        pin_out(gpio, out)


def pin_out(gpio, out):
    if not _applying and 0 <= gpio < N_GPIO:
        bit = 1 << gpio
        _sio["out"] = (_sio["out"] | bit) if out else (_sio["out"] & ~bit)


def pwm_stop(gpio):
    a = PWM_BASE + 0x14 * _slice_of(gpio) + _CSR
    _regs[a] = slice_reg(_slice_of(gpio), _CSR) & ~1


def _slice_of(gpio):
    return (gpio >> 1) & 7


# each slice's GPIOs in order (2n, 2n + 1, 2n + 16, 2n + 17 below N_GPIO: _slice_of's inverse)
_SLICE_GPIOS = tuple(tuple(g for g in range(N_GPIO) if _slice_of(g) == sl) for sl in range(8))


def slice_reg(sl, off):
    return _regs.get(PWM_BASE + 0x14 * sl + off, 0x10 if off == _DIV else (0xFFFF if off == _TOP else 0))


def funcsel(gpio):
    return _regs.get(IO_BANK0 + 8 * gpio + 4, FUNC_NULL) & 0x1F


def set_funcsel(gpio, func):
    """Pin.init and PWM() choose a pin's function as the port's gpio_set_function does."""
    a = IO_BANK0 + 8 * gpio + 4
    _regs[a] = (_regs.get(a, FUNC_NULL) & ~0x1F) | func


# ports/rp2/machine_pwm.c: get_slice_hz, mp_machine_pwm_freq_get/set, duty_get/set_u16
def _slice_hz(offset, div16):
    return (16 * SYS_HZ + offset) // div16


def pwm_freq(sl):
    div16 = slice_reg(sl, _DIV) & 0xFFF or 0x1000  # (a DIV of 0 divides by 256)
    top = slice_reg(sl, _TOP) & 0xFFFF
    d = div16 * (top + 1)
    return _slice_hz(d // 2, d)


def pwm_duty_u16(gpio):
    sl = _slice_of(gpio)
    top = slice_reg(sl, _TOP) & 0xFFFF
    cc = (slice_reg(sl, _CC) >> (16 if gpio & 1 else 0)) & 0xFFFF
    return min(65535, (cc * 65535 + (top + 1) // 2) // (top + 1))


def pwm_set_freq(gpio, freq):
    sl = _slice_of(gpio)
    if (SYS_HZ + freq // 2) // freq < TOP_MAX:
        div16 = 16
        top = (SYS_HZ + freq // 2) // freq - 1
    else:
        div16 = _slice_hz(TOP_MAX * freq - 1, TOP_MAX * freq)
        top = _slice_hz(div16 * freq // 2, div16 * freq) - 1
    if div16 < 16 or div16 >= 256 * 16:
        raise ValueError("freq too small" if div16 >= 256 * 16 else "freq too large")
    _regs[PWM_BASE + 0x14 * sl + _DIV] = div16
    _regs[PWM_BASE + 0x14 * sl + _TOP] = top


def pwm_set_duty_u16(gpio, duty, invert):
    sl = _slice_of(gpio)
    top = slice_reg(sl, _TOP) & 0xFFFF
    cc = (duty * (top + 1) + 65535 // 2) // 65535
    a = PWM_BASE + 0x14 * sl + _CC
    shift = 16 if gpio & 1 else 0
    _regs[a] = (slice_reg(sl, _CC) & ~(0xFFFF << shift)) | (cc << shift)
    inv = 8 if gpio & 1 else 4  # CSR's B_INV, A_INV
    csr = slice_reg(sl, _CSR) | 1  # pwm_set_enabled
    _regs[PWM_BASE + 0x14 * sl + _CSR] = (csr | inv) if invert else (csr & ~inv)


def _pwm_apply(sl):
    """A slice's registers changed: each pin of it whose function is PWM drives what they say."""
    m = _machine()
    csr = slice_reg(sl, _CSR)
    for gpio in _SLICE_GPIOS[sl]:
        if funcsel(gpio) != FUNC_PWM:
            continue
        pwm = m.PWM._made.get(gpio)
        if pwm is None:
            pwm = m.PWM._from_registers(gpio)
        duty = pwm_duty_u16(gpio) if csr & 1 else 0  # (a slice stopped: the line low)
        invert = bool(csr & (8 if gpio & 1 else 4))
        pwm._drive(pwm_freq(sl), duty, invert)


def _pins_apply(changed):
    """SIO's OUT/OE or a GPIO's overrides changed: the pins under SIO drive what they say."""
    global _applying
    m = _machine()
    for gpio in range(N_GPIO):
        if not changed >> gpio & 1:
            continue
        ctrl = _regs.get(IO_BANK0 + 8 * gpio + 4, FUNC_NULL)
        if ctrl & 0x1F != FUNC_SIO:
            continue
        oe = _sio["oe"] >> gpio & 1
        oeover = ctrl >> 12 & 3
        oe = (oe, 1 - oe, 0, 1)[oeover]
        out = _sio["out"] >> gpio & 1
        out = (out, 1 - out, 0, 1)[ctrl >> 8 & 3]
        _applying = True
        try:
            m.Pin(gpio)._from_registers(oe, out)
        finally:
            _applying = False


def gpio_in(only=None):
    """The pads' levels (the pins made, and those whose control mem32 wrote), after INOVER:
    the register read's (its read of the clock made: machine's mem reads observe), not
    Pin.value()'s each (whose polls are counted as the firmware's own)."""
    m = _machine()
    made = m.Pin._made
    out = m.Pin.OUT
    word = 0
    if only is None:  # (the pins there are, not all 30 looked up: a busy wait reads this often)
        while _unmade:
            m.Pin(_unmade.pop())  # (a pin whose control mem32 wrote: made, its pad read from now on)
        gpios = tuple(made)  # (a copy: a pin's first init may sync, and a handler make a pin)
    else:
        gpios = (only,)
    for gpio in gpios:
        if only is None and not (isinstance(gpio, int) and 0 <= gpio < N_GPIO):
            continue
        pin = made.get(gpio)
        if pin is None:
            pin = m.Pin(gpio)
        if not pin._cfg:
            pin.init()
        level = pin._out if pin._mode == out else pin._level  # (as Pin.value() reads it)
        inover = _regs.get(IO_BANK0 + 8 * gpio + 4, FUNC_NULL) >> 16 & 3
        level = (level, 1 - level, 0, 1)[inover]
        word |= (level & 1) << gpio
    return word


def _read32(addr):
    if PWM_BASE <= addr < PWM_BASE + 0xA0:
        return slice_reg((addr - PWM_BASE) // 0x14, (addr - PWM_BASE) % 0x14)
    if addr == PWM_EN:
        return sum((slice_reg(s, _CSR) & 1) << s for s in range(8))
    if IO_BANK0 <= addr < IO_BANK0 + 8 * N_GPIO:
        if addr & 4:
            return _regs.get(addr, FUNC_NULL)
        gpio = (addr - IO_BANK0) // 8  # GPIOn_STATUS: INFROMPAD (bit 17), OEFROMPERI ...
        return (gpio_in(gpio) >> gpio & 1) << 17
    if addr == SIO + 0x04:
        return gpio_in()
    if addr in (SIO + 0x10, SIO + 0x14, SIO + 0x18, SIO + 0x1C):
        return _sio["out"]
    if addr in (SIO + 0x20, SIO + 0x24, SIO + 0x28, SIO + 0x2C):
        return _sio["oe"]
    return None


def _write32(addr, value):
    """A word written at a register's address; False: no register there."""
    mask = (1 << N_GPIO) - 1
    if PWM_BASE <= addr < PWM_BASE + 0xA0:
        sl, off = divmod(addr - PWM_BASE, 0x14)
        _regs[addr] = value & (0xFFF if off == _DIV else 0xFFFF if off == _TOP else 0xFF if off == _CSR else 0xFFFFFFFF)
        _pwm_apply(sl)
        return True
    if addr == PWM_EN:
        for s in range(8):
            a = PWM_BASE + 0x14 * s + _CSR
            csr = slice_reg(s, _CSR)
            if (csr & 1) != (value >> s & 1):
                _regs[a] = (csr & ~1) | (value >> s & 1)
                _pwm_apply(s)
        return True
    if IO_BANK0 <= addr < IO_BANK0 + 8 * N_GPIO:
        if not addr & 4:
            return True  # GPIOn_STATUS: read-only
        gpio = (addr - IO_BANK0) // 8
        if gpio not in _machine().Pin._made:
            _unmade.add(gpio)
        old = _regs.get(addr, FUNC_NULL)
        _regs[addr] = value & 0x3033F31F
        if (old ^ value) & 0x1F:
            m = _machine()
            func = value & 0x1F
            if func == FUNC_SIO:
                m.Pin(gpio)._alt = FUNC_SIO
            elif func == FUNC_PWM:
                _pwm_apply(_slice_of(gpio))
            elif func != FUNC_NULL:  # (SPI, UART, I2C, PIO ...: the pin is that block's, as Pin.ALT says it)
                m.Pin(gpio)._give(func)
        _pins_apply(1 << gpio)
        return True
    sio = {0x10: ("out", None), 0x14: ("out", "set"), 0x18: ("out", "clr"), 0x1C: ("out", "xor")}
    sio.update({0x20: ("oe", None), 0x24: ("oe", "set"), 0x28: ("oe", "clr"), 0x2C: ("oe", "xor")})
    if SIO <= addr < SIO + 0x30 and (addr - SIO) in sio:
        reg, op = sio[addr - SIO]
        old = _sio[reg]
        new = {None: value, "set": old | value, "clr": old & ~value, "xor": old ^ value}[op] & mask
        _sio[reg] = new
        _pins_apply(old ^ new)
        return True
    if addr == SIO + 0x04:
        return True  # GPIO_IN: read-only
    return False


def _atomic(addr):
    """An APB register's aliases (datasheet 2.1.2): +0x1000 XOR, +0x2000 SET, +0x3000 CLR."""
    if 0x40000000 <= addr < 0x40070000 and addr & 0x3000:
        return addr & ~0x3000, addr >> 12 & 3
    return addr, 0


def mems(base):
    """machine.mem8, mem16 and mem32 on an RP2040: the registers above, memory elsewhere.
    ``base`` is machine's memory type (its address checks and repr: machine imports this
    module before it defines it)."""

    class Mem(base):
        def __getitem__(self, addr):
            addr = self._addr(addr)
            _hil.observe()  # (a register read: a busy wait on one moves time)
            word, op = _atomic(addr & ~3)
            value = _read32(word)
            if value is None:
                _note(addr, "read of")
                get = _mem.get
                value = get(addr, 0)
                for i in range(1, self._size):
                    value |= get(addr + i, 0) << (8 * i)
                return self._seen(addr, value, False)
            return self._seen(addr, (value >> (8 * (addr & 3))) & ((1 << self._bits) - 1), True)

        def __setitem__(self, addr, value):
            addr = self._addr(addr)
            word, op = _atomic(addr & ~3)
            old = _read32(word)
            if old is not None:
                if self._size < 4:
                    value &= (1 << self._bits) - 1
                    if word < SIO:  # (the APB bus copies a narrow write across the word: 2.1.4)
                        value = value * (0x01010101 if self._size == 1 else 0x00010001)
                    else:  # (SIO: the bytes written, the rest kept)
                        shift = 8 * (addr & 3)
                        value = (old & ~(((1 << self._bits) - 1) << shift)) | (value << shift)
                value &= 0xFFFFFFFF
                if op:  # (an alias: XOR, SET, CLR)
                    value = (value, old ^ value, old | value, old & ~value)[op]
                if _write32(word, value):
                    return
            _note(addr, "write to")
            for i in range(self._size):
                _mem[addr + i] = (value >> (8 * i)) & 0xFF

    return Mem(8), Mem(16), Mem(32)

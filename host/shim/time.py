# time module for firmware running in the loop: ticks and sleeps in virtual time.
# Ticks have a 32-bit MCU's period (2**30) and start close to the wrap, so code that
# subtracts ticks instead of using ticks_diff fails here as it would on a board.
import _hil

_MASK = _hil.TICKS_MASK
_HALF = _hil.TICKS_PERIOD >> 1


def _wrap_ms():
    """The ticks wrap this long into the run: WELCOME's ticks_wrap_ms (the rig file's
    [interpreter] ticks_wrap_s); imported with no host (the shim's pieces on their own,
    host/bench/shim_pieces.py) they start at 0."""
    settings = _hil._Link.settings
    return settings["ticks_wrap_ms"] if settings else 0


_START_US = (_hil.TICKS_PERIOD - _wrap_ms() * 1000) & _MASK
_START_MS = (_hil.TICKS_PERIOD - _wrap_ms()) & _MASK
_EPOCH_S = 1_735_689_600  # 2025-01-01 00:00:00 UTC: the board's RTC at power-on


def ticks_us():
    _hil.observe()
    return (_START_US + _hil.now()) & _MASK


def ticks_ms():
    _hil.observe()
    return (_START_MS + _hil.now() // 1000) & _MASK


ticks_cpu = ticks_us


def ticks_add(ticks, delta):
    if not -_HALF < delta < _HALF:  # as a board's: ticks_diff could not give it back
        raise OverflowError("ticks interval overflow")
    return (ticks + delta) & _MASK


def ticks_diff(ticks1, ticks2):
    return ((ticks1 - ticks2 + _HALF) & _MASK) - _HALF


def _platform():
    import sys

    return getattr(sys.modules.get("sys", sys), "platform", "")


# (imported once the host has named the board's family; with none named, sleeps run
# callbacks all along, as before the ports' rules below were followed)
_RP2 = _platform() == "rp2"
_ESP32 = _platform() == "esp32"


def sleep_us(us):
    """extmod/modtime.c, time_sleep_us: the port's mp_hal_delay_us, a busy loop that runs
    scheduled callbacks only for part of the wait. ports/rp2/mphalport.c: past 1000 us its
    whole milliseconds go to mp_hal_delay_ms (which handles events), the rest is a tight
    loop; ports/esp32/mphalport.c: mp_handle_pending while more than its 150 us (and 5 us
    call overhead) are left. Soft callbacks due in the rest run when it returns."""
    if not isinstance(us, int):
        raise TypeError("can't convert %s to int" % type(us).__name__)
    if us <= 0:  # returns at once, as on a board, where even that takes a little time
        _hil.observe()
        return
    _hil.blocking()
    t = _hil.now()
    if _RP2:
        _waiting(_hil.c_begin(t + (us // 1000) * 1000 if us > 1000 else t), t + us)  # (_wait, inline)
    elif _ESP32:
        _waiting(_hil.c_begin(t + us - 155 if us > 155 else t), t + us)
    else:
        _hil.run_until(t + us)


def _wait(busy_from, t_end):
    """Wait to t_end, in a C busy loop from busy_from on (_hil.c_begin). (No allocation:
    sleeps work under micropython.heap_lock().)"""
    _waiting(_hil.c_begin(busy_from), t_end)


def _waiting(prev, t_end):
    # (apart from _wait: a frame with few locals around its try fits the C stack's,
    # py/objfun.c VM_MAX_STATE_ON_STACK, where _wait's took a heap block each sleep)
    try:
        _hil.run_until(t_end)
    finally:
        _hil.c_end(prev)


def _sleep_us(us):
    """mp_hal_delay_ms: scheduled callbacks run at their times (ports/rp2/mphalport.c:
    mp_event_wait_ms), on an ESP32 but in the last 155 us (ports/esp32/mphalport.c:
    mp_handle_pending each tick, the rest through mp_hal_delay_us)."""
    if us <= 0:
        _hil.observe()
        return
    _hil.blocking()
    t = _hil.now()
    if _ESP32:
        _wait(t + us - 155 if us > 155 else t, t + us)
    else:
        _hil.run_until(t + us)


def sleep_ms(ms):
    if not isinstance(ms, int):
        raise TypeError("can't convert %s to int" % type(ms).__name__)
    _sleep_us(ms * 1000)


def sleep(seconds):
    _sleep_us(int(seconds * 1_000_000))


_rtc_offset_us = 0  # machine.RTC().datetime(...) moves the wall clock


def _rtc_us():
    return _EPOCH_S * 1_000_000 + _rtc_offset_us + _hil.now()


def _set_rtc_us(us):
    global _rtc_offset_us
    _rtc_offset_us = us - _EPOCH_S * 1_000_000 - _hil.now()


def time():
    return _rtc_us() // 1_000_000


def time_ns():
    return _rtc_us() * 1000


def gmtime(secs=None):
    return _hil._rtime.gmtime(time() if secs is None else secs)


localtime = gmtime


def mktime(t):
    return _hil._rtime.mktime(t)

# The board's _thread (ports/rp2/mpthreadport.c: the RP2040's and RP2350's second core;
# ports/esp32/mpthreadport.c: FreeRTOS tasks), on the one virtual clock (docs/shim.md,
# "Threads"). The firmware's threads are the unix port's, but only one runs at a time: it
# holds the baton, and gives it away
# - when it waits in virtual time (a sleep, a poll, a read past the horizon: _hil.run_until
#   calls wait() here): it blocks until its wake instant, and the others run meanwhile, or
#   the clock moves to the first of their wakes;
# - when another thread's wake has come, or when it has run SLICE_US of virtual time while
#   another could run (at its clock and pin reads, _hil.observe, and at the looks of the
#   branch hook, _hil._branches: tick() here), so two busy loops take turns;
# - when it blocks on a lock another thread holds, and when it ends.
# Which thread runs next, and when, depends only on virtual time and the order of events:
# the same seed gives the same trace. Callbacks (IRQ handlers, Timers) run in whichever
# thread moves the clock, at their instants, as before.
import sys

import _hil

# (the unix port's _thread itself is not kept here: a firmware reaches this module as its
# _thread, and the host's module stays out of its reach, hil_tests/test_board_flash.py; its
# two functions are kept by the confinement before it goes, _hilconfine)
_new_lock, _start_real = _hil._Link.thread_api
get_ident = _hil._Link.thread

SLICE_US = 1_000  # a busy thread's turn, in virtual time, while another could run

_threads = []  # every thread of the firmware's, the main program first
_running = None  # the one holding the baton


class _Thread:
    __slots__ = ("gate", "wake", "done", "since")

    def __init__(self):
        self.gate = _new_lock()  # held while the thread waits for the baton
        self.gate.acquire()
        self.wake = None  # None: ready to run; else the virtual instant it waits for
        self.done = False
        self.since = 0  # when it last got the baton


def _start():
    """The first thread started: the main program becomes one of the firmware's threads."""
    global _running
    main = _Thread()
    main.since = _hil._now
    _threads.append(main)
    _running = main
    _hil._Link.threads = sys.modules[__name__]
    import _hilsys

    _hilsys.before_print = look


def look():
    """Before the firmware prints: its compute so far paid (MCU time), then tick(). On a board
    the other core ran meanwhile: a thread whose wake came during that compute prints first,
    and what it set is there when the printing thread goes on (Pololu's line_follower.py
    prints the list its second thread fills, then reads it)."""
    if _hil._dispatching:
        return
    _hil.pay_cpu()
    tick()


_ending = False  # the firmware has ended (end()): a thread given the baton back unwinds


def _hand(to):
    """The baton to `to`; the caller blocks until it comes back (unless it has ended)."""
    global _running
    me = _running
    _running = to
    to.since = _hil._now
    to.gate.release()
    if not me.done:
        me.gate.acquire()
        if _ending:
            raise SystemExit


def end():
    """The firmware ended (its main program returned, raised or reset): the threads still
    waiting for the baton unwind and end, as the process ends (the unix port would cancel
    them, pthread_cancel, which this build's libc cannot do quietly). Each is woken in turn
    and waited for (a short while of the wall's time)."""
    global _ending
    _ending = True
    for t in _threads[1:]:
        if not t.done:
            t.gate.release()
            for _ in range(200):
                if t.done:
                    break
                _hil._rtime.sleep_ms(1)


def _ready(me):
    """The next thread after `me` that may run now: ready, or its wake come."""
    n = len(_threads)
    i = _threads.index(me)
    for k in range(1, n):
        t = _threads[(i + k) % n]
        if not t.done and (t.wake is None or t.wake <= _hil._now):
            return t
    return None


def _first_wake(me):
    """The waiting thread (not `me`) whose wake comes first, or None."""
    best = None
    for t in _threads:
        if t is not me and not t.done and t.wake is not None and (best is None or t.wake < best.wake):
            best = t
    return best


def due():
    """When the running thread is to let another run (tick): the first wake of those that
    wait, or the end of its turn while another is ready (FOREVER_US: never). MCU time's
    looks (_hil._branches) charge a compute that reaches it, so a thread that only computes
    takes its turn too."""
    me = _running
    later = _first_wake(me)
    t = later.wake if later is not None else _hil.FOREVER_US
    if _ready(me) is not None and me.since + SLICE_US < t:
        t = me.since + SLICE_US
    return t


def wait(t_target, watch):
    """_hil.run_until for the running thread: the others run while it waits."""
    me = _running
    while True:
        other = _ready(me)
        if other is not None:
            me.wake = t_target
            _hand(other)
            me.wake = None
            if _hil._now >= t_target:
                return False
            continue
        later = _first_wake(me)
        if later is None or later.wake >= t_target:
            return _hil._wait(t_target, watch)
        hit = _hil._wait(later.wake, watch)
        if hit:
            return True


def tick():
    """At a clock or pin read, or a look of the branch hook: the baton goes on when another
    thread's wake has come, or when this one has had its turn and another is ready."""
    me = _running
    if me is None or _hil._dispatching:
        return
    other = _ready(me)
    if other is None:
        return
    if other.wake is not None or _hil._now - me.since >= SLICE_US:
        _hand(other)


def block():
    """The running thread cannot go on (a lock another holds): the others run, or the clock
    moves to the first of their wakes; with none that could ever run, it waits for ever."""
    me = _running
    other = _ready(me)
    if other is not None:
        _hand(other)
        return
    later = _first_wake(me)
    _hil._wait(later.wake if later is not None else _hil.FOREVER_US, None)


def _body(me, function, args, kwargs):
    me.gate.acquire()  # (the baton, from _hand)
    try:
        if _ending:
            raise SystemExit
        function(*args, **kwargs)
    except SystemExit:
        pass
    except Exception as e:
        print("Unhandled exception in thread started by %r" % (function,))  # (py/modthread.c, on the console)
        sys.modules.get("sys", sys).print_exception(e)  # (the board's: the firmware's frames only)
    finally:
        me.done = True
        if not _ending:  # (the firmware ended: the thread ends with it, handing nothing on)
            _pass_on(me)


def _pass_on(me):
    """A thread ended: the baton to the next that may run, or the first to wake."""
    global _running
    other = _ready(me) or _first_wake(me)
    if other is not None:
        _hand(other)
    else:  # (nothing else left: the main program ended, its EXIT sent)
        _running = None


def start_new_thread(function, args, kwargs=None):
    if not isinstance(args, tuple):
        raise TypeError("expecting a tuple")
    if kwargs is not None and not isinstance(kwargs, dict):
        raise TypeError("expecting a dict")
    if not _threads:
        _start()
    me = _Thread()
    _threads.append(me)
    return _start_real(_body, (me, function, args, kwargs or {}))  # (the new thread's id)


def exit():
    raise SystemExit


_stack_size = 0


def stack_size(*size):
    """py/modthread.c: the size for the next threads (0: the port's default), the last one back."""
    global _stack_size
    last = _stack_size
    _stack_size = int(size[0]) if size else 0
    return last


class LockType:
    """A lock of the firmware's: taking one another thread holds lets the others run."""

    def __init__(self):
        self._lock = _new_lock()

    def acquire(self, waitflag=1, timeout=-1):
        if self._lock.acquire(0):
            return True
        if not waitflag:
            return False
        end = _hil.FOREVER_US if timeout < 0 else _hil._now + int(timeout * 1_000_000)
        while True:
            if _running is None:
                return self._lock.acquire()
            block()
            if self._lock.acquire(0):
                return True
            if _hil._now >= end:
                return False

    def release(self):
        self._lock.release()

    def locked(self):
        return self._lock.locked()

    def __enter__(self):
        return self.acquire()

    def __exit__(self, *exc):
        self.release()


def allocate_lock():
    return LockType()

# select module for firmware running in the loop. asyncio waits through
# select.poll().ipoll(ms); here that wait is a virtual sleep that ends early when a
# polled UART receives bytes.
import _hil

POLLIN = 0x0001
POLLOUT = 0x0004
POLLERR = 0x0008
POLLHUP = 0x0010
_NOTHING = ()


class _Poll:
    def __init__(self):
        self._map = {}

    def register(self, obj, eventmask=POLLIN | POLLOUT):
        self._map[id(obj)] = [obj, eventmask]

    def modify(self, obj, eventmask):
        entry = self._map.get(id(obj))
        if entry is None:
            raise OSError(2)  # ENOENT, as the built-in poll raises
        entry[1] = eventmask

    def unregister(self, obj):
        self._map.pop(id(obj), None)

    def _ready(self, flags=0):
        ready = []
        for entry in self._map.values():
            obj, mask = entry
            ev = _events(obj, mask)
            if ev:
                ready.append((obj, ev))
                if flags & 1:  # one-shot: no more events until modify() re-arms it
                    entry[1] = 0
        return ready

    def _any_ready(self):
        for obj, mask in self._map.values():
            if _events(obj, mask):
                return True
        return False

    def ipoll(self, timeout=-1, flags=0):
        if not self._map:  # nothing to poll (asyncio's sleeps): a plain virtual sleep
            if timeout == 0:  # a look, not a wait: time moves as a spin
                _hil.observe()
            elif timeout:
                _hil.blocking()
                _hil.run_until(_hil.FOREVER_US if timeout < 0 else _hil.now() + timeout * 1000)
            return _NOTHING
        # A board's poll allocates nothing: the shim's own work here (the ready list, the
        # handles to watch) runs with the firmware's heap lock, if any, released.
        depth = _hil.heap_release()
        try:
            return self._ipoll(timeout, flags)
        finally:
            _hil.heap_restore(depth)

    def _ipoll(self, timeout, flags):
        if timeout == 0:  # a look, not a wait (asyncio between runnable tasks): time moves as a spin
            _hil.observe()
            return self._ready(flags)
        ready = self._ready(flags)
        if ready:  # (no wait: in a loop, as a spin, so time still moves)
            _hil.observe()
            return ready
        _hil.blocking()
        watch = [obj._handle for obj, _ in self._map.values() if hasattr(obj, "_handle")]
        deadline = _hil.FOREVER_US if timeout < 0 else _hil.now() + timeout * 1000
        streams = len(watch) < len(self._map)
        if streams:  # streams a callback makes ready: wake at its instant
            _hil._link.woke = self._any_ready
        try:
            while True:
                t = _hil.now()
                # Streams of Python (and sockets) are looked at again each system tick
                # (1 ms), as a board's poll does between interrupts.
                _hil.run_until(min(deadline, t - t % 1000 + 1000) if streams else deadline, watch)
                ready = self._ready(flags)
                if ready or _hil.now() >= deadline:
                    return ready
        finally:
            _hil._link.woke = None

    poll = ipoll


def _events(obj, mask):
    """The events ready on obj now: a shim UART asks the link; a stream of Python (an
    asyncio ThreadSafeFlag) answers MP_STREAM_POLL through ioctl; anything else with a
    file descriptor (a socket, stdin) asks the real poll, without waiting."""
    ev = 0
    ready = getattr(obj, "_poll_ready", None)
    if ready is not None:
        if mask & POLLIN and ready(POLLIN):
            ev |= POLLIN
        return ev | (mask & POLLOUT)
    ioctl = getattr(obj, "ioctl", None)
    if ioctl is not None:
        got = ioctl(3, mask)  # MP_STREAM_POLL
        if got is not None and got < 0:
            raise OSError(-got)
        return got & mask if got else 0
    real = _hil._rselect.poll()
    real.register(obj, mask)
    for _obj, got in real.ipoll(0):
        ev |= got
    return ev


def poll():
    return _Poll()

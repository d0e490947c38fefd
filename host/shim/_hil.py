# Core of the shim: the link to the host and the firmware's clock.
#
# Runs inside MicroPython. Virtual time is an integer count of microseconds since the
# firmware started (`_now`). The host owns the plant; it tells the shim, with every
# STATE, the earliest time an input may change (`_horizon`). Until then the shim moves
# its clock on its own (sleeps that end before the horizon, busy waits, Timers); to go
# further it sends WAIT and the host advances the plant, stopping early at an edge that
# fires a registered IRQ. Actuator writes are sent as OUT and void the horizon, since
# they change what the plant will do next. docs/clock.md tells the whole story.
import sys

_path = sys.path
sys.path = []
import select as _rselect  # noqa: E402
import time as _rtime  # noqa: E402  the real built-ins, under the shadowing shim

sys.path = _path
del _path

import os  # noqa: E402
import struct  # noqa: E402

import _hilframe as F  # noqa: E402

SPIN_LIMIT = 50  # clock/input reads without a blocking call before time starts to move
DONE_BATCH = 32  # bus reads answered from an image in a row at most: the next is an exchange (a poll
# on its own stays in step with the host, its reports few in the heap and the link)
SPIN_STEP_US = 10  # virtual time each further read costs while spinning
BRANCHES = 256  # the firmware's own branches between two looks at whether it spins (_branches)
BEHIND_US = 100_000  # MCU time: callbacks this far ahead of the clock: the board falls behind
TICKS_PERIOD = 1 << 30  # a 32-bit MCU's small-int tick period
TICKS_MASK = TICKS_PERIOD - 1

mode = F.MODE_LOCKSTEP
_lockstep = True  # mode == MODE_LOCKSTEP, for the hot paths
_now = 0
_horizon = 0
_spin = 0
_b_now = _b_spin = -1  # the clock and the spin count at _branches' last look, the compute
_b_owed = -1  # owed then (MCU time; -1: not known), and the branches since (_b_window)
_b_window = 0
_b_since = -1  # when the firmware's own code last called the board, as _branches saw it (-1: it
_b_looks = 0  # just did), and its looks since: named once a run after POLL_SPAN_US (a POLL_SPIN)
_b_said = False
_b_told = 0  # when the host last heard from the board (the wall's ms: every ALIVE_MS, the link stays alive)
ALIVE_MS = 1_000
_b_told_at = 0  # and the virtual time then
_b_syncs = 0  # the exchanges so far (_Link.syncs) at that look
FOREVER_US = F.FOREVER_US
_NO_IMAGE = b""
_NO_STREAMS = bytes(16)
_timer_due = FOREVER_US
_timers = []
_handles = []
_pending = []  # (callback, argument) due to run between main-program bytecodes
_dispatching = False
_cb_reads = 0  # the running soft callback's clock and input reads (past SPIN_LIMIT its reads move time)
_HELD = -(1 << 28)  # (_cb_reads in a hard handler: its reads never move time)
_wrote = False
_irq_off = 0
_link = None
_wake_real_us = 0
_rt_origin_us = 0


class _Console:
    """The REPL UART's transmitter (docs/shim.md, "Printing takes time"): print() blocks
    until what it printed, all but the last FIFO's worth, has left at the baud rate, as a
    board's blocking UART TX does. The time owed is paid at the firmware's next clock
    read, wait or output (with the wait it ends or begins: no extra exchange with the
    host), so the text keeps the stamp of the instant it was printed at."""

    ns_per_byte = 0  # 10 bits (start, 8 data, stop) at the baud rate; 0: printing is free
    fifo_bytes = 128  # the TX FIFO (the ESP32's UART has 128 bytes, the RP2040's 32)
    idle_ns = 0  # when the transmitter has sent all it holds (virtual time, ns)
    debt_ns = 0  # how long print() has blocked that the clock has not yet moved for
    # MCU time (docs/mcu-time.md): with [board] cpu, _hilfast.owed_us (the main program's
    # compute since the last charge, µs: added to the debt above, paid the same way) and
    # _hilfast.busy_us (until when callbacks' compute keeps the CPU busy); else None
    cpu = busy = irq = None  # (irq: _hilfast.irq_us, all the callbacks' compute so far)
    owing = None  # _hilfast.owing_us: owed_us without taking it (_branches), with MCU time
    ran_us = 0  # the main program's compute charged since its last wait began (WAIT's compute_us)
    runs = []  # (t_us, compute_us) of each wait begun since the last exchange (CPU_RUNS, then WAIT)
    stack = None  # _hilfast.stack (the firmware's running functions), with MCU time
    longest_us = 0  # the longest compute between two waits so far (sent with its code: CPU)
    top_us = 0  # this stretch's largest charge since it outgrew longest_us, and the code
    top_stack = None  # that ran when it was charged (sampled then: a record's pieces only)
    irq_told = 0  # the callbacks' compute told the host (CPU_IRQ, once per CPU_WINDOW_US), and
    irq_from = 0  # since when
    behind = False  # the callbacks' compute has outrun the clock by BEHIND_US (said once)


def console_setup(baud, fifo_bytes):
    _Console.ns_per_byte = 10_000_000_000 // baud if baud > 0 else 0
    _Console.fifo_bytes = fifo_bytes


def _printed(n_bytes):
    """n_bytes went to the console UART at the firmware's instant (_now plus what it owes)."""
    per = _Console.ns_per_byte
    t_ns = _now * 1000 + _Console.debt_ns
    start = _Console.idle_ns if _Console.idle_ns > t_ns else t_ns
    end = start + n_bytes * per
    _Console.idle_ns = end
    free_ns = end - _Console.fifo_bytes * per  # print() returns once the rest fits in the FIFO
    if free_ns > t_ns:
        _Console.debt_ns += free_ns - t_ns


def cpu_start(getenv):
    """Compute costs the board's CPU time from here on, when the host names a CPU
    (WELCOME's cpu, its cost table cpu_cost; host/rig/targets/mcutime.py): the firmware's work is
    counted by this interpreter (_hilfast, host/core/micropython/hilcount.patch), the
    shim's own is not. Without the counter (a user's own interpreter, HIL_PURE) compute
    stays free, which it says once."""
    settings = _Link.settings
    name = settings["cpu"].decode()
    if not name:
        return
    fast = None
    if not (getenv and getenv("HIL_PURE")):
        try:
            import _hilfast as fast
        except ImportError:
            pass
    if fast is None or not hasattr(fast, "owed_us"):
        sys.stderr.write("mpy-fil: [board] cpu = %s: this interpreter cannot count, compute is free here\n" % name)
        return
    if not _lockstep:  # (the clock is the wall's: compute takes the host's real time)
        sys.stderr.write("mpy-fil: [board] cpu = %s: not in real time, where compute takes the host's time\n" % name)
        return
    _exempt(fast)
    # (the board's heap the firmware's collections are modelled in: only its own objects count)
    fast.cost(settings["cpu_cost"], settings["cpu_heap"])
    if hasattr(fast, "heap_roots"):  # (what a board holds in C for the firmware: no other of the shim's
        fast.heap_roots((_handles, _timers, _pending))  # objects keeps the firmware's alive in its count)
    _Console.cpu, _Console.busy, _Console.stack = fast.owed_us, fast.busy_us, fast.stack
    _Console.owing = getattr(fast, "owing_us", None)
    _Console.irq = getattr(fast, "irq_us", None)  # (a build before it: callbacks do not preempt)
    _Link.irq_begin, _Link.irq_end = fast.irq_begin, fast.irq_end
    _reads_charge()
    import _hilsys

    _hilsys.before_print = pay_cpu  # (a print leaves after the compute before it: stamped then)


def _charge_cpu():
    """The main program's compute since the last charge, owed as print()'s blocking is;
    True when the clock owes a µs or more."""
    if _dispatching:  # (a callback's compute is its own: _hilfast.irq_end charges it as the CPU's)
        return _Console.debt_ns >= 1000
    owed = _Console.cpu()
    if owed:
        _Console.debt_ns += owed * 1000
        ran = _Console.ran_us + owed
        _Console.ran_us = ran
        if owed > _Console.top_us and owed * 4 > _Console.longest_us:  # (the code of a would-be record's
            _Console.top_us = owed  # largest piece, sampled as it is charged: bounded, one call per larger piece)
            try:
                _Console.top_stack = _Console.stack()
            except MemoryError:  # (under the firmware's heap_lock: the record's code is taken at its wait)
                _Console.top_stack = None
    return _Console.debt_ns >= 1000


def _wait_begins():
    """MCU time: a wait begins, which ends the main program's compute stretch (whether the
    shim serves the wait itself or asks the host): its compute is one run for the budgets
    and the CPU load (CPU_RUNS, then the WAIT), and a record stretch is said (CPU)."""
    _charge_cpu()
    ran = _Console.ran_us
    if not ran:
        return
    _Console.ran_us = 0
    depth = heap_release()  # (a wait under the firmware's heap_lock: these records allocate, a board's do not)
    try:
        if ran > _Console.longest_us:
            _cpu_stretch(ran)
        _Console.top_us, _Console.top_stack = 0, None
        runs = _Console.runs
        runs.append((_now, ran))
        if len(runs) > F.CPU_RUNS_MAX:  # (the oldest go now, with the next message sent)
            _send_runs(runs[: F.CPU_RUNS_MAX])
            del runs[: F.CPU_RUNS_MAX]
    finally:
        heap_restore(depth)


def _mcu_compute():
    """MCU time, at an exchange: the main program's compute before this WAIT (the last wait
    begun since the last exchange, if nothing ran since it began), the waits' before it sent
    as a CPU_RUNS; a record stretch said; the callbacks' compute told once a window."""
    compute_us = _Console.ran_us
    _Console.ran_us = 0
    runs = _Console.runs
    if runs:
        if not compute_us:
            compute_us = runs.pop()[1]
        if runs:
            _send_runs(runs)
            runs.clear()
    if compute_us > _Console.longest_us:
        _cpu_stretch(compute_us)
    _Console.top_us, _Console.top_stack = 0, None
    if _Console.irq is not None and _now // F.CPU_WINDOW_US != _Console.irq_from // F.CPU_WINDOW_US:
        _irq_load()
    return compute_us


def _send_runs(runs):
    payload = struct.pack(F.CPU_RUNS_FMT, len(runs))
    for t, ran in runs:
        payload += struct.pack(F.CPU_RUN_FMT, t, ran)
    send(F.CPU_RUNS, payload)


def _irq_load():
    """The callbacks' compute since the last time told, to the host (a window's CPU load)."""
    total = _Console.irq()
    if total != _Console.irq_told:
        send(F.CPU_IRQ, struct.pack(F.CPU_IRQ_FMT, _Console.irq_from, _now, total - _Console.irq_told))
        _Console.irq_told = total
    _Console.irq_from = _now


def _cpu_stretch(compute_us):
    """The longest compute between two waits so far ends here: a CPU message with the code
    that ran its largest piece (the firmware's frames, outermost first), for the report."""
    _Console.longest_us = compute_us
    frames = _Console.top_stack or _Console.stack()
    shim = __file__.rsplit("/", 1)[0]  # (the boot's frames: counted, begun before the shim's folder was exempt)
    text = "\n".join(
        '  File "%s", line %d, in %s' % (f, line, fn)
        for f, fn, line in frames
        if f != "<stdin>" and not f.startswith(shim) and not f.endswith("/_hilboot.py")
    )
    send(F.CPU, struct.pack(F.CPU_FMT, _now, compute_us, _Console.top_us) + text.encode())


def _console_owed_us():
    """The whole microseconds print() has blocked for, now taken off the debt."""
    owed = _Console.debt_ns // 1000
    _Console.debt_ns -= owed * 1000
    return owed


def pay_console():
    """Move the clock on by what print() owes (before an output, which a board makes after
    the print returned)."""
    if _Console.cpu is not None:
        _charge_cpu()
    if _Console.debt_ns >= 1000:
        _released_run_until(_now + _console_owed_us(), None)


class HostGone(Exception):
    pass


class LinkDamaged(Exception):
    """A frame from the host was damaged or lost: the run cannot go on (the host says so)."""


class CallbackFailed(Exception):
    """An IRQ handler or Timer callback raised. A board prints it and carries on without
    that call; in the loop the run ends, naming the callback (nothing fails unseen)."""

    def __init__(self, callback, error):
        if isinstance(error, CallbackFailed):  # (a hard handler's, named already: hard_handler)
            super().__init__(*error.args)
            return
        sys.modules.get("sys", sys).print_exception(error)  # (the board's: its frames only, _hilboot)
        name = getattr(callback, "__name__", repr(callback))
        super().__init__("the callback %s raised %s: %s" % (name, type(error).__name__, error))


class ResetRequest(BaseException):
    """machine.reset(): unwinds the firmware like a board that restarts."""


class HostStop(BaseException):
    """The host ended the session (BYE): unwinds the firmware back to the REPL."""


class _Link:
    """Frames over the pty the host named in HIL_LINK (the unix port in the loop)."""

    # While a poll waits on streams only a callback can make ready (an asyncio
    # ThreadSafeFlag): its check, True when one is. (Here, not a module global: more
    # globals in this module slow every global lookup of the hot paths.)
    woke = None
    # The plant may carry an output to an input at the same instant (a wire): a read
    # after a write then syncs at that instant (the WELCOME's flag).
    zero = False
    heap_lock = heap_unlock = None  # micropython's, set by start()
    collect = None  # gc.collect, set by start()
    reserve = None  # the shim's slice of the heap, in pieces (make_room)
    spent = True  # some of the reserve is not held: take it again after the shim's work
    ballast = None  # the interpreter's heap beyond the firmware's (_hilboot._board_heap)
    syncs = 0  # exchanges so far: a handler that blocks inside a batch makes more
    # A STATE may carry input changes past the time it wakes the firmware (the host's
    # lookahead, docs/clock.md): held here in time order, each applied as the clock passes
    # it; `after` is the host's horizon past them. An output, a print or a new input drops them.
    held = []
    after = 0
    ahead = False  # since the last STATE the host's plant may be past this clock
    thread = main_thread = None  # _thread.get_ident and the firmware's thread (start())
    threads = None  # _hilthread once the firmware has started a thread of its own (the board's _thread)
    thread_api = None  # the unix port's allocate_lock and start_new_thread, for _hilthread (_hilconfine)
    branches = None  # _branches, while _hilfast.branches calls it
    callbacks = 0  # IRQ handlers and Timer callbacks run so far (a light sleep's wake)
    # The scheduler's queue holds at most this many soft callbacks (MICROPY_SCHEDULER_DEPTH:
    # 8 in ports/rp2/mpconfigport.h and ports/esp32/mpconfigport.h; py/mpconfig.h's default
    # of 4 is the unix port's, not a board's).
    depth = 8
    # From this instant on the firmware is inside a call that is C on a board (a busy loop,
    # a blocking driver call: time_pulse_us, a bus transfer), where the port runs no
    # scheduled callback: soft ones wait in the queue for its return (c_begin). FOREVER_US: none.
    defer_from = F.FOREVER_US
    hard = False  # a hard IRQ's handler is running (they do not nest)
    # _hilfast.apply_state when the interpreter has it (the harness's build) and HIL_PURE
    # is not set, else None (the pure-Python loop of _sync: a user's own interpreter)
    fast = None
    fast_edges = False  # apply_state takes an EDGES too (a build before it: the pure path does)
    merge = None  # _hilfast.merge_edges: _apply_state's merge of an EDGES in C (None: in Python)
    pin_setup = pin_value = None  # _hilfast.pin_setup and pin_value (machine.Pin.value in C), or None
    roomy = None  # _hilfast.roomy (a Pin's attribute table with room: its class's methods found sooner), or None
    # _hilfast.link's (the harness's build, not HIL_PURE): the link's frames, their CRC and a
    # STATE's decoding and applying in C, with no allocation an exchange; None: in Python
    c = None
    out = False  # True: an OUT is queued in C (c.out; not kept bound: the firmware could reach the link through it)
    hdr = [0, 0, 0, 0, 0]  # the STATE's base, t_end, horizon, count, paused µs (c.wait fills it)
    cur = [0, 0, False]  # apply's offset, change and watched hit (c.apply)
    # The bus reads the shim answers itself until an instant (the last BUS_IMAGE's payload, read
    # in place by _hilframe.bus_image_find: _hil.transfer), and the one that came before the
    # STATE or BUS_REPLY being read.
    image = image_next = b""
    done = 0  # bus reads answered from an image since the last BUS
    # each stream's count of reads answered from the image streams_of (a chip's samples read in turn)
    streams = bytearray(16)
    streams_of = None
    # The PIO_AHEAD that came with the last BUS_REPLY (rp2.py takes it), and the frames sent
    # so far: rp2.py answers a PIO frame from it only while no frame went out since
    pio = None
    frames = 0
    edges = None  # the EDGES payload that came with the last STATE (encoder segments), or None
    pin = None  # machine.Pin (set by machine.py), whose changes apply_state makes in C
    g = None  # this module's globals, where apply_state sets _now (lockstep; None: real time)
    ctx = None  # (this module's globals, _Link, CallbackFailed): apply_state runs the handlers
    irq_begin = irq_end = None  # _hilfast's, with MCU time (cpu_start): dispatch tells it of callbacks
    until = -1  # the running wait's end (_run_until): the callbacks due on its way run until then
    lost = False  # a soft callback's call was lost (_lost: said once)
    passes = 0  # a wait's passes in a row that found callbacks queued by callbacks (_next_pass)
    # _hilfast.arm (the harness's build, not HIL_PURE): the callbacks left queued run at the
    # firmware's next branches, one a branch (_leftovers); None: at its next call into the shim
    arm = None
    # The host's settings for this run, from WELCOME (_hilframe.unpack_welcome: console_baud,
    # ticks_wrap_ms, entry, the board's folder, ...; docs/protocol.md): set by start()
    settings = None

    def __init__(self, path):
        f = open(path, "r+b")
        c = _c_link(f)
        if c is not None:  # (the same frames, their bytes and their decoding, in C)
            _Link.c = c
            _c_framed(self, c, f.close)
            return
        poller = _rselect.poll()
        poller.register(f.fileno(), _rselect.POLLIN)  # (its answers carry the fd, never the file)
        readinto = f.readinto
        got = memoryview(bytearray(512))  # (read into: no 512 bytes in one piece per read)

        def read():
            n = readinto(got)
            if not n:
                return b""
            try:
                return got[:n]  # (the decoder copies it before the next read)
            except MemoryError:  # (read already: it must not be lost)
                spend_reserve()
                return got[:n]

        def close():
            f.close()

        _framed(self, f.write, read, poller.poll, close)

    def exchange(self, wait_payload, t_now, state_fmt):
        """Send WAIT and return the payload of the STATE that answers it."""
        self.queue(F.WAIT, wait_payload)
        self.flush()
        edges = None
        while True:
            type_, _seq, p = self.recv()
            if type_ == F.BYE:
                raise HostStop()
            if type_ == F.STATE:
                if struct.unpack_from(state_fmt, p, 0)[0] == t_now:
                    _Link.image, _Link.image_next = _Link.image_next, _NO_IMAGE
                    _Link.done = 0  # (the reads it answered went with the WAIT)
                    _Link.edges = edges
                    return p
                edges = None  # (a STATE for another WAIT is stale: a Ctrl-C cut that wait short)
            elif type_ == F.EDGES:  # the encoder edges of the STATE that follows (_sync applies both)
                edges = p
            elif type_ == F.BUS_IMAGE:
                _Link.image_next = p
            elif type_ == F.EVAL:  # the host looks inside while it holds the clock (docs/live.md)
                import _hilrepl

                _hilrepl.answer(self, p)

    def other(self, c, frame, t_now):
        """The frames that came before the STATE of the C link's wait (c.wait in _sync),
        handled as exchange handles them, up to that STATE."""
        while frame is not None:
            if frame == 0:
                raise _damaged(*c.counters())
            if frame == -1:  # (a frame of another kind not taken for want of memory: read again)
                spend_reserve()
            else:
                type_, _seq, p = frame
                if type_ == F.BYE:
                    raise HostStop()
                if type_ == F.BUS_IMAGE:
                    _Link.image_next = p
                elif type_ == F.EVAL:  # the host looks inside while it holds the clock (docs/live.md)
                    import _hilrepl

                    _hilrepl.answer(self, p)
            p = frame = None
            try:
                frame = c.wait(_Link.hdr, t_now)
            except MemoryError:
                frame = -1


def _c_link(f):
    """The link in C (_hilfast.link over the pty's fd), or None: not in this interpreter, or
    HIL_PURE set (the pure path: a user's own interpreter)."""
    getenv = getattr(os, "getenv", None)
    if getenv and getenv("HIL_PURE"):
        return None
    try:
        import _hilfast
    except ImportError:
        return None
    if not hasattr(_hilfast, "defers"):  # (a build before exchange, run and out: the pure path)
        return None
    return _hilfast.link(f.fileno(), HostGone)


def _c_framed(link, c, close):
    """_framed's queue, flush, recv and close over the C link: the same frames, the same
    decoding (what the firmware can reach of it sends only frames it encodes)."""
    queue_c, recv_c = c.queue, c.recv

    def queue(type_, payload):
        queue_c(type_, payload)
        _Link.frames += 1

    def recv():
        while True:
            try:
                frame = recv_c()
            except MemoryError:  # (not taken: read again)
                spend_reserve()
                continue
            if frame is None:
                raise _damaged(*c.counters())
            return frame

    def flush():
        c.flush()

    def close_link():
        close()

    # (no bound method kept: its object out of sight, docs/security.md)
    link.queue, link.flush, link.recv, link.close = queue, flush, recv, close_link
    link.own_queue = queue  # (_sync's check: _hilrepl puts another in its place)


def _damaged(frames, bad_crc, bad_length, truncated, seq_gaps, duplicates):
    return LinkDamaged(
        "a frame from the host was damaged or lost on the plant link (bad_crc=%d, bad_length=%d, "
        "truncated=%d, seq_gaps=%d; good frames %d, duplicates dropped %d): the run cannot be "
        "trusted past it" % (bad_crc, bad_length, truncated, seq_gaps, frames, duplicates)
    )


def _framed(link, write, read, poll, close):
    """Give ``link`` its queue(type_, payload), flush(), recv() and close() over the host's
    stream: its ``write``, ``read`` (bytes), ``poll`` and ``close``. The stream (the pty's
    file, its methods), the frames queued and the bytes read are held only in these
    closures (MicroPython has no __closure__, a bound method no __self__), never in an
    attribute: what the firmware can reach of the link sends only frames the shim encodes
    and takes only frames it decodes, never bytes of its own, and no attribute is the
    host's file or its fd (docs/security.md, "The link and the coverage file")."""
    link.queue, link.flush = _framed_out(write)
    link.recv = _framed_in(read, poll)
    link.close = close


def _framed_out(write):
    out = []
    seq = 0

    # The frames' own allocations are made before anything is sent or taken: where one
    # fails (a frame longer than the room make_room saw), the reserve goes and it is made again.
    def queue(type_, payload):
        nonlocal seq
        try:
            frame = F.encode(type_, seq, payload)
        except MemoryError:
            spend_reserve()
            frame = F.encode(type_, seq, payload)
        out.append(frame)
        seq = (seq + 1) & 0xFF
        _Link.frames += 1

    def flush():
        nonlocal out
        if out:
            try:
                data = b"".join(out)
            except MemoryError:
                spend_reserve()
                data = b"".join(out)
            out = []
            view = memoryview(data)
            while view:
                n = write(view)
                view = view[n:]

    return queue, flush


def _framed_in(read, poll):
    dec = F.Decoder()

    def recv():
        while True:
            try:
                frame = dec.next()
            except MemoryError:
                spend_reserve()
                frame = dec.next()
            if frame is not None or dec.damaged:
                if dec.damaged:
                    c = dec.counters()
                    raise _damaged(
                        c["frames"], c["bad_crc"], c["bad_length"], c["truncated"], c["seq_gaps"], c["duplicates"]
                    )
                return frame
            events = poll(1000)
            if not events:
                if dec.pending():
                    dec.expire()  # a partial frame that stopped arriving
                continue
            if events[0][1] & (_rselect.POLLHUP | _rselect.POLLERR):
                raise HostGone("plant link closed")
            data = read()
            if not data:
                raise HostGone("plant link closed")
            try:
                dec.feed(data)  # (the decoder's buffer is replaced only once it is made)
            except MemoryError:
                spend_reserve()
                dec.feed(data)

    return recv


class _StdioLink(_Link):
    """Frames over the board's own console (USB serial): processor in the loop. Ctrl-C
    is data while it runs; a board's stdin read(n) waits for all n bytes, so bytes are
    taken one at a time while the poller says there are more."""

    def __init__(self):
        import micropython

        inp = sys.stdin.buffer if hasattr(sys.stdin, "buffer") else sys.stdin
        poller = _rselect.poll()
        poller.register(sys.stdin, _rselect.POLLIN)
        ready = poller.poll

        def read():
            data = b""
            while len(data) < 512:
                c = inp.read(1)
                if not c:
                    break
                data += c
                if not ready(0):
                    break
            return data

        def close():
            micropython.kbd_intr(3)

        _framed(self, (sys.stdout.buffer if hasattr(sys.stdout, "buffer") else sys.stdout).write, read, ready, close)
        micropython.kbd_intr(-1)


def register(obj):
    """Give a shim object a handle the host refers to."""
    _handles.append(obj)
    return len(_handles) - 1


def send(type_, payload):
    _link.queue(type_, payload)


def send_output(type_, payload):
    """An actuator write (OUT, UART_TX): from now on the plant may behave differently."""
    global _horizon, _wrote
    _link.queue(type_, payload)
    _Link.image = _NO_IMAGE  # (the plant's next events may change: the host images anew)
    _horizon = _now
    _wrote = True
    if _Link.held:
        _drop_held()


def said(n_bytes=0):
    """The firmware printed: its next wait goes to the host (as after an output), so the
    host stamps the text with the virtual time it was printed at (docs/traces.md). With
    the console's baud rate set, n_bytes (0: not counted) cost their time on the UART."""
    global _horizon
    if _Console.cpu is not None:
        _charge_cpu()  # (the text leaves once what ran before it is done)
    if n_bytes and _Console.ns_per_byte:
        _printed(n_bytes)
    if _horizon > _now:
        _horizon = _now
    if _Link.held:
        _drop_held()


def _drop_held():
    """The firmware changed what the plant does (or printed) inside a lookahead: the held
    changes are void, and the host, told of it, rewinds to this instant."""
    _Link.held = []
    _Link.ahead = False


def send_out(handle, attr, value):
    global _horizon, _wrote
    if _Console.cpu is not None:
        _charge_cpu()
    if _Console.debt_ns >= 1000:  # a board writes once the print before has returned
        pay_console()
    if not _Link.out or _link.queue is not _link.own_queue or not _Link.c.out(now(), handle, attr, value):
        _send_out_py(handle, attr, value)
        return
    _Link.frames += 1  # (as send_output, the OUT queued in C: _hilfast.link's out)
    if _Link.image is not _NO_IMAGE:
        _Link.image = _NO_IMAGE
    _horizon = _now
    _wrote = True
    if _Link.held:
        _drop_held()


def _send_out_py(handle, attr, value):
    send_output(F.OUT, struct.pack(F.OUT_FMT, now(), handle, attr, value))  # F.pack_out, inline


cfg_last = {}
"""Each pin's last CFG's handle (a Pin's, a PWM's, an ADC's), cleared by a CFG of anything
else (a bus, a UART, PIO): a Pin made anew as it was, its pin not taken since, sends none
(machine.Pin._init)."""


def configure(handle, kind, name, mode_=0, pull=0, param=0, sync=False):
    """A CFG at the firmware's instant (as an OUT carries its time): the host brings the
    plant to it first, so what the CFG changes there (a line let go) starts then. With MCU
    time (or a print's time owed) that instant is after the compute before it, as an OUT's
    is (send_out): a pin let go after 30 us of compute is let go 30 us later, on the clock
    the firmware's next read sees."""
    global _horizon
    if _Console.cpu is not None:
        _charge_cpu()
    if _Console.debt_ns >= 1000:
        pay_console()
    if kind == F.CFG_PIN or kind == F.CFG_PWM or kind == F.CFG_ADC:
        cfg_last[name] = handle
    elif kind != F.CFG_IRQ:
        cfg_last.clear()
    _Link.image = _NO_IMAGE  # (a CFG may change the plant: the host images anew)
    if _Link.held or _Link.ahead:  # the host is ahead of this instant: back to it before the CFG
        _drop_held()
        _horizon = _now
        _sync(now(), None)
    _link.queue(F.CFG, F.pack_cfg(now(), handle, kind, mode_, pull, param, str(name).encode()))
    if sync:  # inputs: learn the current level before the firmware reads it
        _sync(now(), None)


def _image_entry(image, handle, op, address, n_read, data, t):
    """The offset of the entry of the BUS_IMAGE payload ``image`` that answers this transfer
    at ``t`` (its stream's count moved on), or -1: the host's."""
    if op != F.BUS_XFER or not n_read or _Link.done >= DONE_BATCH:
        return -1
    streams = _Link.streams
    if _Link.streams_of is not image:  # (a new image: its streams' counts from 0)
        _Link.streams_of = image
        streams[:] = _NO_STREAMS
    at = F.bus_image_find(image, handle, address, data, n_read, t, streams)
    if at >= 0:
        F.bus_image_took(image, at, streams)
    return at


def transfer(handle, op, address, n_read, data):
    """A bus transfer (I2C, SPI: host/shim/_hilbus.py) at the firmware's instant: the
    host answers it from the devices as the plant is at that instant (BUS, BUS_REPLY:
    docs/protocol.md), then the clock moves on by the transfer's time on the bus. Like an
    output it may change what the plant does next (a register written, a data-ready pin
    cleared). Returns (status, count, bytes read, the instant): the caller passes the time
    the transfer took on the bus (which depends on its outcome) to bus_time()."""
    global _horizon, _wrote
    if _Console.cpu is not None:
        _charge_cpu()
    if _Console.debt_ns >= 1000:  # a board starts the transfer once the print before has returned
        pay_console()
    depth = heap_release()
    make_room()
    try:
        t = now()
        image = _Link.image
        if image:  # a register read whose bytes the host sent, inside their window: no exchange
            at = _image_entry(image, handle, op, address, n_read, data, t)
            if at >= 0:
                # (the shim as a BUS_REPLY leaves it: the lookahead void, the reply's horizon)
                if _Link.held:
                    _drop_held()
                _link.queue(F.BUS_DONE, F.pack_bus_done(t, at))  # (sent with the next message)
                _Link.done += 1
                _Link.ahead = False
                _horizon = F.bus_image_horizon(image)
                _wrote = True
                return F.BUS_OK, len(data), F.bus_image_got(image, at), t
            _Link.image = _NO_IMAGE  # (the host answers this one, and sends a new image)
        _Link.done = 0
        if _Link.held:
            _drop_held()  # (the host rewinds to this instant)
        _link.queue(F.BUS, F.pack_bus(t, handle, op, address, n_read, data))
        _link.flush()
        while True:
            type_, _seq, p = _link.recv()
            if type_ == F.BYE:
                raise HostStop()
            if type_ == F.BUS_REPLY:
                break
            if type_ == F.BUS_IMAGE:
                _Link.image = p
            elif type_ == F.PIO_AHEAD:  # (rp2.py's: the PIO read's next frames answered)
                _Link.pio = p
        _t, status, count, horizon, got = F.unpack_bus_reply(p)
        if status & F.BUS_ASK_STACK:  # a poll of this read named: the firmware's stack with it
            status &= ~F.BUS_ASK_STACK
            import _hilpoll

            _hilpoll.send_stack(t)
        _Link.ahead = False  # the host's plant is at this instant
        _horizon = horizon
        _wrote = True
    finally:
        if _Link.spent:
            keep_reserve()
        heap_restore(depth)
    return status, count, got, t


def bus_time(t_end):
    """The firmware blocks on the bus until t_end (a transfer's end, virtual time): a C
    call on a board (the ports' I2C, SPI, bitstream, 1-Wire and DHT drivers wait without
    running scheduled callbacks: docs/shim.md, "Where callbacks run"), so soft callbacks
    due meanwhile run when it returns."""
    if t_end > _now:
        prev = c_begin(_now)
        try:
            _released_run_until(t_end, None)
        finally:
            c_end(prev)


# -- clock ------------------------------------------------------------------------


def _lockstep_now():
    return _now


def _realtime_now():
    """The board's clock less the host's pauses; never back (a pause the host measured longer
    than this clock saw it would take it back: held until the clock passes it)."""
    global _now
    t = _rtime.ticks_diff(_rtime.ticks_us(), _rt_origin_us)
    if t > _now:
        _now = t
    return _now


now = _lockstep_now


def observe():
    """Called by every clock or input read; lets busy waits make progress."""
    global _spin, _now
    if _dispatching:  # a handler runs at its edge's instant: its reads move no time ...
        _callback_read()
        return
    if _Link.threads is not None:  # (the firmware's threads take turns: _hilthread)
        _Link.threads.tick()
    if _pending:  # left by a C call (c_begin) or a wait: at the firmware's branches
        _leftovers()
    if _lockstep:
        t = _now
        _spin += 1
        if _spin > SPIN_LIMIT:
            t += SPIN_STEP_US
    else:
        t = now()
    if t >= _horizon or t >= _timer_due:
        # (a read: not the blocking calls' thread check, on this hot path; the heap lock
        # released, since the firmware may read the clock under it and this may sync). A
        # read is C on a board: the soft callbacks due on the way run at the branches
        # after it (on an interpreter that cannot see them, here: _leftovers).
        _Link.until = -1 if _Link.arm is not None else t
        _released_run_until(t, None)
    else:
        _now = t


_observe_free = observe


def _callback_read():
    """A read inside a handler. A hard IRQ's handler's reads move no time (it runs at its
    edge's instant). A soft callback is the firmware's code on a board, run from the
    scheduler: the clock and the pins go on while it runs. Its first SPIN_LIMIT reads move no
    time, as a handler's few reads of its pin and the clock; past them it spins (a busy wait
    for a pin or a delay, `while echo.value() == 0: pass`), each read SPIN_STEP_US on, the
    host asked at the horizon: the changes come, hard IRQs' handlers run at their instants,
    the soft callbacks they queue wait for this one to return (py/scheduler.c: the scheduler
    is locked while a scheduled callback runs)."""
    global _cb_reads, _now
    _cb_reads += 1
    if _cb_reads <= SPIN_LIMIT or not _lockstep:
        return
    t = _now + SPIN_STEP_US
    if t >= _horizon or t >= _timer_due:
        _Link.until = -1 if _Link.arm is not None else t
        _released_run_until(t, None)
    else:
        _now = t


def pay_cpu():
    """MCU time: the main program's compute so far paid, as before a clock read (the callbacks
    due within it run); nothing without MCU time. Before each print() too (_hilsys.before_print):
    on a board the text leaves once the compute before it is done, so the console's stamp is
    that instant (and the blocking of the prints before it is over by then)."""
    if _Console.cpu is not None and not _dispatching and _charge_cpu():
        _released_run_until(_now, None)


def _observe_mcu():
    """observe() with MCU time (cpu_start puts it in observe's place, so that the clock
    reads of a run without it check nothing more): the compute before the read is paid
    first, as a wait that ends that much later."""
    if not _dispatching and _charge_cpu():
        _released_run_until(_now, None)
    _observe_free()


def _branches():
    """At every BRANCHES-th branch of the firmware's own code (_hilfast.branches, the VM's
    branch hook in the harness's build). A loop that read no clock and no input since the
    last look (the clock and the spin count as they were) spends a board's time there: it
    is a read, as far as virtual time goes (observe): without MCU time one that spins (past
    SPIN_LIMIT each costs SPIN_STEP_US), with it the compute so far is charged once a Timer
    or an input change comes due within it (none due: nothing charged yet, the stretch
    goes on; one due before the next look at this pace: the next look is sooner, so the
    loop sees a flag its callback sets within a few branches of the callback's instant, as
    on a board). So `while playing: pass` ends when the Timer that clears `playing` fires,
    where it would hang with compute free of time (docs/mcu-time.md, "A loop that calls
    nothing of the board's"). Allocates nothing (it runs under heap_lock too)."""
    global _b_now, _b_spin, _b_owed, _b_window, _b_since, _b_looks, _b_told, _b_syncs
    window = BRANCHES
    owing = _Console.owing
    threads = _Link.threads  # (their turns: observe's tick, at a read or a look below)
    if _Link.syncs != _b_syncs:  # (the host heard from the board: an exchange)
        _b_syncs, _b_told = _Link.syncs, _rtime.ticks_ms()
    elif _rtime.ticks_diff(_rtime.ticks_ms(), _b_told) >= ALIVE_MS and _now > _b_told_at:
        _spin_told(False)  # (only while virtual time moves: a loop stuck at one instant is a hang)
    if _b_now != _now or _b_spin != _spin:
        _b_since = -1
    elif _dispatching and _cb_reads < 0:
        pass  # (a hard handler's loop: it runs at its edge's instant, its reads move no time)
    elif _dispatching or threads is not None or _Link.thread() == _Link.main_thread:
        if _b_since < 0:
            _b_since, _b_looks = _now, 0
        _b_looks += 1
        if not _b_said and _now - _b_since >= F.POLL_SPAN_US:
            _spin_told(True)
        if _dispatching:  # a soft callback's loop (`while not ready: pass`, a flag a hard handler
            _callback_read()  # sets): the look is one of its reads, so its clock goes on
        elif owing is None:
            observe()
        else:
            owed = owing() + _Console.debt_ns // 1000
            ahead = _now + owed
            due = _horizon if _horizon < _timer_due else _timer_due
            if threads is not None:  # (another thread's wake or turn: it runs then)
                turn = threads.due()
                if turn < due:
                    due = turn
            if ahead >= due:
                observe()
            elif _b_owed >= 0 and due < FOREVER_US and owed - _b_owed > due - ahead:
                window = (due - ahead) * _b_window // (owed - _b_owed) + 1
                _b_owed, _b_window = owed, window
                return window
    _b_now = _now
    _b_spin = _spin
    _b_owed = -1 if owing is None else owing() + _Console.debt_ns // 1000
    _b_window = window
    return window


def _spin_told(name):
    """A POLL_SPIN to the host. Without `name`: the firmware has run on for ALIVE_MS of wall
    time since the host last heard from it (a loop of clock or register reads, or of
    nothing at all, inside a long horizon, where no exchange is due): the host hears the
    board is alive, as from a wait (its watchdog counts wall time between messages; the
    message changes nothing it records). With `name` (once a run): a loop that called
    nothing of the board's for POLL_SPAN_US of virtual time, with the firmware's stack: the
    host's note says where it spins. A board spins there too; a loop that waits for a
    callback's flag ends when the callback fires."""
    global _b_said, _b_told, _b_told_at
    _b_told, _b_told_at = _rtime.ticks_ms(), _now
    try:
        text = ""
        if name:
            import _hilpoll

            stack = _hilpoll.firmware_stack()
            text = "\n" + "\n".join(stack) if stack else ""
        send(F.POLL, F.pack_poll(_now, max(_b_since, 0), _b_looks * BRANCHES, F.POLL_SPIN, 0, 0, name, text.encode()))
        _link.flush()
        _b_said = _b_said or name
    except MemoryError:  # (under heap_lock: nothing said; the next look tries again)
        pass


def _reads_charge():
    global observe
    observe = _observe_mcu


def blocking():
    """A blocking call (sleep, idle, poll): the firmware is not spinning."""
    global _spin
    _spin = 0


def run_until(t_target, watch=None):
    """Move virtual time to t_target, running timers and IRQ handlers on the way.

    With `watch` (a list of handles), return True as soon as one of them changes.
    Under micropython.heap_lock() too (see heap_release). With the firmware's threads
    (_hilthread), the others run meanwhile."""
    threads = _Link.threads
    if threads is not None:
        return threads.wait(t_target, watch)
    return _wait(t_target, watch)


def _wait(t_target, watch):
    """run_until in the thread that holds the clock."""
    if _Link.threads is None and _Link.thread() != _Link.main_thread:
        raise RuntimeError("a second thread waits in virtual time: the loop runs one thread of control (docs/shim.md)")
    _Link.until = t_target  # (the wait handles events: the callbacks due on its way run)
    if _Console.cpu is not None and not _dispatching:
        _wait_begins()
    if _pending:  # left by a C call (c_begin), a read or a callback: the wait's first checks
        dispatch(t_target)
    if _Console.cpu is not None or _Console.debt_ns >= 1000:
        return _released_owed(t_target, watch)
    # (_released_run_until's usual case, inline: one call less a wait)
    _Link.heap_lock()
    depth = _Link.heap_unlock()  # (heap_release's: the firmware's lock depth)
    if depth:
        return _released_locked(t_target, watch, depth, True)
    hit = _run_until(t_target, watch)
    if _Link.spent:
        keep_reserve()
    return hit


def run_until_woken(watch=None):
    """Sleep until a wake source: an IRQ handler or a Timer callback has run (with
    `watch`, IRQs off: until one of those pins changed). machine.lightsleep()/deepsleep()
    without a time; with no wake source at all, to the end of the run, as a board sleeps."""
    if watch:
        while not run_until(FOREVER_US, watch):
            pass
        return
    ran = _Link.callbacks
    _link.woke = lambda: _Link.callbacks != ran
    try:
        run_until(FOREVER_US)
    finally:
        _link.woke = None


def _released_run_until(t_target, watch):
    if _Console.cpu is not None or _Console.debt_ns >= 1000:
        return _released_owed(t_target, watch)
    # (the usual case, with a frame of its own small enough for the C stack)
    depth = heap_release()
    if depth:
        return _released_locked(t_target, watch, depth)
    hit = _run_until(t_target, watch)
    if _Link.spent:
        keep_reserve()
    return hit


def _released_locked(t_target, watch, depth, locked=False):
    if locked:  # (the rest of heap_release: the firmware's lock let go)
        for _ in range(depth):
            _Link.heap_unlock()
    try:
        return _run_until(t_target, watch)
    finally:
        if _Link.spent:
            keep_reserve()
        heap_restore(depth)


def _released_owed(t_target, watch):
    """_released_run_until with MCU time, or a print's time owed first."""
    if _Console.cpu is not None:
        _charge_cpu()  # (the wait begins once the compute before it is done)
    if _Console.debt_ns >= 1000:
        # print() blocked this long before the firmware read the clock or began this wait:
        # the wait ends that much later (one exchange with the host, stamped at the print).
        owed = _console_owed_us()
        if _Console.irq is not None and not _dispatching:  # MCU time: the callbacks preempt it
            t0 = _now
            _preempted_until(_now + owed)
            if t_target < FOREVER_US:
                t_target += _now - t0
        else:
            if watch:  # an input that changes meanwhile is seen once the print has returned
                _released_run_until(_now + owed, None)
            if t_target < FOREVER_US:
                t_target += owed
    depth = heap_release()
    run = _run_until if _Console.cpu is None else _run_until_idle
    if not depth:
        hit = run(t_target, watch)
        if _Link.spent:
            keep_reserve()
        return hit
    try:
        return run(t_target, watch)
    finally:
        if _Link.spent:
            keep_reserve()
        heap_restore(depth)


# A firmware may fill its heap, catch the MemoryError and go on: on a board its sleeps, pin
# and ADC reads, prints and soft IRQs allocate nothing (py/scheduler.c keeps scheduled
# callbacks in a fixed queue; ports/esp32/mphalport.c and ports/unix/unix_mphal.c wait
# without the heap), and py/gc.c's gc_alloc collects and tries once more before
# py/runtime.c's m_malloc_fail raises. The shim's link work does allocate (frames, the
# callbacks' queue), so it keeps a reserve the firmware never gets: before its own
# allocations it checks for room (make_room), lets the reserve go when there is none (the
# collect gives it back to the heap), and takes it again once its work is garbage
# (keep_reserve). The reserve is in pieces, so that what the shim keeps between waits (the
# decoder's bytes, its lists) cannot stop it coming back. Measured: a wait with its
# exchanges, timer callbacks and IRQs allocates at most 2.2K, most of it garbage before
# the rest is needed; the link reads into a buffer of its own (its read, in _Link.__init__).
ROOM_BYTES = 1024  # free heap, in one piece, an exchange's work needs at once
# held back from the firmware, in the shim's share of the heap (host/rig/targets/heap.py): the
# first piece holds the longest frame (_hilframe.MAX_PAYLOAD), the link's own allocations
# take the reserve when one fails
RESERVE_PIECES = (4096 + 256, 1024, 1024, 512, 512)


def make_room():
    """Before the shim allocates: when the firmware has left less than ROOM_BYTES, the
    reserve goes back to the heap. (The probe is garbage at once.)"""
    try:
        bytearray(ROOM_BYTES)
    except MemoryError:
        spend_reserve()


def spend_reserve():
    """The reserve back to the heap (for the shim's work, or the firmware's last words)."""
    pieces = _Link.reserve
    for i in range(len(pieces)):
        pieces[i] = None
    _Link.spent = True
    _Link.collect()


def keep_reserve():
    """The reserve taken again, once the shim's work is garbage (what the firmware, or a
    callback of its, holds meanwhile is not taken: the rest at the next wait)."""
    pieces = _Link.reserve
    for i in range(len(pieces)):
        if pieces[i] is None:
            try:
                pieces[i] = bytearray(RESERVE_PIECES[i])
            except MemoryError:
                return
    _Link.spent = False


def heap_release():
    """Under micropython.heap_lock(): a board's sleep or poll allocates nothing, the shim's
    link work does, so the shim unlocks the heap around its own work (and heap_restore
    locks it again). Returns the firmware's lock depth (0: not locked, nothing done)."""
    lock, unlock = _Link.heap_lock, _Link.heap_unlock
    lock()
    depth = unlock()  # (heap_unlock returns the depth left: here, the firmware's)
    for _ in range(depth):
        unlock()
    return depth


def heap_restore(depth):
    """The firmware's heap lock back, as heap_release found it."""
    lock = _Link.heap_lock
    for _ in range(depth):
        lock()


def _run_until(t_target, watch):
    global _now
    t_pass = FOREVER_US  # the wait's next pass, while callbacks queue more callbacks (dispatch)
    while True:
        t_stop = t_target if t_target < _timer_due else _timer_due
        if t_pass < t_stop:
            t_stop = t_pass
        t = now()
        if t_stop < _horizon or (t_stop <= t and not (_link.zero and t == _horizon)):
            if t_stop > t:
                if _lockstep:
                    _now = t_stop
                else:
                    _rtime.sleep_us(t_stop - t)
                    now()
            hit = False
        elif _Link.held:
            hit = _apply_held(watch)
        else:
            if _Link.ahead:  # no input change before the horizon: wait from just before it
                _Link.ahead = False  # (the host's plant may be up to there, past a lookahead)
                if _lockstep and _now < _horizon - 1:
                    _now = _horizon - 1
            hit = _sync(t_stop, watch)
        if _timer_due <= _now:
            _fire_timers()
        if _pending:
            dispatch(_Link.until)
            if _link.woke is not None and _link.woke():
                return True
            if _pending:
                t_pass = _next_pass()
            else:
                t_pass = FOREVER_US
                _Link.passes = 0
        else:
            t_pass = FOREVER_US
        if hit:
            return True
        if _now >= t_target and (_horizon > _now or not _link.zero):
            return False


def _next_pass():
    """When the wait handles events again for the callbacks still queued (those queued by
    the ones that ran: dispatch): a board's wait runs them at its next passes, at once;
    past SPIN_LIMIT passes in a row with callbacks queued by callbacks, each further one
    costs SPIN_STEP_US, as a spinning read does (a callback that queues itself again until
    the clock moves: a board's passes take its CPU's time). Never, when they wait for
    something else (the wait's end, a C call, IRQs off, the callbacks' MCU time past the
    wait's end)."""
    until = _Link.until
    if _now >= until or _now >= _Link.defer_from or _irq_off or _dispatching:
        return FOREVER_US
    if _Console.busy is not None and _Console.busy() > until:
        return FOREVER_US
    _Link.passes += 1
    return _now + SPIN_STEP_US if _Link.passes > SPIN_LIMIT else _now


def _preempted_until(t_end):
    """MCU time: the main program computes (or print() blocks) until t_end; a callback that
    fires meanwhile (a hard IRQ's handler, a Timer's) preempts it for its own compute, so
    that it ends that much later, and so on for those that fire in that extra time."""
    irq = _Console.irq()
    wait_end = _Link.until
    while True:
        _Link.until = t_end  # (the firmware runs meanwhile: its branches run the callbacks due)
        _released_run_until(t_end, None)
        more = _Console.irq() - irq
        if more <= 0:
            _Link.until = wait_end
            return
        irq += more
        t_end += more


def _run_until_idle(t_target, watch):
    """_run_until, then on until the callbacks run on the way are done (MCU time: the
    main program goes on once their compute is, _Console.busy)."""
    hit = _run_until(t_target, watch)
    busy = _Console.busy()
    while busy > _now:
        if busy > min(_now, t_target) + BEHIND_US and not _Console.behind:  # (ahead of the clock, or of
            # the wait's end: the main program held that long)
            _Console.behind = True  # (said once: the handlers go on taking all the CPU)
            sys.stderr.write(
                "mpy-fil: at t=%d us the callbacks' compute keeps the CPU busy until t=%d us"
                " (the main program's wait was to end at t=%d us): the board would fall behind\n"
                % (_now, busy, t_target)
            )
        _run_until(busy, None)
        busy = _Console.busy()
    return hit


def _sync(t_until, watch):
    # (Each function on this path keeps its locals and its stack within the C stack's frame,
    # py/objfun.c VM_MAX_STATE_ON_STACK, 11 words: a larger one is a heap block an exchange.)
    c = _Link.c
    if c is None:
        make_room()
        return _sync_py(t_until, watch, _compute_us())
    if not c.room(ROOM_BYTES):  # (make_room's probe, given back at once)
        spend_reserve()
    _Link.syncs += 1
    if _Link.threads is None and _Link.thread() != _Link.main_thread:
        raise RuntimeError("a second thread waits in virtual time: the loop runs one thread of control (docs/shim.md)")
    # the WAIT, the STATE's frame and its decoding in C (_hilfast.link)
    _Link.frames += 1
    if _link.queue is not _link.own_queue:  # (a line the host runs at a pause may not wait: _hilrepl refuses)
        _link.queue(F.WAIT, b"")
    # (waits here for the host: host/rig/targets/target.py, WAITING_ON_LINK)
    frame = c.exchange(t_until, _compute_us(), watch)
    if frame is not None:  # (-1: a frame of another kind not taken for want of memory)
        _link.other(c, frame, _now)
    _woke()
    hdr = _Link.hdr
    if not hdr[3] and not c.has_edges():  # (nothing to apply: what either loop ends with)
        _finish_state(None, hdr[1], hdr[2])
        return False
    if _dispatching or _irq_off:  # (as below: the pure loop)
        return _pure_apply(c, watch)
    return _c_apply(c, watch)


def _pure_apply(c, watch):
    """The held STATE applied by the pure loop (inside a callback, with IRQs off)."""
    hdr = _Link.hdr
    return _apply_state(c.state(), hdr[0], hdr[1], hdr[2], hdr[3], watch, c.edges())


def _compute_us():
    """The firmware's compute since the last STATE woke it (MCU time: its board's)."""
    if _Console.cpu is None:
        compute_us = _rtime.ticks_diff(_rtime.ticks_us(), _wake_real_us)
    else:
        compute_us = _mcu_compute()
    return compute_us if compute_us > 0 else 0


def _woke():
    """A STATE came (the C link's): the bus image that came with it in use, the clock's marks."""
    global _wake_real_us, _spin, _rt_origin_us
    # (a class attribute's store costs some 700 instructions: none where nothing changes)
    if _Link.image_next is not _NO_IMAGE or _Link.image is not _NO_IMAGE:
        _Link.image, _Link.image_next = _Link.image_next, _NO_IMAGE
    if _Link.done:
        _Link.done = 0  # (the reads it answered went with the WAIT)
    _wake_real_us = _rtime.ticks_us()
    if not _lockstep:  # real time: the STATE ends in the µs the host paused (docs/clock.md)
        _rt_origin_us = _rtime.ticks_add(_rt_origin_us, _Link.hdr[4])
    _spin = 0


def _c_apply(c, watch):
    """The held STATE applied in C (_hilfast.link's run: apply_state's loop)."""
    cur = _Link.cur
    stop = c.run(watch, _Link.pin)
    if stop:
        return cur[2] or stop == 2
    hdr = _Link.hdr
    if cur[1] < hdr[3]:  # changes past its end (the host's lookahead): held
        _finish_state(_held_rest(c, cur, hdr), hdr[1], hdr[2])
    else:
        _finish_state(None, hdr[1], hdr[2])
    return cur[2]


def _held_rest(c, cur, hdr):
    return F.unpack_changes(c.state(), cur[0], hdr[0], hdr[3] - cur[1], [])


def _sync_py(t_until, watch, compute_us):
    """_sync's exchange through the link's Python (a user's own interpreter, HIL_PURE)."""
    global _wake_real_us, _spin, _rt_origin_us
    # F.pack_wait and F.unpack_state, inline, with the codec's layouts in locals: this runs
    # once per wake. (No module globals for them: more globals here slow every lookup.)
    state_fmt = F.STATE_FMT
    payload = struct.pack(F.WAIT_FMT, _now, t_until, compute_us)
    if watch:
        for h in watch:
            payload += struct.pack(F.WATCH_FMT, h)
    p = _link.exchange(payload, _now, state_fmt)
    _wake_real_us = _rtime.ticks_us()
    if not _lockstep:  # real time: the STATE ends in the µs the host paused, which this clock skips (docs/clock.md)
        _rt_origin_us = _rtime.ticks_add(_rt_origin_us, struct.unpack_from("<Q", p, len(p) - 8)[0])
    _spin = 0  # new inputs: handlers and main start reading the clock afresh
    base, t_end, horizon, n = struct.unpack_from(state_fmt, p, 0)
    fast = _Link.fast
    edges = _Link.edges
    if edges is not None:
        _Link.edges = None
        if struct.unpack_from(F.EDGES_FMT, edges, 0)[0] != base:  # (not this STATE's: never acted on)
            edges = None
    if fast is None or _dispatching or _irq_off or (edges and not _Link.fast_edges):
        # (inside a callback, with IRQs off or in a C call: only the pure path keeps soft
        # callbacks waiting and the queue bounded; _hilfast runs them all, as dispatch does outside)
        return _apply_state(p, base, t_end, horizon, n, watch, edges)
    # the same as _apply_state, in C (host/shim/cmod/_hilfast)
    cur = [F.STATE_LEN, 0, False]
    if edges is None:
        stop = fast(p, cur, base, t_end, n, _handles, _Link.pin, _pending, watch, _Link.ctx, _Link.g)
    else:
        stop = fast(p, cur, base, t_end, n, _handles, _Link.pin, _pending, watch, _Link.ctx, _Link.g, edges)
    if stop:
        return cur[2] or stop == 2
    i = cur[1]
    _finish_state(F.unpack_changes(p, cur[0], base, n - i, []) if i < n else None, t_end, horizon)
    return cur[2]


def _apply_state(p, base, t_end, horizon, n, watch, edges=None):
    """A STATE's changes applied in time order, the handlers due at each instant run before
    the next (the pure-Python path; _hilfast.apply_state does the same in C). ``edges``: the
    EDGES that came with it, whose encoder edges (all up to t_end) merge with its changes:
    its segments' edges (F.expand_edges) and the changes in time order, at one instant the
    edges first (the plant emits an instant's encoder edges before its other parts' changes)."""
    changes = F.unpack_changes(p, F.STATE_LEN, base, n, [])
    if edges is not None and _Link.merge is not None:  # (the same in C: _hilfast.merge_edges)
        changes = _Link.merge(edges, base, changes)
    elif edges is not None:
        changes = F.merge_edges(F.unpack_edges(edges)[1], changes)
    return _apply_changes(changes, t_end, horizon, watch)


def _apply_changes(changes, t_end, horizon, watch):
    """Changes (t, handle, kind, value, extra) applied in order up to t_end, the handlers
    due at each instant run before the next; those past t_end held."""
    global _now
    hit = False
    group_t = -1
    held = None
    handles, pending = _handles, _pending
    for i, (t, h, kind, value, extra) in enumerate(changes):
        if t > t_end:  # past the wake (the host's lookahead): held, applied as the clock passes it
            held = changes[i:]
            break
        if t != group_t:
            if pending and group_t >= 0:
                stop = _handlers_wrote(group_t)
                if stop:
                    return hit or stop == 2
            group_t = t
            if _lockstep:
                _now = t
        handles[h]._hil_apply(kind, value, extra)
        if watch and h in watch:
            hit = True
    if _pending and group_t >= 0:
        stop = _handlers_wrote(group_t)
        if stop:
            return hit or stop == 2
    _finish_state(held, t_end, horizon)
    return hit


def _finish_state(held, t_end, horizon):
    """A STATE applied up to its end: the clock at t_end, the changes past it held."""
    global _now
    if _lockstep:
        _now = t_end
    else:
        now()
    _hold(held, horizon)


def _hold(held, horizon):
    """After a STATE: the changes past its end held, the horizon the first of them (or the host's)."""
    global _horizon
    if _Link.ahead is not _lockstep:
        _Link.ahead = _lockstep
    if held:
        _Link.held = held
        _Link.after = horizon
        _horizon = held[0][0]
    else:
        _horizon = horizon


def _apply_held(watch):
    """The next held changes (those of one instant), applied at their time with their
    handlers, as _sync applies a STATE's; True when a watched input changed (or a handler
    made a polled stream ready)."""
    global _now, _horizon, _wake_real_us, _spin
    held = _Link.held
    t0 = held[0][0]
    if _lockstep:
        _now = t0
    _wake_real_us = _rtime.ticks_us()
    _spin = 0
    hit = False
    i = 0
    for t, h, kind, value, extra in held:
        if t != t0:
            break
        _handles[h]._hil_apply(kind, value, extra)
        if watch and h in watch:
            hit = True
        i += 1
    del held[:i]
    _horizon = held[0][0] if held else _Link.after
    if _pending:
        stop = _handlers_wrote(t0)
        if stop:
            return hit or stop == 2
    return hit


def _handlers_wrote(t):
    """Run the handlers due at time t. If they changed an output, the rest of the batch
    (computed by the host for the old outputs) is void: stay at t and resync (1). If they
    made a polled stream ready (a ThreadSafeFlag set from an IRQ), the poll wakes at t
    and the rest of the batch is void too (2). If a handler blocked (slept), its own
    exchanges moved time on past this batch: the rest of it is stale (3). 0: carry on."""
    global _wrote, _now, _horizon
    _wrote = False
    syncs = _Link.syncs
    dispatch(_Link.until)
    if _Link.syncs != syncs:
        return 3
    woke = _link.woke is not None and _link.woke()
    if _wrote or woke:
        if _lockstep:
            _now = t
        _horizon = _now
        return 2 if woke else 1
    return 0


# -- callbacks: IRQ handlers and Timer callbacks ------------------------------------


# As MicroPython's scheduler (py/scheduler.c): a soft callback (a Timer's, a Pin IRQ's
# without hard=True, micropython.schedule's) waits in a queue of Link.depth entries until
# the firmware is back at a bytecode boundary or in a wait that handles events; a hard
# IRQ's handler (Pin.irq(hard=True), on the port shared/runtime/mpirq.c, mp_irq_handler)
# runs at its edge, even inside a C call or another callback. The queue's entries are
# (callback, argument); an argument whose _hard is true is a hard IRQ's, never counted.


def _is_hard(arg):
    return getattr(arg, "_hard", False)


def room():
    """mp_sched_full's negation: the queue holds fewer than Link.depth soft callbacks."""
    pending = _pending
    if len(pending) < _Link.depth:
        return True
    n = 0
    for _cb, arg in pending:
        if not _is_hard(arg):
            n += 1
    return n < _Link.depth


def _queue(callback, arg):
    """py/scheduler.c, mp_sched_schedule: queue a soft callback; False, and nothing
    queued, when the queue is full."""
    if len(_pending) < _Link.depth or _is_hard(arg) or room():
        _pending.append((callback, arg))
        return True
    return False


def schedule(callback, arg):
    """A Timer's or an IRQ's call queued (_queue). A port's Timer and IRQ handlers ignore
    a full queue (ports/rp2/machine_timer.c alarm_callback, ports/esp32/machine_timer.c
    machine_timer_isr, shared/runtime/mpirq.c mp_irq_handler): the call is lost (_lost)."""
    if not _queue(callback, arg):
        _lost(callback)


def _lost(callback):
    """A soft callback not queued: the queue was full. Said once a run: on a board too the
    callbacks come faster than the firmware runs them, and their calls are lost."""
    if not _Link.lost:
        _Link.lost = True
        sys.stderr.write(
            "mpy-fil: at t=%d us a call of %s was lost: the scheduler's queue held %d callbacks"
            " (they come faster than they run: the board would fall behind; docs/shim.md)\n"
            % (_now, getattr(callback, "__name__", "a callback"), _Link.depth)
        )


def mp_schedule(function, arg):
    """micropython.schedule (py/modmicropython.c, mp_micropython_schedule): RuntimeError
    when the queue is full. Called from the main program, the callback runs at the next
    branch (_leftovers); from a callback or a hard IRQ's handler, once the
    running callbacks are done (the scheduler is locked meanwhile, as on the port)."""
    # (the port's queue is a fixed array: from a hard handler, the heap locked, it allocates nothing)
    depth = heap_release()
    queued = _queue(function, arg)
    heap_restore(depth)
    if not queued:  # (the firmware hears of it: no lost call to say)
        raise RuntimeError("schedule queue full")
    if not _dispatching:
        _leftovers()
    elif _now < _Link.until and _now < _Link.defer_from and not _irq_off:
        # from a callback run in a wait that handles events: the wait's next pass runs it at
        # this instant (ports/rp2/mphalport.c, mp_hal_delay_ms: mp_event_wait_ms, then
        # mp_handle_pending again), so the rest of the STATE being applied waits, as after
        # an output (_handlers_wrote: 1); it ran at the STATE's next change or end
        global _wrote
        _wrote = True


def dispatch(until, one=False, drain=False):
    """Run the pending callbacks in order, never re-entrantly, unless IRQs are off: every
    hard IRQ's handler, and the soft callbacks as the port's scheduler runs them, one a
    pending check (py/scheduler.c, mp_sched_run_pending: "Run at most one pending Python
    callback", in 1.25 to 1.28). A check outside a wait (`one`: the firmware's next
    branch, py/vm.c, _at_branch) runs one. A wait handles events again as
    long as its time is not up (`until`, its end: the ports' mp_hal_delay_ms loops on
    mp_event_wait_ms), so there the next one runs, and so on, until the queue is empty or
    a callback has taken the clock (or, with MCU time, the callbacks' compute) past the
    wait's end: the rest run one at each later check, and a main program whose callbacks
    outlast their period crawls, as on a board. A callback queued by a running one waits
    for the next pass. `drain`: all of them, those queued meanwhile too (_leftovers, on an
    interpreter that cannot see branches). Inside a callback or a C call (from
    Link.defer_from on) only hard IRQs' handlers run: the soft ones wait for the callback
    or the call to return."""
    global _dispatching, _cb_reads
    if _irq_off:
        return
    if _dispatching or _now >= _Link.defer_from:
        if not _Link.hard:
            _run_hard()
        return
    _dispatching = True
    pending, link = _pending, _Link
    wait_end = link.until
    busy = _Console.busy  # (MCU time: the callbacks' compute keeps the CPU busy until then)
    if busy is not None:
        link.irq_begin()  # (what the main program computed before them is its own)
    i = 0
    end = len(pending)  # (those a callback queues run at the next pass: py/scheduler.c, one a check)
    try:
        while i < end or (drain and i < len(pending)):
            callback, arg = pending[i]
            if (_now > until or (busy is not None and busy() > until)) and not _is_hard(arg):
                if not one:  # (past the wait's end, or not in one; or this check's one has run)
                    i += 1
                    continue
                one = False
            del pending[i]
            end -= 1
            link.callbacks += 1
            _cb_reads = _HELD if _is_hard(arg) else 0
            try:
                callback(arg)
            except Exception as e:  # (a reset, a host stop: BaseExceptions, go through)
                raise CallbackFailed(callback, e)  # noqa: B904  (MicroPython warns on "from")
            if busy is not None:  # (each one's compute from its instant or the end of the one before)
                link.irq_end(_now)
                link.irq_begin()
    finally:
        _dispatching = False
        link.until = wait_end  # (a callback's own wait set it)
        if busy is not None:
            link.irq_end(_now)
    if pending and link.arm is not None:
        link.arm(_at_branch)


def _leftovers():
    """The callbacks left queued (by a C call, a wait whose time was up, a check that ran
    one), at a point where a board does not run them: with the harness's build, at the
    firmware's next bytecode branches, one a branch, as the port's VM does (_hilfast.arm,
    py/vm.c pending_exception_check); on another interpreter, which cannot see branches,
    all of them now, at the firmware's call into the shim (docs/shim.md)."""
    arm = _Link.arm
    if arm is None:
        dispatch(FOREVER_US, drain=True)
    else:
        arm(_at_branch)


def _at_branch():
    """A branch of the firmware's (_hilfast.arm): one queued soft callback runs, unless
    the branch is inside a callback or what is a C call on a board (then the next one)."""
    if _dispatching or _now >= _Link.defer_from:
        _Link.arm(_at_branch)
    elif _pending:
        dispatch(-1, True)


def _run_hard():
    """The hard IRQs' handlers in the queue, in order (the soft callbacks stay)."""
    pending = _pending
    i = 0
    while i < len(pending):
        callback, arg = pending[i]
        if not _is_hard(arg):
            i += 1
            continue
        del pending[i]
        run_hard_now(callback, arg)


def hard_handler(handler):
    """A hard IRQ's (or hard Timer's) handler as the port runs it (shared/runtime/mpirq.c,
    mp_irq_handler: gc_lock() around the call): the heap locked, so what would allocate on a
    board raises MemoryError here too (a float, a list grown, a string made). The shim's own
    work inside it (a pin read or write, a clock read) allocates nothing, or unlocks as it
    does under the firmware's own heap_lock. A failure names the firmware's handler. (Made
    once, where the handler is set: the call itself allocates nothing.) Not on the pure path
    (HIL_PURE, an interpreter without _hilfast), whose outputs allocate: there unlocked."""

    def hard(arg):
        lock = _Link.c is not None  # (the pure path, a user's own interpreter: its outputs allocate, so unlocked)
        if lock:
            _Link.heap_lock()
        try:
            handler(arg)
        except Exception as e:
            if lock:  # (the traceback's printing allocates: a board prints it unlocked too)
                _Link.heap_unlock()
            raise CallbackFailed(handler, e)  # noqa: B904  (MicroPython warns on "from")
        if lock:
            _Link.heap_unlock()

    return hard


def run_hard_now(callback, arg):
    """A hard IRQ's handler run now (_run_hard's, one at a time; an I2CTarget's request,
    whose answer the controller reads, inside what the port's interrupt does)."""
    global _dispatching, _cb_reads
    was, reads = _dispatching, _cb_reads
    _Link.callbacks += 1
    _Link.hard = _dispatching = True  # (its reads move no time: _callback_read)
    _cb_reads = _HELD
    try:
        callback(arg)
    except Exception as e:
        raise CallbackFailed(callback, e)  # noqa: B904
    finally:
        _Link.hard = False
        _dispatching, _cb_reads = was, reads


def c_begin(since):
    """The firmware enters what is a C function of the port that waits without running
    scheduled callbacks (time_pulse_us's busy loop, a bus transfer, the end of sleep_us):
    soft callbacks that come from virtual time ``since`` on stay queued (timers still come
    due and queue at their times, as a board's hardware timer does) until c_end; they run
    at the firmware's next branches, one a branch, as on a board (py/vm.c,
    pending_exception_check; _leftovers), or in its next wait. Hard IRQs' handlers run at
    their edges meanwhile. Returns what c_end takes (no allocation: this works under micropython.heap_lock())."""
    if _pending:
        _leftovers()
    prev = _Link.defer_from
    if since < prev:
        _Link.defer_from = since
    return prev


def c_end(prev):
    """The C function has returned (c_begin's result; in a finally)."""
    _Link.defer_from = prev
    if _pending and _Link.arm is not None:
        _Link.arm(_at_branch)


def disable_irq():
    global _irq_off
    state = _irq_off
    _irq_off = 1
    return state


def enable_irq(state=0):
    global _irq_off
    _irq_off = state
    if not state and _pending:
        _leftovers()


def add_timer(timer):
    if timer not in _timers:
        _timers.append(timer)
    _update_timer_due()


def remove_timer(timer):
    if timer in _timers:
        _timers.remove(timer)
    _update_timer_due()


def _update_timer_due():
    global _timer_due
    due = F.FOREVER_US
    for tm in _timers:
        if tm._due < due:
            due = tm._due
    _timer_due = due


def _fire_timers():
    make_room()  # (the copy, the queue's entries)
    for tm in list(_timers):
        if tm._due <= _now:
            schedule(tm._callback, tm)
            if tm._period_us:
                tm._due += tm._period_us
            else:
                _timers.remove(tm)
    _update_timer_due()


# -- start and end --------------------------------------------------------------


def start():
    """Open the link (the pty in HIL_LINK, else the board's console) and shake hands."""
    global _link, mode, _lockstep, _now, _horizon, now, _wake_real_us, _rt_origin_us
    getenv = getattr(os, "getenv", None)  # boards have no environment
    path = getenv("HIL_LINK") if getenv else None
    _link = _Link(path) if path else _StdioLink()
    info = "%s;%s" % (".".join(str(v) for v in sys.implementation.version[:3]), sys.implementation._machine)
    send(F.HELLO, F.pack_hello(info.encode()))
    _link.flush()
    type_, _seq, p = _link.recv()
    if type_ != F.WELCOME:
        raise OSError("expected WELCOME from the host, got type 0x%02x" % type_)
    if struct.unpack_from("<H", p, 0)[0] != F.PROTO_VERSION:
        raise OSError(
            "host speaks link protocol %d, shim speaks %d" % (struct.unpack_from("<H", p, 0)[0], F.PROTO_VERSION)
        )
    _proto, mode, t_start, flags, settings = F.unpack_welcome(p)
    p = None
    _Link.settings = settings
    _Link.zero = bool(flags & F.WELCOME_ZERO_DELAY)
    import _hilsys  # the board's sys (sys.platform, _machine when the host names it), os, micropython

    identity = settings["identity"]
    board = identity.decode().split(";", 1) if identity else ()
    baud = settings["console_baud"]  # (0 on a board: its own UART pays)
    console_setup(baud, 32 if board and board[0] == "rp2" else 128)  # the UART's TX FIFO
    _hilsys.install(said, baud > 0, *board)
    _now = t_start
    _horizon = t_start
    _wake_real_us = _rtime.ticks_us()
    _lockstep = mode == F.MODE_LOCKSTEP
    if mode == F.MODE_REALTIME:
        _rt_origin_us = _rtime.ticks_add(_rtime.ticks_us(), -t_start)
        now = _realtime_now
    # The u-prefixed names resolve to the built-ins before any file on the path; in
    # sys.modules they are the shim's, as utime is time on a board. (Locals, not module
    # globals: more globals here slow every global lookup of the hot paths.)
    import gc
    import micropython

    _Link.heap_lock, _Link.heap_unlock = micropython.heap_lock, micropython.heap_unlock
    _Link.collect = gc.collect
    _Link.reserve = [None] * len(RESERVE_PIECES)  # (taken by _hilboot once the shim has imported all it keeps)
    try:
        import _thread

        _Link.thread = _thread.get_ident
    except ImportError:  # a board without threads
        _Link.thread = int
    _Link.main_thread = _Link.thread()
    _Link.fast = _fast_path(getenv)
    import select as shim_select  # (asyncio imports both anyway)
    import time as shim_time

    import _umachine

    sys.modules["umachine"] = _umachine
    sys.modules["uselect"] = shim_select
    sys.modules["utime"] = shim_time


def _fast_path(getenv):
    """The C loop of a STATE's changes, or None: not in this interpreter, or HIL_PURE set."""
    if getenv and getenv("HIL_PURE"):
        return None
    try:
        import _hilfast
    except ImportError:
        return None
    _Link.g = globals() if _lockstep else None
    _Link.ctx = (globals(), _Link, CallbackFailed)
    if hasattr(_hilfast, "arm"):  # (a build before it: the queue runs at the next call in)
        _exempt(_hilfast)
        _Link.arm = _hilfast.arm
    if hasattr(_hilfast, "branches"):  # (a loop that calls nothing of the board's)
        _Link.branches = _branches  # (held here too: _hilfast's reference is no root)
        _hilfast.branches(_branches, BRANCHES)
    _Link.fast_edges = hasattr(_hilfast, "EDGES_MAX")  # (apply_state expands an EDGES itself)
    _Link.merge = getattr(_hilfast, "merge_edges", None)
    _Link.roomy = getattr(_hilfast, "roomy", None)
    if hasattr(_hilfast, "pin_value"):  # (machine.Pin.value in C: machine.py installs it)
        _Link.pin_setup, _Link.pin_value = _hilfast.pin_setup, _hilfast.pin_value
    if _Link.c is not None:
        _Link.c.bind(_Link.hdr, _Link.cur, _handles, _pending, _Link.ctx, _Link.g, globals())
        _Link.out = True
    # (a build before "defers" runs every soft callback in apply_state's dispatch, in a C call too)
    return _hilfast.apply_state if hasattr(_hilfast, "defers") else None


def _exempt(fast):
    """The shim's modules are the harness's, not the firmware's (a board has them in C):
    their branches are no pending checks (_hilfast.arm) and their work no MCU time."""
    # the shim's folder as its modules were compiled (this function's own file: before the
    # sandbox, _hilconfine) and as they are now (imported later)
    fast.exempt(fast.stack(True)[-1][0].rsplit("/", 1)[0] + "/")
    fast.exempt(__file__.rsplit("/", 1)[0] + "/")
    fast.exempt("/_hil/")  # (the folder the sandbox shows them in: _hilconfine)
    fast.exempt("asyncio/task.py")  # (the task queue a board has in C, _asyncio: frozen here, _hilboot)


def finish(kind, code=0, text=None):
    """Tell the host the firmware ended (returned, reset, exited or raised)."""
    if _link is None:
        return
    if _Link.reserve is not None:
        spend_reserve()  # (the firmware may have left no room for the last frames)
    if _Console.runs:  # (MCU time: the compute before the waits served since the last exchange)
        _send_runs(_Console.runs)
        _Console.runs = []
    if text is not None:
        send(F.FAULT, F.pack_fault(now(), text.encode()))
    if isinstance(_link, _StdioLink):
        _link.close()  # Ctrl-C works again before the host sees EXIT
    send(F.EXIT, F.pack_exit(now(), kind, code))
    _link.flush()
    if _Link.threads is not None:  # (the firmware's other threads end with it: _hilthread.end)
        _Link.threads.end()

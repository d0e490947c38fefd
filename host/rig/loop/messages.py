"""The messages the shim sends, each to its function: ``on_<name>(rig, payload)`` for the
frame types in :data:`HANDLERS` (``docs/protocol.md``), called by :meth:`Rig.dispatch
<host.rig.loop.rig.Rig.dispatch>` with the payload's bytes."""

from host.artefacts.linklog import NO_LOG
from host.link import frames as F
from host.rig.hardware import peripherals
from host.rig.hardware.pollwatch import shim_poll_text
from host.rig.loop import endings
from host.shim._hilpio import unpack_pio_done

_NO_WATCH = frozenset()


def on_out(rig, p: bytes) -> None:
    t, h, attr, value = F.unpack_out(p)
    if t != rig.plant.t_us:
        rig.clock.catch_up(t)
    if rig.linklog is not NO_LOG:  # (not recorded: no call at each message)
        rig.linklog.out(t, h, attr, value)
    info = rig.wiring.handles[h]  # (the handle's kind's handler applies it: Outputs' module doc)
    info.peripheral.out(rig.outputs, t, info, attr, value)


def on_wait(rig, p: bytes) -> None:
    if len(p) < F.WAIT_NO_WATCH_BELOW:  # (the usual WAIT: no handle watched)
        t_now, t_until, compute_us = F.unpack_wait_head(p)
        watch = _NO_WATCH
    else:
        t_now, t_until, compute_us, watch = F.unpack_wait(p)
        watch = frozenset(watch) if watch else _NO_WATCH
    rig.clock.block(t_now, t_until, watch)
    if rig.console_log.pending:
        rig.console_log.stamp(t_now)
    for call in rig._compute_hooks:
        call(compute_us)
    if rig.cpu_load is not None:  # (MCU time: the firmware's CPU load, docs/mcu-time.md)
        rig.cpu_load.wait(t_now, compute_us)
    if rig.linklog is not NO_LOG:  # (not recorded: no call at each message)
        rig.linklog.wait(t_now, t_until, watch)


def on_cfg(rig, p: bytes) -> None:
    """A CFG at its instant ``t``: the plant brought to it first (as for an OUT), so that
    a pin made an input on a line the plant drives too lets it go then, to the µs."""
    t, h, kind, mode, pull, param, name = F.unpack_cfg(p)
    if t != rig.plant.t_us:
        rig.clock.catch_up(t)
    key = name.decode()
    rig.linklog.cfg(t, h, peripherals.name_of(kind), key, mode, pull, param, rig.wiring.signal_of(key))
    info = rig.wiring.configure(h, kind, mode, pull, key, param)
    if rig.wiring.lets_go(info):
        rig.plant.set_input(info.signal, peripherals.RELEASED)
    if info is not None and info.is_input:
        rig.inputs.sync(t, h, info, rig.plant)


def on_seen(rig, p: bytes) -> None:
    t, h, sample_no = F.unpack_seen(p)  # (the host's compiled form: host/link/frames.py)
    rig.speculation.commit(t)
    for call in rig._seen_hooks.get(rig.wiring.handles[h].signal, ()):
        call(t, sample_no)
    if rig.linklog is not NO_LOG:  # (not recorded: no call at each message)
        rig.linklog.seen(t, h, sample_no)


def on_uart_tx(rig, p: bytes) -> None:
    t, h = F.unpack_uart_tx_head(p)  # (F.unpack_uart_tx)
    data = bytes(p[F.UART_TX_LEN :])
    rig.clock.catch_up(t)
    info = rig.wiring.handles[h]
    info.peripheral.transmit(rig.outputs, t, info, data)
    if rig.linklog is not NO_LOG:
        rig.linklog.uart_tx(t, h, data)


def on_bus(rig, p: bytes) -> None:
    """A bus transfer: answered at once from the devices as the plant is at its instant."""
    t, h, op, address, n_read, data = F.unpack_bus(p)
    rig.clock.catch_up(t)
    rig.stats.bus_round_trips += 1
    info = rig.wiring.handles[h]
    unclocked = rig.wiring.unclocked(info.key) if op == F.BUS_SPI_XFER else _NO_WATCH
    trace = rig.bus_trace
    trace.asking = True  # (a poll named here waits for the firmware's stack: BUS_ASK_STACK)
    try:
        status, count, got = trace.answer(rig.plant, info, h, t, op, address, n_read, data, unclocked)
    finally:
        trace.asking = False
    images = rig.bus_images
    lease = rig.clock.lease_us()
    if images.on:
        images.seen(t, h, op, address, n_read, data, status)
        image = images.image(t, lease, (h, op, address, n_read, data))
        if image is not None:
            rig.session.hold(F.BUS_IMAGE, image)
    if info.peripheral.kind == F.CFG_PIO and not rig.pacing.walled:  # (the read's next frames: host.rig.hardware.pio)
        ahead = info.pio.ahead.answer(h, t, int(info.key[2:]), (op, address, n_read, data), (status, count, got), lease)
        if ahead is not None:
            rig.session.hold(F.PIO_AHEAD, ahead)
    ask = F.BUS_ASK_STACK if trace.held_poll is not None else 0
    rig.session.send(F.BUS_REPLY, F.pack_bus_reply_head(t, status | ask, count, lease) + got)  # (F.pack_bus_reply)


def on_bus_done(rig, p: bytes) -> None:
    """A bus read the shim answered from the last BUS_IMAGE: traced as if it were a BUS."""
    t, entry = F.unpack_bus_done(p)
    rig.bus_images.done(rig, t, entry)


def on_pio_done(rig, p: bytes) -> None:
    """A PIO frame the shim answered from the last PIO_AHEAD: played and traced as if it were a BUS."""
    t, sm_id, entry = unpack_pio_done(p)
    rig.wiring.pio.ahead.done(rig, t, sm_id, entry)


def on_i2ct_done(rig, p: bytes) -> None:
    """A controller's transaction on this board's I2CTarget done: what it read, for the set
    of boards that waits for it (``host.rig.loop.boardset``)."""
    t, h, status, acks, got = F.unpack_i2ct_done(p)
    rig.linklog.i2ct_done(t, h, status, acks, got)
    rig._i2ct_done = (status, acks, got)


def on_poll(rig, p: bytes) -> None:
    """The shim names a poll that never ends: a pin, a memory address (host/rig/hardware/pollwatch.py)."""
    poll = F.unpack_poll(p)
    if poll[3] == F.POLL_STACK:  # the firmware's stack for the bus poll the host named
        rig.bus_trace.poll_stack(poll[7])
    elif poll[3] == F.POLL_SPIN and not poll[6]:  # (a loop that moves virtual time: alive, not yet named)
        return
    elif rig.bus_trace.polls.first((poll[3], poll[5])):  # (kind, target): once a run
        rig.bus_trace.say(poll[0], shim_poll_text(poll, rig.wiring, rig.plant))


def on_cpu(rig, p: bytes) -> None:
    """MCU time: the longest compute stretch so far, with the code that ran it (host/rig/targets/mcutime.py)."""
    if rig.cpu_load is not None:
        rig.cpu_load.stretch(*F.unpack_cpu(p))


def on_cpu_runs(rig, p: bytes) -> None:
    """MCU time: the compute before each wait the shim served itself since the last
    exchange, each a value for the compute budgets and a piece of the CPU load."""
    for t_us, compute_us in F.unpack_cpu_runs(p):
        for call in rig._compute_hooks:
            call(compute_us)
        if rig.cpu_load is not None:
            rig.cpu_load.wait(t_us, compute_us)


def on_cpu_irq(rig, p: bytes) -> None:
    """MCU time: the callbacks' compute over a span (host/rig/targets/mcutime.py)."""
    if rig.cpu_load is not None:
        rig.cpu_load.callbacks(*F.unpack_cpu_irq(p))


def on_fault(rig, p: bytes) -> None:
    t, text = F.unpack_fault(p)
    console_until(rig, t)
    rig.linklog.fault(t)
    endings.fault(rig, t, text.decode(errors="replace"))


def on_exit(rig, p: bytes) -> None:
    t, kind, code = F.unpack_exit(p)
    console_until(rig, t)
    rig.linklog.exit(t, kind, code)
    rig.clock.catch_up(t)  # (the firmware may have run ahead alone, within its horizon)
    if kind == F.EXIT_RESET:  # machine.reset(): the board restarts, the plant carries on
        if code != endings.DEEPSLEEP_WAKE:  # (a deep sleep's wake resets by design)
            endings.reset(rig, t)
        rig.restart()
        rig.resets += 1
    else:
        rig.exit_kind, rig.exit_code = kind, code
        endings.exited(rig, t, kind, code)


def console_until(rig, t_us: int) -> None:
    """The firmware ends (or raised) at ``t_us``: what it printed since its last wait was
    printed by then (the console's pipe is read with the link's bytes, before they are
    handled: FdTransport.read_some)."""
    if rig.console_log.pending:
        rig.console_log.stamp(t_us)


HANDLERS = {
    F.OUT: on_out,
    F.WAIT: on_wait,
    F.CFG: on_cfg,
    F.SEEN: on_seen,
    F.UART_TX: on_uart_tx,
    F.FAULT: on_fault,
    F.EXIT: on_exit,
    F.BUS: on_bus,
    F.BUS_DONE: on_bus_done,
    F.PIO_DONE: on_pio_done,
    F.I2CT_DONE: on_i2ct_done,
    F.POLL: on_poll,
    F.CPU: on_cpu,
    F.CPU_IRQ: on_cpu_irq,
    F.CPU_RUNS: on_cpu_runs,
}
"""Frame type -> its handler."""

"""How virtual time relates to the wall clock: one object per clock mode.

:class:`Lockstep` (the default) moves the plant as far as the firmware lets it at once:
to the time it asked to wake, through IRQ edges it batches speculatively, stopping only
where a batch fills, a watched input changes or ground truth is due. Virtual time costs
no wall time. :class:`RealTime` is the same clock held to the wall: it sleeps until each
plant change is due and hands an IRQ edge over at once, so the firmware's real timing
shows. As SimPy's ``RealtimeEnvironment`` is its ``Environment`` with one step
overridden, this is :class:`Lockstep` with its step overridden (``docs/clock.md``).

A pause (the wall time while no run call serves the firmware: between two ``run_for``, or
from the start to the first) is not the firmware's time in real time: the firmware, blocked
in a wait, does not see it pass, and the run call after it takes its own length of wall time
(:meth:`RealTime.resume`, "Pauses" in ``docs/clock.md``).
"""

import struct
import time

from host.link import frames as F
from host.link import spare_core

CHUNK_US = 20_000  # plant advance step while UART bytes flow
BUSY_POLL_S = 0.0005  # lockstep: read the link in a loop this long before sleeping


class Lockstep:
    name = "lockstep"
    code = F.MODE_LOCKSTEP  # the WELCOME's mode byte
    speculates = True  # batches IRQ edges, rewinds when a handler changes an output
    irq_ends_batch = False

    walled = False  # held to the wall clock: pauses are told to the shim (a STATE's trailer)

    def begin(self, t_us: int) -> None:
        """The firmware starts (or restarts) at virtual ``t_us``."""

    def pause(self) -> None:
        """A run call returns: the firmware waits until the next serves it."""

    def resume(self, t_now_us: int, t_plant_us: int) -> None:
        """A run call serves the firmware's wait (blocked at ``t_now_us``, the plant at
        ``t_plant_us``)."""

    def take_trailer(self) -> bytes:
        return b""

    def busy_poll_s(self, allowed: bool = True) -> float:
        """How long to spin on the link before sleeping: only if the front end allows it
        (a campaign's workers, pytest-xdist workers on every core do not) and a core is spare."""
        return BUSY_POLL_S if allowed and spare_core() else 0.0

    def step(self, clock, target_us: int, watch) -> tuple[int, int]:
        """How far the plant goes next toward ``target_us``: (time, change limit or 0).

        A watched wait goes event by event; while UART bytes flow, in chunks (the
        byte-count limit of a batch needs the bytes); otherwise in one go; the plant
        stopping itself once the batch is full (also inside a chunk: a fast output wired
        to an input fills one); both stop at the recorder's truth samples."""
        plant = clock.plant
        if watch:
            return min(plant.next_change_us(), target_us), 0
        if clock.wiring.uart:
            return clock.to_truth(min(plant.t_us + CHUNK_US, target_us)), clock.inputs.room()
        return clock.to_truth(target_us), clock.inputs.room()


class RealTime(Lockstep):
    name = "realtime"
    code = F.MODE_REALTIME
    speculates = False  # (the two clocks differ by the link's latency: nothing to rewind)
    walled = True
    irq_ends_batch = True

    PAUSE_FMT = "<Q"  # a real-time STATE's trailer: the µs of pause since the last one

    def __init__(self):
        self.wall0 = 0.0
        self.paused = False
        self.pause_us = 0  # not yet told to the shim
        self.paused_us = 0  # in all: the wall time the firmware's clock does not count

    def begin(self, t_us: int) -> None:
        self.wall0 = time.monotonic() - t_us / 1e6
        self.paused = True  # (until a run call serves the firmware: its boot is its own time)

    def pause(self) -> None:
        self.paused = True

    def resume(self, t_now_us: int, t_plant_us: int) -> None:
        """The first wait served after a pause: the wall time since the later of where the
        firmware blocked and where the plant stopped is the pause. The clock's origin moves on
        by it, and the STATE that answers the wait tells the shim to move its own."""
        if not self.paused:
            return
        self.paused = False
        pause_us = self.now_us() - max(t_now_us, t_plant_us)
        if pause_us > 0:
            self.wall0 += pause_us / 1e6
            self.pause_us += pause_us
            self.paused_us += pause_us

    def take_trailer(self) -> bytes:
        pause_us, self.pause_us = self.pause_us, 0
        return struct.pack(self.PAUSE_FMT, pause_us)

    def busy_poll_s(self, allowed: bool = True) -> float:
        return 0.0

    def now_us(self) -> int:
        """Virtual time by the wall clock."""
        return int((time.monotonic() - self.wall0) * 1e6)

    def step(self, clock, target_us: int, watch) -> tuple[int, int]:
        t_next = min(clock.plant.next_change_us(), target_us)
        delay = self.wall0 + t_next / 1e6 - time.monotonic()
        if delay > 0:
            time.sleep(delay)
        return t_next, 0


PACINGS = {"lockstep": Lockstep, "realtime": RealTime}

"""How virtual time relates to the wall clock: one object per clock mode.

:class:`Lockstep` (the default) moves the plant as far as the firmware lets it at once:
to the time it asked to wake, through IRQ edges it batches speculatively, stopping only
where a batch fills, a watched input changes or ground truth is due. Virtual time costs
no wall time. :class:`RealTime` is the same clock held to the wall: it sleeps until each
plant change is due and hands an IRQ edge over at once, so the firmware's real timing
shows. As SimPy's ``RealtimeEnvironment`` is its ``Environment`` with one step
overridden, this is :class:`Lockstep` with its step overridden (``docs/clock.md``).
"""

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

    def begin(self, t_us: int) -> None:
        """The firmware starts (or restarts) at virtual ``t_us``."""

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
    irq_ends_batch = True

    def __init__(self):
        self.wall0 = 0.0

    def begin(self, t_us: int) -> None:
        self.wall0 = time.monotonic() - t_us / 1e6

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

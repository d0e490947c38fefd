"""Speculation: a batch of plant changes the firmware may not take as computed.

In lockstep the host advances the plant past IRQ edges without stopping at each
(``docs/clock.md``): it snapshots the plant when the batch starts, and when an IRQ
handler changes an output inside the batch, it rewinds to that moment. Budget events
that a batch produces are held back here until the firmware has moved past their time,
so a rewound batch never reaches a budget.
"""

from host.core.errors import LinkError


class Speculation:
    def __init__(self, plant):
        self.plant = plant
        self.snapshot = None  # (t_us, the plant's snapshot) while a batch may be rewound
        self.deferred: list[tuple] = []  # (t_us, callable, args) not yet committed

    @property
    def open(self) -> bool:
        return self.snapshot is not None

    def begin(self) -> None:
        """Snapshot the plant: the changes from here on may be rewound."""
        self.snapshot = (self.plant.t_us, self.plant.snapshot())

    def end(self) -> None:
        """The firmware took the whole batch: nothing in it will be rewound."""
        self.snapshot = None

    def defer(self, t_us: int, call, args: tuple) -> None:
        self.deferred.append((t_us, call, args))

    def commit(self, t_us: int) -> None:
        """Events up to ``t_us`` can no longer be rewound: call them, in order."""
        deferred = self.deferred
        if deferred and deferred[0][0] <= t_us:
            keep = []
            for event in deferred:
                if event[0] <= t_us:
                    event[1](*event[2])
                else:
                    keep.append(event)
            self.deferred = keep

    def rewind(self, t_us: int, plant_t_us: int) -> None:
        """Back to ``t_us`` (where a handler changed an output): restore the snapshot and
        advance to ``t_us`` again (the firmware already has those changes); forget the
        events after it."""
        if self.snapshot is None or self.snapshot[0] > t_us:
            raise LinkError(
                f"firmware reported t={t_us} us, before the plant's {plant_t_us} us, with no snapshot to "
                f"return to (link protocol error)"
            )
        self.plant.restore(self.snapshot[1])
        # (the changes on the way are the firmware's already: an encoder's edges go as
        # segments, dropped, its counters moved past them in closed form as emit would)
        self.plant.advance_edges(t_us, 0, [])
        self.snapshot = None
        self.deferred = [e for e in self.deferred if e[0] <= t_us]

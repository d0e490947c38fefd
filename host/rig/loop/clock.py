"""The host's half of the protocol of time (``docs/clock.md``): the firmware's pending
wait, the plant advanced for it, the plant caught up with the firmware's own time (or
rewound, when a handler changed an output inside a speculative batch), and the STATE
that answers the wait. The pacing (:mod:`host.rig.loop.pacing`) decides each step."""

import os
from dataclasses import dataclass

from host.artefacts.linklog import NO_LOG
from host.link import frames as F

_NO_WATCH = frozenset()
LOOKAHEAD_US = 20_000
"""How far past a wait's end the plant's inputs go in its STATE (lockstep): the shim holds
them and applies each at its time, so a firmware that wakes, finds nothing to drive and
waits again needs no exchange for it. A lookahead the firmware voids (an output inside
it) makes the next ones wait: 1, 2, 4 ... up to LOOKAHEAD_BACKOFF_MAX exchanges."""
LOOKAHEAD_BACKOFF_MAX = 256
EDGE_SEGMENTS_ENV = "MPY_FIL_EDGE_SEGMENTS"
"""Encoder edges go to the shim as segments (EDGES, docs/clock.md "Encoder edges as
segments"), not one change each: by default, but with MCU time on; ``MPY_FIL_EDGE_SEGMENTS=1``
in the host's environment turns them on with it too, ``=0`` off everywhere."""


SEGMENT_MIN_EDGES = 32
"""A wait whose encoders are due fewer edges than this (at their rates as its batch begins)
takes them a change each: for so few, an EDGES frame and its expansion cost both ends more
than the changes do (the rover's 7 or 8 edges an exchange cost it 4-5 % more instructions on
each side as segments; docs/bench.md)."""


def edge_segments_wanted(mcu_time: bool = False) -> bool:
    """Whether encoder edges go as segments: the environment's ``MPY_FIL_EDGE_SEGMENTS`` when
    it says, else all but with MCU time on (there the shim's own objects, other with segments,
    can still move a modelled collection of the firmware's: docs/mcu-time.md, "The collector's
    pause")."""
    said = os.environ.get(EDGE_SEGMENTS_ENV, "").strip().lower()
    if said in ("1", "yes", "true", "on"):
        return True
    if said in ("0", "no", "false", "off"):
        return False
    return not mcu_time


@dataclass
class Wait:
    t_now: int  # the firmware's time when it blocked
    t_until: int  # when it wants to wake, at the latest
    watch: frozenset  # handles whose change wakes it earlier


class Clock:
    def __init__(self, plant, pacing, wiring, inputs, speculation, recorder, stats, session, log):
        self.plant = plant
        self.pacing = pacing
        self.wiring = wiring
        self.inputs = inputs
        self.speculation = speculation
        self.recorder = recorder
        self.stats = stats
        self.session = session
        self.log = log  # the link log (host.artefacts.linklog)
        self.wait: Wait | None = None
        self.lookahead_us = LOOKAHEAD_US if pacing.speculates else 0
        self.looked = False  # the last STATE looked ahead, and nothing voided it yet
        self.look_skip = 0  # exchanges to go before the next lookahead
        self.look_backoff = 1
        self._woke_us = F.FOREVER_US  # the last STATE's wake time, while the firmware runs
        self.end_us = 0  # the end of the run being served (a bus transfer's lease stops there)
        self.images = None  # host.rig.hardware.busimage.BusImages: bus reads the shim may answer itself
        # Encoder edges as segments the shim expands (EDGES, docs/protocol.md): set by the rig
        # (edge_segments_wanted), used where edge_routes allows, up to a wait's end (never in
        # the lookahead, whose changes the shim holds one by one)
        self.edge_segments = edge_segments_wanted()

    def block(self, t_now: int, t_until: int, watch: frozenset) -> None:
        """A WAIT: the firmware took the whole last batch and blocks until ``t_until``."""
        self._woke_us = F.FOREVER_US
        t_plant = self.plant.t_us
        if t_now != t_plant:
            self.catch_up(t_now)
            t_plant = self.plant.t_us
        else:  # (catch_up at the plant's instant: the commit alone)
            self.commit(t_now)
        if self.looked:  # the lookahead served: the next ones come at once
            self.looked = False
            self.look_backoff = 1
        self.speculation.end()
        self.wait = Wait(t_now, max(t_until, t_plant), watch)

    def serve(self, t_end_us: int) -> None:
        """Advance the plant for the pending wait, no further than ``t_end_us``; answer
        the wait when it is over."""
        wait = self.wait
        self.end_us = t_end_us
        if self.pacing.walled:  # (real time: a pause before this wait is not the firmware's time)
            self.pacing.resume(wait.t_now, self.plant.t_us)
        stopped = self.advance(min(wait.t_until, t_end_us), wait.watch)
        t_wake = self.plant.t_us
        if stopped or t_wake >= wait.t_until:
            self.wait = None
            images = self.images
            image = None
            if images is not None and images.on and images.reads:
                image = images.image(t_wake, self.lease_us(), "wake")
            if self.lookahead_us and not stopped and wait.t_until > wait.t_now:  # (a sync: none)
                self._look_ahead(t_end_us)
            if image is not None:  # (taken at the wake, before the lookahead ran the plant on)
                self.session.hold(F.BUS_IMAGE, image)
            self._send_state(wait.t_now, t_end_us, t_wake)
        elif self.speculation.snapshot is None:  # (not open)
            self.commit(t_wake)  # nothing in this batch can be rewound

    def _look_ahead(self, t_end_us: int) -> None:
        """Advance the plant past the wait's end (never past the run's), its changes going
        in the same STATE, speculatively: an output inside rewinds it."""
        plant = self.plant
        t_look = min(plant.t_us + self.lookahead_us, t_end_us)
        if self.look_skip:
            self.look_skip -= 1
            return
        if t_look <= plant.t_us or plant.zero_delay:
            return
        if not self.speculation.open:
            self.speculation.begin()
        self.looked = True
        self.advance(t_look, _NO_WATCH)

    @property
    def firmware_us(self) -> int:
        """Where the firmware is known to be: the plant's time, or, while the plant has looked
        ahead of a STATE the firmware is running from, that STATE's wake time."""
        return min(self.plant.t_us, self._woke_us)

    def run_alone(self, t_end_us: int) -> None:
        """The firmware ended: the plant runs on alone."""
        while self.plant.t_us < t_end_us:
            self.advance(t_end_us, _NO_WATCH)
            self.inputs.drop()
        self.commit(self.plant.t_us)

    def advance(self, target_us: int, watch: frozenset) -> bool:
        """Advance the plant, collecting what the firmware must see. True when the batch
        must go now: a watched input changed, the batch is full, or (real time) an IRQ
        edge is due. Lockstep batches IRQ edges speculatively."""
        plant, pacing, inputs, recorder = self.plant, self.pacing, self.inputs, self.recorder
        route, route_all = inputs.route, inputs.route_all
        if pacing.speculates and self.speculation.snapshot is None and self.wait is not None and self.wiring.irq_armed:
            self.speculation.begin()
        if plant.zero_delay:  # a wire carries a write to an input at its own instant
            for change in plant.advance_to(plant.t_us, inputs.room()):
                route(change, watch)
        routes = self._edge_routes(watch, target_us) if self.edge_segments and self.wait is not None else None
        while plant.t_us < target_us:
            t_next, limit = pacing.step(self, target_us, watch)
            if routes is not None and limit:
                segs = []
                changes = plant.advance_edges(t_next, limit, segs, inputs.segment_room())
                irq, hit = route_all(changes, watch)
                if segs and inputs.route_segments(segs, routes):
                    irq = True
            else:
                irq, hit = route_all(plant.advance_to(t_next, limit) if limit else plant.advance_to(t_next), watch)
            if recorder is not None:
                recorder.sample(plant)
            if hit or (irq and pacing.irq_ends_batch) or inputs.full():
                return True
        return False

    def _edge_routes(self, watch, target_us: int):
        """Each encoder's channels as EDGES segments go (``Inputs.edge_routes``), or None: not
        a plant with encoders whose edges have a closed form (``edge_counters``), fewer than
        SEGMENT_MIN_EDGES due before ``target_us``, a recording (it writes each edge), a
        watched wait, real time or a wire at zero delay."""
        plant = self.plant
        if watch or self.recorder is not None or not self.pacing.speculates or plant.zero_delay:
            return None
        counters = plant.edge_counters
        if not counters or sum([abs(c.rate) for c in counters]) * (target_us - plant.t_us) < SEGMENT_MIN_EDGES:
            return None
        return self.inputs.edge_routes(counters, watch)

    def catch_up(self, t_us: int) -> None:
        """Bring the plant to the firmware's time: forward if the shim moved on inside
        its horizon, back if a handler changed an output inside a speculative batch."""
        plant = self.plant
        t_plant = plant.t_us
        while t_us > t_plant:  # (through ground truth's sample times, as advance() goes)
            for change in plant.advance_to(self.to_truth(t_us)):
                self.stats.lease_violations += 1
                self.inputs.route(change, _NO_WATCH)
            if self.recorder is not None:
                self.recorder.sample(plant)
            t_plant = plant.t_us
        if t_us < t_plant and self.pacing.speculates:
            if self.looked:  # the firmware voided the lookahead: wait longer for the next
                self.looked = False
                self.look_skip = self.look_backoff
                self.look_backoff = min(2 * self.look_backoff, LOOKAHEAD_BACKOFF_MAX)
            self.speculation.rewind(t_us, plant.t_us)
            if self.recorder is not None:
                self.recorder.rewind(t_us)
            self.inputs.unsample(t_us)
            self.stats.rollbacks += 1
            self.log.rollback(t_us)
        self.commit(t_us)

    def to_truth(self, t_us: int) -> int:
        """``t_us``, or the next ground-truth sample time if the recorder wants one before
        it: how far the plant may go in one step."""
        recorder = self.recorder
        if recorder is None:
            return t_us
        plant = self.plant
        t_truth = recorder.next_truth_us
        # A sample due before ``t_us`` with no change of the plant's before it or at it is
        # taken here, the plant moved to its instant (nothing due: only its time moves, as
        # a step there would move it), without a step of the loop's for it.
        while plant.t_us < t_truth < t_us and t_truth < plant.next_change_us():
            plant.advance_to(t_truth)
            recorder.sample(plant)
            t_truth = recorder.next_truth_us
        return min(t_us, max(t_truth, plant.t_us + 1))

    def commit(self, t_us: int) -> None:
        """Nothing up to ``t_us`` can be rewound: held-back budget events go to the
        budgets, and the recording may go to disk up to there."""
        self.speculation.commit(t_us)
        if self.recorder is not None:
            self.recorder.commit(t_us)

    def lease_us(self) -> int:
        """How far the firmware may run on alone from the plant's time, as a STATE's horizon
        says (after a bus transfer): to the next input change, never past the run's end."""
        return min(self.plant.next_change_us(), max(self.end_us, self.plant.t_us))

    def _send_state(self, base_us: int, t_end_us: int, t_us: int) -> None:
        """The STATE that wakes the firmware at ``t_us``, with the changes up to where the
        plant is (past ``t_us`` after a lookahead)."""
        # (never past the run's end: a firmware with nothing to wake it for would run on
        # alone, far past what was asked for, while the host waits for it)
        horizon = min(self.plant.next_change_us(), max(t_end_us, self.plant.t_us))
        changes = self.inputs.take()
        segments = self.inputs.take_segments()
        self._woke_us = t_us
        if segments:  # (with the STATE, in one write: the shim expands them as it applies it)
            self.session.hold(F.EDGES, F.pack_edges(base_us, segments))
            self.stats.edge_segments += len(segments)
        # (the trace has the changes the firmware takes, the segments' edges merged into the
        # STATE's as the shim merges them: a run's trace is the same with segments or a change
        # an edge wherever its exchanges are the same, docs/traces.md)
        try:
            state = F.pack_state(base_us, t_us, horizon, changes)
            self.session.send(F.STATE, state + self.pacing.take_trailer() if self.pacing.walled else state)
        finally:  # (logged once sent: its writing overlaps the firmware's work; not recorded: no call)
            if self.log is not NO_LOG:
                self.log.state(t_us, base_us, horizon, changes, segments)
        self.stats.link_round_trips += 1

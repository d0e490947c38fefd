"""Wheel encoders as the pins a board sees: edges at exactly computed times.

An encoder disk turns with the motor shaft (``gear_ratio`` shaft turns per wheel turn,
1 for a disk on the wheel). Its state is an integer edge count ``n``; the output levels
are a function of ``n``. Between two speed changes the disk angle grows linearly, kept as
a *phase* in edges (``p = p0 + rate * (t - t0)``, an edge at every integer), so the next
edge is a division away.

=================================  ====================================================
class                              signal
=================================  ====================================================
:class:`QuadratureEncoder`         A/B in quadrature, 4 edges per line (seed 004, Table 1:
                                   phases AB = 00, 10, 11, 01 going forward, so A leads B)
:class:`SlottedDiskEncoder`        one channel from a slotted disk and an optical
                                   interrupter, 2 edges per slot, no direction (seeds
                                   002, 003)
=================================  ====================================================

``polarity`` = -1 models an encoder mounted mirrored (its channels run backwards when
the wheel turns forwards). Slip (wheel travel the disk does not see) is the drive's
business: it hands each encoder the disk's own speed (see ``encoder_rad_s``).
"""

import math

from sim_plant.plant import NEVER_US, Change

_new_tuple = tuple.__new__  # Change(...) without the Python-level __new__ (this runs per edge)

QUAD_A = (0, 1, 1, 0)
QUAD_B = (0, 0, 1, 1)
"""Seed 004, Table 1: phase 0..3 gives (A, B) = 00, 10, 11, 01."""


class _EdgeCounter:
    """An integer edge count driven by a linearly growing phase."""

    edges_per_line = 1
    names: tuple[str, ...] = ()

    def __init__(self, names, *, wheel: int, lines_per_rev: int, gear_ratio: float = 1.0, polarity: int = 1):
        if lines_per_rev <= 0 or gear_ratio <= 0:
            raise ValueError(
                f"encoder {names}: lines_per_rev ({lines_per_rev}) and gear_ratio ({gear_ratio}) must be > 0"
            )
        if polarity not in (1, -1):
            raise ValueError(f"encoder {names}: polarity must be +1 or -1, got {polarity!r}")
        self.names = tuple(names)
        self.wheel = wheel
        self.lines_per_rev = lines_per_rev
        self.gear_ratio = float(gear_ratio)
        self.polarity = polarity
        self.edges_per_wheel_rev = self.edges_per_line * lines_per_rev * self.gear_ratio
        self._edges_per_rad = self.edges_per_wheel_rev / (2 * math.pi)
        # the output that changes when the count steps to n (indexed by n & mask)
        self._mask = self.edges_per_line - 1
        self._fwd = tuple(self._changed(k - 1, k) for k in range(self.edges_per_line))
        self._bwd = tuple(self._changed(k + 1, k) for k in range(self.edges_per_line))
        self.n = 0  # edge count (signed: the disk's real position)
        self.p0 = 0.5  # phase at t0, in edges: the disk starts mid-way between two edges
        self.t0_us = 0
        self.rate = 0.0  # edges per microsecond
        self.next_us = NEVER_US

    def _levels(self, n: int) -> tuple[int, ...]:
        raise NotImplementedError

    def _changed(self, n_old: int, n_new: int) -> tuple[str, int]:
        old, new = self._levels(n_old), self._levels(n_new)
        (i,) = [i for i in range(len(new)) if old[i] != new[i]]
        return self.names[i], new[i]

    @property
    def levels(self) -> tuple[int, ...]:
        return self._levels(self.n)

    def initial_outputs(self) -> dict:
        return dict(zip(self.names, self.levels))

    def set_speed(self, t_us: int, wheel_rad_s: float) -> None:
        """The wheel's disk turns at ``wheel_rad_s`` from ``t_us`` on."""
        p = self.p0 + self.rate * (t_us - self.t0_us)
        n = self.n
        self.p0 = self._phase(p, n)
        self.t0_us = t_us
        self.rate = wheel_rad_s * self.polarity * self._edges_per_rad * 1e-6
        rate = self.rate
        if rate > 0.0:
            t = self.t0_us + math.ceil((n + 1 - self.p0) / rate)
        elif rate < 0.0:
            t = self.t0_us + math.ceil((self.p0 - n) / -rate)
        else:
            self.next_us = NEVER_US
            return
        self.next_us = t if t > t_us else t_us + 1

    @staticmethod
    def _phase(p: float, n: int) -> float:
        """The disk's phase as a new base: between the edge just counted and the next one
        (``p`` strays from it by rounding to whole microseconds)."""
        return n if p < n else (n + 1 if p > n + 1 else p)

    def emit(self, t_us: int, out: list) -> None:
        """The edge due at ``t_us``: step the count, append the level that changed, plan
        the next edge (same base: the edge times of a constant speed are exact)."""
        rate = self.rate
        if rate > 0.0:
            n = self.n + 1
            name, level = self._fwd[n & self._mask]
            t = self.t0_us + math.ceil((n + 1 - self.p0) / rate)
        else:
            n = self.n - 1
            name, level = self._bwd[n & self._mask]
            t = self.t0_us + math.ceil((self.p0 - n) / -rate)
        self.n = n
        out.append(_new_tuple(Change, (t_us, name, level)))
        self.next_us = t if t > t_us else t_us + 1

    def truth(self) -> dict:
        return {f"{self.names[0].split('.')[0]}_edges": self.n}

    plain_emit = emit
    """The closed-form emit: an encoder whose class's ``emit`` is still this one lets
    :mod:`sim_plant.edge_window` compute a window of its edges at once."""

    @staticmethod
    def emit_until(encoders, nxt: int, t_stop: int, soonest_other: int, out: list, limit: int) -> tuple[int, int]:
        """The plant's loop over the instants where only encoders are due (each encoder's
        ``emit`` its ``plain_emit``), from ``nxt`` through ``t_stop`` (before
        ``soonest_other``, the next event of anything else), in one call: at each instant the
        edges due, in the encoders' order, each by its ``emit``, then the next instant; it
        stops after the instant that brings ``out`` to ``limit`` (0: no limit). Returns (the
        last instant emitted, or -1 if none; the next instant due)."""
        last = -1
        while nxt <= t_stop:
            for enc in encoders:
                if enc.next_us == nxt:
                    enc.emit(nxt, out)
            last = nxt
            nxt = soonest_other
            for enc in encoders:
                if enc.next_us < nxt:
                    nxt = enc.next_us
            if limit and len(out) >= limit:
                break
        return last, nxt


class QuadratureEncoder(_EdgeCounter):
    """Two channels 90 degrees apart: ``lines_per_rev`` lines on the disk give 4 edges
    (counts) each. Outputs ``names = (a, b)``."""

    edges_per_line = 4

    def _levels(self, n: int) -> tuple[int, int]:
        phase = n & 3
        return QUAD_A[phase], QUAD_B[phase]


class SlottedDiskEncoder(_EdgeCounter):
    """One channel: each of ``lines_per_rev`` slots passes the interrupter as one high
    and one low half-period, whatever the direction. Output ``names = (out,)``."""

    edges_per_line = 2

    def _levels(self, n: int) -> tuple[int]:
        return (n & 1,)


MISS_GAPS = 4096
"""Gaps between missed edges a :class:`MissingEdgeEncoder` is given (used in turn, then again from the first)."""


class MissingEdgeEncoder(QuadratureEncoder):
    """A quadrature encoder whose edges now and then come two at once, as they do for a
    board when two edges fall closer together than its interrupt latency.

    After every ``gaps[i]`` edges (drawn at reset, each >= 2) the next edge is emitted
    at the same instant as the current one, if the wheel has turned the same way for
    the last two edges (a board only misses edges at speed). ``missed`` counts them.
    The disk's phase is not moved: the edge after comes when it would have, so the
    counts still follow the wheel's travel."""

    def __init__(self, names, *, gaps: tuple, **kwargs):
        super().__init__(names, **kwargs)
        self.gaps = gaps
        self.gap_no = 0
        self.until_miss = gaps[0]
        self.missed = 0
        self.last_dir = 0
        self.doubled = False  # the next edge is due at the instant of the last one

    def emit(self, t_us: int, out: list) -> None:
        super().emit(t_us, out)
        direction = 1 if self.rate > 0.0 else -1
        same = direction == self.last_dir
        self.last_dir = direction
        if self.doubled:
            self.doubled = False
        elif self.until_miss > 1:
            self.until_miss -= 1
        elif same:
            self.gap_no = (self.gap_no + 1) % len(self.gaps)
            self.until_miss = self.gaps[self.gap_no]
            self.missed += 1
            self.doubled = True
            self.next_us = t_us

    @staticmethod
    def _phase(p: float, n: int) -> float:
        # after an edge that came early the count is one edge ahead of the disk until
        # the disk reaches it: keep the disk's phase (the next edge comes when it would
        # have; turning back, the early edge is taken back at once)
        return n - 1 if p < n - 1 else (n + 2 if p > n + 2 else p)

    def set_speed(self, t_us: int, wheel_rad_s: float) -> None:
        before = self.rate
        super().set_speed(t_us, wheel_rad_s)
        if self.doubled:
            if before * self.rate > 0.0:
                self.next_us = t_us  # still due now: it turns the same way
            else:  # stopped or turned back at that instant: the edge never comes
                self.doubled = False
                self.missed -= 1

    def truth(self) -> dict:
        return {**super().truth(), f"{self.names[0].split('.')[0]}_missed": self.missed}

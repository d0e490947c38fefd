"""Encoder edges of a whole window at once (numpy): the hot path of an encoder-heavy plant.

Between two events of the other parts (the drive's speed steps) every encoder turns at a
constant rate, so its edge times are a closed form of the edge count: the same float
arithmetic as :meth:`sim_plant.physics.encoder._EdgeCounter.emit` (IEEE division and ceiling,
element by element), for all the window's edges in one go. The window's edges are merged
in time order, at one instant in the order of the encoders, as the plant's event loop
emits them one by one; a batch limit cuts after the instant that reached it, as there.
An encoder whose ``emit`` is its own (:class:`MissingEdgeEncoder`), a rate of an edge a
microsecond or more (emit's clamp to later instants could bite) or a window too short
to pay for numpy's calls (``MIN_EDGES``) goes the loop's way. ``host/tests/test_edge_window.py`` checks
the two ways give the same changes.
"""

import math

import numpy as np

from sim_plant.plant import Change

_new_tuple = tuple.__new__
# Fewer edges expected in a window: the loop's way. numpy's fixed cost (some 25 calls a
# window) is about 4 us an edge over the encoder bench's windows of ~46 edges (the drive's
# speed steps come every few ms), against about 1 us an edge for the loop (docs/bench.md).
MIN_EDGES = 1024


def plain(encoders) -> bool:
    """Whether every encoder emits as :class:`sim_plant.physics.encoder._EdgeCounter` does
    (its class's ``emit`` is its ``plain_emit``): a window may compute them."""
    return all(type(enc).emit is getattr(type(enc), "plain_emit", None) for enc in encoders)


def _times(enc, t_stop: int):
    """The counter's edges from its next one through ``t_stop`` at its current rate, and
    the time of the one after: (times, counts after each, next time), or None when emit's
    clamp could bite (the times not strictly increasing)."""
    rate = enc.rate
    t1 = enc.next_us
    k = int((t_stop - t1) * abs(rate)) + 3
    while True:
        j = np.arange(1, k + 1, dtype=np.int64)
        if rate > 0.0:
            counts = enc.n + j
            raw = np.ceil((counts + 1 - enc.p0) / rate)
        else:
            counts = enc.n - j
            raw = np.ceil((enc.p0 - counts) / -rate)
        times = np.empty(k + 1, dtype=np.int64)
        times[0] = t1
        times[1:] = enc.t0_us + raw.astype(np.int64)
        if times[-1] > t_stop:
            break
        k *= 2
    if not (times[1:] > times[:-1]).all():
        return None
    m = int(np.searchsorted(times, t_stop, side="right"))
    return times[:m], counts[:m], int(times[m])


def emit_window(encoders, t_stop: int, out: list, limit: int, min_edges: int = MIN_EDGES):
    """Every edge of ``encoders`` from their next ones through ``t_stop`` appended to ``out``
    (no other part's event in between), up to the instant that brings ``out`` to ``limit``
    (0: no limit). Returns the last instant emitted, or None (nothing done: the loop's way)."""
    # (lists, not generators: this runs at each window of the plant's loop)
    if sum([abs(enc.rate) for enc in encoders]) * (t_stop - min([enc.next_us for enc in encoders])) < min_edges:
        return None
    parts = []
    for k, enc in enumerate(encoders):
        if enc.next_us > t_stop:
            continue
        if not -1.0 < enc.rate < 1.0:
            return None
        got = _times(enc, t_stop)
        if got is None:
            return None
        parts.append((k, enc, *got))
    if not parts:
        return None
    times = np.concatenate([p[2] for p in parts])
    which = np.concatenate([np.full(len(p[2]), i, dtype=np.int64) for i, p in enumerate(parts)])
    edges = []  # (name, level) of each edge, the parts one after the other
    for _k, enc, _t, counts, _after in parts:
        table = enc._fwd if enc.rate > 0.0 else enc._bwd
        mask = enc._mask
        edges += [table[c & mask] for c in counts.tolist()]
    order = np.lexsort((which, times))  # by time, at one instant in the encoders' order
    if limit:
        order = _cut(times, order, limit - len(out))
    taken = np.bincount(which[order], minlength=len(parts))
    for i, (_k, enc, t_enc, counts, t_after) in enumerate(parts):
        m = int(taken[i])
        if m:
            enc.n = int(counts[m - 1])
            enc.next_us = int(t_enc[m]) if m < len(t_enc) else t_after
    for o, t in zip(order.tolist(), times[order].tolist()):
        name, level = edges[o]
        out.append(_new_tuple(Change, (t, name, level)))
    return int(times[order[-1]])


def _cut(times, order, room: int):
    """``order`` (the edges in time order) up to the end of the instant that fills ``room``
    (all of it if none does)."""
    room = max(room, 1)
    if len(order) <= room:
        return order
    in_order = times[order]
    return order[: int(np.searchsorted(in_order, in_order[room - 1], side="right"))]


SEGMENT_RATE = 0.5
"""Segments (:func:`segments`) only below this many edges a microsecond: two edges of one
counter are then more than 2 us apart, so the closed form's times strictly increase and
``emit``'s clamp to later instants never bites (rounding cannot close a gap of 2)."""


def _edge_us(enc, m: int) -> int:
    """When the counter reaches count ``m`` past its next edge: ``emit``'s own arithmetic."""
    rate = enc.rate
    if rate > 0.0:
        return enc.t0_us + math.ceil((m - enc.p0) / rate)
    return enc.t0_us + math.ceil((enc.p0 - (m + 1)) / -rate)


def segments(encoders, t_stop: int, segs: list):
    """Every edge of ``encoders`` from their next ones through ``t_stop`` (no other part's
    event in between) as one segment per encoder that has some, appended to ``segs`` as
    (encoder index, first edge's time, count before it, edges, t0_us, p0, rate): the edges
    themselves are left to whoever expands them (the shim). Each counter is moved past them
    as ``emit`` would have. Returns the last instant of an edge, or None (nothing done: a
    counter turns too fast for segments)."""
    for enc in encoders:
        if enc.next_us <= t_stop and not -SEGMENT_RATE < enc.rate < SEGMENT_RATE:
            return None
    t_last = None
    for k, enc in enumerate(encoders):
        t1 = enc.next_us
        if t1 > t_stop:
            continue
        rate = enc.rate
        step = 1 if rate > 0.0 else -1
        n = enc.n
        # edges j = 1 .. count reach n + step * j; the first at t1, the others by the closed form
        count = max(1, int((t_stop - t1) * abs(rate)))
        while count > 1 and _edge_us(enc, n + step * count) > t_stop:
            count -= 1
        while _edge_us(enc, n + step * (count + 1)) <= t_stop:
            count += 1
        last = t1 if count == 1 else _edge_us(enc, n + step * count)
        segs.append((k, t1, n, count, enc.t0_us, enc.p0, rate))
        enc.n = n + step * count
        enc.next_us = _edge_us(enc, enc.n + step)
        if t_last is None or last > t_last:
            t_last = last
    return t_last

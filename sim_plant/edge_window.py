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
    if sum(abs(enc.rate) for enc in encoders) * (t_stop - min(enc.next_us for enc in encoders)) < min_edges:
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

# The shim's per-edge pieces timed inside MicroPython, without a host (docs/bench.md):
#   MICROPYPATH=host/shim:host/bench/encoder_bot $MICROPYTHON host/bench/shim_pieces.py
# (HIL_PURE=1 for the pure-Python path). A STATE of 100 quadrature edges on the encoder
# bot's two pins, its handlers armed, is decoded and applied through _hil._sync over and
# over against a link stub that answers at once; the same with no handlers armed; the
# frame's decoding alone; the handlers called bare. Prints wall us an edge of each piece.
import gc
import os

import _hil
import _hilframe as F

EDGES = 100  # a STATE's changes (the bench's PID period at 10,000 edges a second)
ROUNDS = 300


class _StubLink:
    zero = False
    woke = None
    state = b""

    def queue(self, type_, payload):
        pass

    def flush(self):
        pass

    def exchange(self, payload, t_now, fmt):
        return self.state


def _state(a, b, base):
    changes = []
    for k in range(EDGES // 4):  # a quadrature cycle: A up, B up, A down, B down
        for j, (pin, level) in enumerate(((a, 1), (b, 1), (a, 0), (b, 0))):
            changes.append((base + 40 * k + 10 * j + 10, pin._handle, F.CH_LEVEL, level, 0))
    return F.pack_state(base, base + 10 * EDGES, base + 10 * EDGES + 1, changes)


def _per_edge(fn):
    gc.collect()
    best = None
    for _ in range(3):
        t0 = _hil._rtime.ticks_us()
        for _ in range(ROUNDS):
            fn()
        dt = _hil._rtime.ticks_diff(_hil._rtime.ticks_us(), t0)
        best = dt if best is None or dt < best else best
    return best / (ROUNDS * EDGES)


def main():
    link = _hil._link = _StubLink()
    link.state = F.pack_state(0, 0, 1, [])
    _hil._Link.thread = int
    _hil._Link.main_thread = 0
    getenv = getattr(os, "getenv", None)
    _hil._Link.fast = _hil._fast_path(getenv) if not (getenv and getenv("HIL_PURE")) else None
    from encoder import QuadEncoder

    enc = QuadEncoder(4, 5)
    link.state = _state(enc.a, enc.b, 0)
    frame = F.encode(F.STATE, 0, link.state)
    path = "C (_hilfast)" if _hil._Link.fast is not None else "pure Python"
    dec = F.Decoder()

    def decode():
        dec.expect_seq = -1
        dec.feed(frame)
        dec.next()

    def sync():
        _hil._sync(10 * EDGES, None)

    full = _per_edge(sync)
    counted = enc.count
    for pin in (enc.a, enc.b):
        pin._handler = None
    apply_only = _per_edge(sync)
    decode_us = _per_edge(decode)

    class Stub:
        def __init__(self):
            self.v = 0

        def value(self):
            return self.v

    class Bare(QuadEncoder):
        def __init__(self):
            self.a, self.b, self.count = Stub(), Stub(), 0

    bare = Bare()

    def handlers():
        for _ in range(EDGES // 4):
            bare.a.v = 1
            bare.on_a(bare.a)
            bare.b.v = 1
            bare.on_b(bare.b)
            bare.a.v = 0
            bare.on_a(bare.a)
            bare.b.v = 0
            bare.on_b(bare.b)

    bare_us = _per_edge(handlers)
    print("shim pieces, %s, us an edge (a STATE of %d edges):" % (path, EDGES))
    print("  frame decode (Decoder.feed + next, CRC): %.2f" % decode_us)
    print("  _sync, no handlers armed (STATE decode + apply): %.2f" % apply_only)
    print("  _sync, handlers armed (+ dispatch + the handlers): %.2f" % full)
    print("  dispatch + handlers (the difference): %.2f" % (full - apply_only))
    print("  the handlers bare (stub pins, loop included): %.2f" % bare_us)
    print("  counts moved: %d" % counted)


main()

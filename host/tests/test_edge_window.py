"""The plant's encoder edges computed a window at once (sim_plant/edge_window.py) are the
edges the event loop emits one by one: the same changes in the same order, the counters
left in the same state, with and without a batch limit."""

import copy

from hypothesis import given, settings
from hypothesis import strategies as st

from sim_plant import edge_window
from sim_plant.physics.encoder import MissingEdgeEncoder, QuadratureEncoder, SlottedDiskEncoder


def _one_by_one(encoders, t_stop, out, limit):
    """The loop of RobotPlant.advance_to over encoders alone."""
    nxt = min(enc.next_us for enc in encoders)
    last = None
    while nxt <= t_stop:
        for enc in encoders:
            if enc.next_us == nxt:
                enc.emit(nxt, out)
        last = nxt
        nxt = min(enc.next_us for enc in encoders)
        if limit and len(out) >= limit and nxt > last:
            break
    return last


def _state(encoders):
    return [(enc.n, enc.next_us, enc.p0, enc.t0_us, enc.rate) for enc in encoders]


def _encoders(speeds, t0):
    made = []
    for i, rad_s in enumerate(speeds):
        kind = (QuadratureEncoder, SlottedDiskEncoder)[i % 2]
        names = (f"e{i}.a", f"e{i}.b") if kind is QuadratureEncoder else (f"e{i}.out",)
        enc = kind(names, wheel=i % 2, lines_per_rev=7 + 13 * i, gear_ratio=98.5 if i < 2 else 1.0)
        enc.set_speed(t0, rad_s)
        made.append(enc)
    return made


speed = st.one_of(st.just(0.0), st.floats(0.01, 80.0), st.floats(-80.0, -0.01))  # rad/s


@settings(max_examples=150, deadline=None)
@given(
    speeds=st.lists(speed, min_size=1, max_size=3),
    t0=st.integers(0, 10**9),
    span=st.integers(0, 30_000),
    limit=st.one_of(st.just(0), st.integers(1, 300)),
    steps=st.integers(1, 3),
)
def test_a_window_emits_what_the_loop_emits(speeds, t0, span, limit, steps):
    a = _encoders(speeds, t0)
    b = copy.deepcopy(a)
    for step in range(steps):
        t_stop = t0 + span * (step + 1)
        want, got = [], []
        last_want = _one_by_one(a, t_stop, want, limit)
        last_got = edge_window.emit_window(b, t_stop, got, limit, min_edges=8)  # (windows of every size)
        if last_got is None:  # (the loop's way: too few edges, or a rate it leaves alone)
            last_got = _one_by_one(b, t_stop, got, limit)
        assert got == want
        assert [type(c[0]) for c in got] == [type(c[0]) for c in want]
        assert last_got == last_want
        assert _state(b) == _state(a)


def test_a_window_is_taken_at_speed_and_left_to_the_loop_for_a_missing_edge_encoder():
    fast = _encoders([60.0, -55.0], 1000)
    out = []
    assert edge_window.emit_window(fast, 2_000, out, 0) is None and not out  # (too few: the loop's)
    assert edge_window.emit_window(fast, 200_000, out, 0) is not None and len(out) > edge_window.MIN_EDGES
    assert edge_window.plain(fast)
    odd = MissingEdgeEncoder(("m.a", "m.b"), gaps=(5, 7), wheel=0, lines_per_rev=7, gear_ratio=98.5)
    assert not edge_window.plain([*fast, odd])

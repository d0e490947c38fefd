"""Encoder edges as segments (EDGES, on by default, ``MPY_FIL_EDGE_SEGMENTS=0`` off; docs/clock.md,
"Encoder edges as segments"): the plant's segments (sim_plant/edge_window.py, ``segments``) expanded
by the codec (``_hilframe.expand_edges``, the shim's pure path) give exactly the edges its
event loop emits one by one, and leave the counters as it does; a run with segments gives
the firmware every edge in order at its instant (the encoder bot's counts are the plant's
edges at 10,000 and 40,000 edges a second, its outputs and console the same as with one
change an edge), and so do the pico robot (quadrature encoders beside its other parts) and
the duct robot (slot encoders, a timer, UART bytes), on the shim's C path and its pure-Python
path alike, their traces the same as with a change an edge (a STATE record lists the edges
the firmware took, and no STATE of theirs is cut by its limit of changes)."""

import copy
import json
import tempfile
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from host.bench import ENCODER_BOT, encoder_firmware
from host.link import frames as F
from host.rig import Recording, Rig, RigSpec
from host.rig.loop.clock import EDGE_SEGMENTS_ENV
from host.tests.test_edge_window import _encoders, _one_by_one, _state
from sim_plant import edge_window

speed = st.one_of(st.just(0.0), st.floats(0.01, 80.0), st.floats(-80.0, -0.01))  # rad/s


def _handles(encoders):
    """Each channel its own handle (the order of the names)."""
    names = [name for enc in encoders for name in enc.names]
    return {name: h for h, name in enumerate(names)}


def _wire(raw, encoders, handles):
    """The plant's segments as an EDGES carries them (Inputs.route_segments' fields)."""
    out = []
    for k, t1, n, count, t0, p0, rate in raw:
        enc = encoders[k]
        mask = enc.edges_per_line - 1
        levels = [enc._levels(m) for m in range(mask + 1)]
        hs = [handles[name] for name in enc.names] + [F.NO_HANDLE]
        bits = [sum(lv[c] << m for m, lv in enumerate(levels)) if c < len(enc.names) else 0 for c in (0, 1)]
        out.append((hs[0], hs[1], mask, bits[0], bits[1], t1, n, count, t0, p0, rate))
    return out


@settings(max_examples=200, deadline=None)
@given(
    speeds=st.lists(speed, min_size=1, max_size=3),
    t0=st.integers(0, 10**9),
    span=st.integers(0, 30_000),
    steps=st.integers(1, 3),
)
def test_segments_expand_to_the_edges_the_loop_emits(speeds, t0, span, steps):
    a = _encoders(speeds, t0)
    b = copy.deepcopy(a)
    handles = _handles(a)
    for step in range(steps):
        t_stop = t0 + span * (step + 1)
        want, raw = [], []
        last_want = _one_by_one(a, t_stop, want, 0)
        last_got = edge_window.segments(b, t_stop, raw)
        if last_want is None:  # (no edge due)
            assert last_got is None and raw == []
            continue
        if last_got is None:  # (a counter too fast for segments: the loop's way)
            assert any(abs(enc.rate) >= edge_window.SEGMENT_RATE for enc in b)
            return
        assert last_got == last_want
        got = F.expand_edges(_wire(raw, b, handles))
        assert got == [(t, handles[name], F.CH_LEVEL, level, 0) for t, name, level in want], (
            f"segments {raw} expand to other edges than the loop's"
        )
        assert _state(b) == _state(a)
        assert F.unpack_edges(F.pack_edges(t0, _wire(raw, b, handles)))[1] == _wire(raw, b, handles)
        for enc_a, enc_b, rad_s in zip(a, b, speeds):  # a speed step between two windows
            enc_a.set_speed(t_stop, -rad_s / 2)
            enc_b.set_speed(t_stop, -rad_s / 2)


def test_an_unwired_channel_gives_no_edges_and_a_fast_counter_no_segments():
    (enc,) = _encoders([40.0], 0)
    raw = []
    assert edge_window.segments([enc], 200_000, raw) is not None
    ha, _hb, *rest = _wire(raw, [enc], {enc.names[0]: 7, enc.names[1]: 8})[0]
    only_a = F.expand_edges([(ha, F.NO_HANDLE, *rest)])
    assert only_a and {h for _t, h, *_ in only_a} == {7}
    assert len(only_a) * 2 == raw[0][3]  # (quadrature: every other edge is channel a's)
    (fast,) = _encoders([0.0], 0)
    fast.set_speed(0, 1e5)
    assert abs(fast.rate) >= edge_window.SEGMENT_RATE
    assert edge_window.segments([fast], 1_000, []) is None


# -- runs ------------------------------------------------------------------------------


def _run(rate: int, run_ms: int, monkeypatch, segments: bool, pure: bool = False) -> dict:
    monkeypatch.setenv(EDGE_SEGMENTS_ENV, "1" if segments else "0")
    if pure:
        monkeypatch.setenv("HIL_PURE", "1")
    else:
        monkeypatch.delenv("HIL_PURE", raising=False)
    with tempfile.TemporaryDirectory(prefix="mpy-fil-segments-") as tmp:
        main_dir = encoder_firmware(Path(tmp) / "fw", rate, run_ms)
        spec = RigSpec(str(ENCODER_BOT / "rig.toml"), seed=1, main_dir=main_dir, allow_exit=True)
        with Rig(spec, Recording(trace=True, artefacts=Path(tmp) / "out")) as rig:
            rig.run_for(run_ms / 1000 + 0.5)
            truth = rig.truth()
            console = rig.console
            stats = rig.stats
        lines = (Path(tmp) / "out" / "trace.jsonl").read_text().splitlines()
        trace = [r for r in map(json.loads, lines) if "header" not in r]  # (the header names the tmp folder)
    counts = [line for line in console.splitlines() if line.startswith("counts ")]
    return {
        "counts": tuple(int(c) for c in counts[-1].split()[1:]) if counts else None,
        "edges": (truth["enc_l_edges"], truth["enc_r_edges"]),
        "console": console,
        "trace": trace,
        "segments": stats.edge_segments,
        "exchanges": stats.link_round_trips,
    }


def _outputs(trace) -> list:
    """What the firmware did: its outputs, configurations and end, at their instants."""
    return [r for r in trace if r.get("msg") in ("OUT", "CFG", "EXIT")]


def _delivered(trace) -> list:
    """The changes the firmware took, in order: each STATE's up to the instant of a
    rollback that follows it (a handler wrote there: the shim dropped the rest, and the
    host's next STATE goes on from that instant)."""
    taken, state = [], None
    for r in trace:
        if r.get("msg") == "STATE":
            if state is not None:
                taken += state
            state = r["changes"]
        elif r.get("msg") == "ROLLBACK" and state is not None:
            taken += [c for c in state if c[0] <= r["t"]]
            state = None
    return taken + (state or [])


@pytest.mark.hil
@pytest.mark.parametrize("rate", [10_000, 40_000])
def test_every_edge_reaches_the_firmware_in_order_at_its_instant(monkeypatch, rate):
    per_edge = _run(rate, 1500, monkeypatch, segments=False)
    seg = _run(rate, 1500, monkeypatch, segments=True)
    assert seg["segments"] > 0, "the run sent no EDGES: the edges went one change each"
    assert "Traceback" not in seg["console"], seg["console"][-800:]
    assert seg["counts"] == seg["edges"], f"the firmware counted {seg['counts']}, the plant made {seg['edges']} edges"
    assert seg["edges"] == per_edge["edges"] and seg["console"] == per_edge["console"]
    assert _outputs(seg["trace"]) == _outputs(per_edge["trace"]), "the firmware's outputs differ with segments"
    delivered, want = _delivered(seg["trace"]), _delivered(per_edge["trace"])
    assert len(delivered) == len(want) and delivered == want, (
        f"{len(delivered)} changes reached the firmware with segments, {len(want)} one change an edge; first "
        f"difference: {next(((a, b) for a, b in zip(delivered, want) if a != b), None)}"
    )
    if rate == 40_000:  # the limit of changes a STATE no longer cuts the waits: one exchange a Timer tick
        assert seg["exchanges"] < per_edge["exchanges"] * 0.6, (seg["exchanges"], per_edge["exchanges"])


@pytest.mark.hil
def test_the_pure_path_expands_segments_as_the_c_path_does(monkeypatch):
    fast = _run(40_000, 700, monkeypatch, segments=True)
    pure = _run(40_000, 700, monkeypatch, segments=True, pure=True)
    assert fast["segments"] > 0
    assert fast["console"] == pure["console"]
    assert fast["trace"] == pure["trace"], "the C path's link trace with segments differs from the pure path's"


APPS = {  # (app or rig file, world, seed, simulated s): encoders beside other parts
    "pico_bot": (str(Path(__file__).parents[2] / "examples" / "pico_bot" / "rig.toml"), "box-ahead", 11, 3.0),
    "duct": ("duct", "bench", 1, 3.0),  # slot encoders (one channel), a 160 Hz timer, a record stream on a UART
}


@pytest.mark.hil
@pytest.mark.parametrize("key", list(APPS))
def test_apps_take_the_same_inputs_with_segments(make_rig, monkeypatch, key):
    """With segments the firmware takes the same inputs at the same instants as with a
    change an edge (its outputs and console the same), and the pure path does as C does
    (segments for every wait, however few its edges: SEGMENT_MIN_EDGES 0)."""
    from host.rig.config.apps import get_app
    from host.rig.loop import clock

    monkeypatch.setattr(clock, "SEGMENT_MIN_EDGES", 0)
    name, world, seed, seconds = APPS[key]
    got = {}
    for segments, pure in ((False, False), (True, False), (True, True)):
        monkeypatch.setenv(EDGE_SEGMENTS_ENV, "1" if segments else "0")
        if pure:
            monkeypatch.setenv("HIL_PURE", "1")
        else:
            monkeypatch.delenv("HIL_PURE", raising=False)
        options = dict(get_app(name).worlds[world])
        rig = make_rig(name, seed=seed, plant_options=options, trace=True, record=False)  # (a recording: no segments)
        rig.run_for(seconds)
        console, stats = rig.console, rig.stats
        rig.stop()
        lines = (rig.artefacts / "trace.jsonl").read_text().splitlines()
        got[segments, pure] = ([r for r in map(json.loads, lines) if "header" not in r], console, stats.edge_segments)
    (plain, plain_console, _), (seg, seg_console, n_segments) = got[False, False], got[True, False]
    assert got[True, True][:2] == (seg, seg_console), f"{key}: the pure path's trace with segments differs from C's"
    assert n_segments > 0, f"{key}: the run sent no EDGES"
    assert seg_console == plain_console
    assert _outputs(seg) == _outputs(plain), f"{key}: the firmware's outputs differ with segments"
    assert _delivered(seg) == _delivered(plain), f"{key}: the firmware took other inputs with segments"
    assert seg == plain, (  # (no STATE cut by its limit of changes in these runs: the same exchanges)
        f"{key}: the trace with segments differs from the one with a change an edge; first difference: "
        f"{next(((a, b) for a, b in zip(seg, plain) if a != b), None)}"
    )


def test_a_segment_counts_the_irq_edges_its_channels_fire():
    from host.rig.hardware.inputs import _irq_edges

    for mask, bits_a, bits_b in ((3, 0b0110, 0b1100), (1, 0b10, 0)):
        for irq_a in range(4):
            for irq_b in range(4):
                for n in range(-6, 6):
                    for count in range(10):
                        for step in (1, -1):
                            want = 0
                            for j in range(1, count + 1):
                                m, was = n + step * j, n + step * (j - 1)
                                a = bits_a >> (m & mask) & 1
                                if a != bits_a >> (was & mask) & 1:
                                    trigger, level = irq_a, a
                                else:
                                    trigger, level = irq_b, bits_b >> (m & mask) & 1
                                want += bool(trigger & (F.IRQ_RISING if level else F.IRQ_FALLING))
                            got = _irq_edges(mask, bits_a, bits_b, irq_a, irq_b, n, count, step)
                            assert got == want, (mask, irq_a, irq_b, n, count, step, got, want)


def test_segments_are_on_by_default_but_with_mcu_time(monkeypatch):
    from host.rig.loop.clock import edge_segments_wanted

    monkeypatch.delenv(EDGE_SEGMENTS_ENV, raising=False)
    assert edge_segments_wanted() and not edge_segments_wanted(mcu_time=True), "by default: on, off with MCU time"
    for said, on in (("0", False), ("no", False), ("1", True), ("yes", True)):
        monkeypatch.setenv(EDGE_SEGMENTS_ENV, said)
        got = (edge_segments_wanted(), edge_segments_wanted(mcu_time=True))
        assert got == (on, on), f"{EDGE_SEGMENTS_ENV}={said}: expected {(on, on)} (without, with MCU time), got {got}"


@pytest.mark.hil
def test_a_wait_with_few_edges_takes_them_a_change_each(monkeypatch):
    """Segments only where a wait's encoders are due SEGMENT_MIN_EDGES edges or more: the
    encoder bot at 10,000 edges a second sends them, the rover (under 200) none."""
    monkeypatch.delenv(EDGE_SEGMENTS_ENV, raising=False)
    monkeypatch.delenv("HIL_PURE", raising=False)
    bot = _run(10_000, 700, monkeypatch, segments=True)
    with Rig(RigSpec("rover", seed=1), Recording()) as rig:
        rig.run_for(3.0)
        rover = rig.stats.edge_segments, rig.stats.irq_edges
    assert bot["segments"] > 0, "expected the encoder bot's edges as segments, got none"
    assert rover[0] == 0 and rover[1] > 0, (
        f"expected the rover's {rover[1]} IRQ edges a change each, got {rover[0]} segments"
    )

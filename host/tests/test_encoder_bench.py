"""The encoder-heavy case of ``make bench`` (host/bench/encoder_bot): at both of its edge
rates every edge reaches the firmware's Pin.irq handlers in order, at its instant: the
counts it decodes from A and B (an edge out of order or at a wrong instant would decode
as a step backwards, or be read with the other channel's old level) equal the plant's
edges, and the run's recorded signals are the pinned ones (a faster harness must deliver
exactly the same), with a STATE change an edge and with the edges as EDGES segments
(``MPY_FIL_EDGE_SEGMENTS=1``, host/tests/test_edge_segments.py)."""

import hashlib

import pytest

from host.bench import ENCODER_RATES, run_encoder_bot


@pytest.mark.parametrize("segments", [False, True], ids=["a change an edge", "edges as segments"])
@pytest.mark.parametrize("edges_per_s", ENCODER_RATES)
def test_every_edge_is_counted_in_order_at_both_rates(edges_per_s, segments):
    run = run_encoder_bot(edges_per_s, run_ms=1000, segments=segments)
    assert bool(run["segments"]) == segments, f"expected segments {segments}, the run sent {run['segments']}"
    edges = sum(run["edges"])
    assert edges >= 0.8 * edges_per_s, f"expected about {edges_per_s} edges in the second driven, got {run['edges']}"
    assert run["counts"] == run["edges"], (
        f"expected the firmware's counts to equal the plant's edges at {edges_per_s} edges/s, "
        f"got counts {run['counts']} against edges {run['edges']}"
    )


PINNED_SIGNALS = "434f7a4d471c9b760cfc0a1fe64ff2a435e1d7561a595bab3bcff628341fceb0"


def test_the_recorded_signals_are_the_pinned_ones(tmp_path):
    run_encoder_bot(10_000, run_ms=300, record=True, trace=False, artefacts=tmp_path / "run")
    digest = hashlib.sha256((tmp_path / "run" / "signals.csv").read_bytes()).hexdigest()
    assert digest == PINNED_SIGNALS, f"signals.csv changed: {digest}; artefacts in {tmp_path}"

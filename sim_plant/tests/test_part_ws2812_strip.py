"""The ws2812_strip part (sim_plant/catalogue/ws2812_strip.py): a bitstream decoded as a
WS2812 decodes it (GRB order, a LED per 24 bits, the latch after reset_us), colours as
outputs, and a timing out of the datasheet's tolerance counted and named (any colours,
any timing: hypothesis)."""

from hypothesis import given, settings
from hypothesis import strategies as st

from sim_plant.catalogue.assembly import assemble

WS2812 = (400, 850, 800, 450)


def strip(count=3, **options):
    return assemble({"body": "bench", "parts": [{"kind": "ws2812_strip", "name": "leds", "count": count, **options}]})


def test_a_frame_shows_at_the_latch_in_grb_order_one_led_per_24_bits():
    p = strip()
    p.bitstream("leds.din", WS2812, bytes((0, 255, 0, 255, 0, 0, 0, 0, 7, 9, 9, 9)))  # red, green, blue; a 4th
    assert p.output("leds.led0") == 0, "nothing shows before the latch"
    changes = p.advance_to(1_000)
    assert [(c.name, c.value) for c in changes] == [("leds.led0", 0xFF0000), ("leds.led1", 0x00FF00), ("leds.led2", 7)]
    # 12 bytes at 1.25 us a bit: 120 us, then the 280 us reset
    assert changes[0].t_us == 120 + 280
    assert p.truth()["leds_lit"] == 3 and p.truth()["leds_timing_faults"] == 0


def test_a_stream_before_the_latch_goes_on_with_the_same_frame():
    p = strip(count=2)
    p.bitstream("leds.din", WS2812, bytes((0, 255, 0)))
    p.advance_to(100)  # 30 us of stream, the line low for 70 us: no latch yet
    p.bitstream("leds.din", WS2812, bytes((255, 0, 0)))
    p.advance_to(2_000)
    assert p.output("leds.led0") == 0xFF0000 and p.output("leds.led1") == 0x00FF00


def test_a_timing_out_of_tolerance_is_counted_named_and_decoded_as_the_chip_would():
    p = strip(count=1)
    p.bitstream("leds.din", (800, 1700, 1600, 900), bytes((0, 1, 0)))  # the 400 kHz tuple
    p.advance_to(5_000)
    assert p.truth()["leds_timing_faults"] == 1
    assert p.output("leds.led0") == 0xFFFFFF, "every high is long enough to read as a 1: white"
    problem = p.input_owner("leds.din").timing_problem
    assert "high_0 800 ns" in problem and "low_0 1700 ns" in problem and "within 150 ns" in problem
    p.bitstream("leds.din", (450, 800, 750, 500), bytes((0, 1, 0)))  # 50 ns off: within
    p.advance_to(10_000)
    assert p.truth()["leds_timing_faults"] == 1 and p.output("leds.led0") == 0x010000


def test_a_frame_in_bursts_of_one_kind_of_bit_is_one_write_and_no_fault():
    """A PIO program's frame comes as bursts as its FIFO fills; a burst of black has no 1
    bit (its times unmeasured: None), one of white no 0: neither is out of tolerance."""
    p = strip(count=2)
    p.bitstream("leds.din", (250, 1000, None, None), bytes(3))
    p.advance_to(40)  # (30 us of stream, 10 us low: the same frame)
    p.bitstream("leds.din", (None, None, 875, 375), bytes((255,) * 3))
    p.advance_to(2_000)
    assert p.output("leds.led0") == 0 and p.output("leds.led1") == 0xFFFFFF
    assert p.truth()["leds_timing_faults"] == 0 and p.truth()["leds_writes"] == 1, p.truth()
    p.bitstream("leds.din", (250, 1000, None, None), bytes(6))
    p.advance_to(4_000)
    assert p.output("leds.led1") == 0 and p.truth()["leds_writes"] == 2


rgb = st.tuples(*[st.integers(0, 255)] * 3)


@settings(max_examples=50, deadline=None)
@given(colours=st.lists(rgb, min_size=1, max_size=8), timing=st.tuples(*[st.integers(0, 3000)] * 4))
def test_any_colours_sent_in_grb_order_show_and_a_timing_is_a_fault_iff_one_time_is_off(colours, timing):
    p = strip(count=len(colours))
    p.bitstream("leds.din", WS2812, bytes(c for r, g, b in colours for c in (g, r, b)))
    p.advance_to(100_000)
    assert [p.output(f"leds.led{i}") for i in range(len(colours))] == [r << 16 | g << 8 | b for r, g, b in colours]
    p.bitstream("leds.din", timing, b"\x00")
    off = any(abs(t - want) > 150 for t, want in zip(timing, WS2812))
    assert p.truth()["leds_timing_faults"] == int(off)

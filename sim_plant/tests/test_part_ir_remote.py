"""The ir_remote part: an NEC frame's bursts and spaces on the receiver's output (low
during a burst), repeat codes every 108 ms while a key is held, and the keys sent."""

from sim_plant.catalogue.assembly import assemble


def edges(presses, until_us, address=0):
    plant = assemble(
        {"body": "bench", "parts": [{"kind": "ir_remote", "name": "ir", "address": address, "presses": presses}]}
    )
    assert plant.output("ir.out") == 1, "idle high (no carrier)"
    return plant, [(c.t_us, c.value) for c in plant.advance_to(until_us) if c.name == "ir.out"]


def decode(changes, t0):
    """The word of one frame from its edges (a space of 1687.5 us is a 1)."""
    lows = [t for t, v in changes if v == 0]
    highs = [t for t, v in changes if v == 1]
    assert lows[0] == t0 and highs[0] - t0 == 9_000 and lows[1] - highs[0] == 4_500
    word = 0
    for i in range(32):
        space = lows[i + 2] - highs[i + 1]
        assert highs[i + 1] - lows[i + 1] in (562, 563), "each bit's burst: 562.5 us"
        assert space in (562, 563, 1687, 1688), space
        word |= (space > 1_000) << i
    return word


def test_a_tap_sends_one_frame_address_command_and_their_inverses():
    plant, changes = edges([[0.1, 0x18, 0.0]], 400_000, address=0x04)
    assert len(changes) == 2 + 2 * 32 + 2, "start burst and space, 32 bits, the last burst"
    assert decode(changes, 100_000) == 0x04 | 0xFB << 8 | 0x18 << 16 | 0xE7 << 24
    assert changes[-1] == (100_000 + 9_000 + 4_500 + 32 * 1_125 + 16 * 1_125 + round(562.5), 1)
    assert plant.truth()["ir_sent"] == [0x18]


def test_a_held_key_sends_repeat_codes_every_108_ms_and_the_next_key_after_them():
    _plant, changes = edges([[0.1, 0x5A, 0.25], [0.3, 0x1C, 0.0]], 600_000)
    lows, highs = [t for t, v in changes if v == 0], [t for t, v in changes if v == 1]
    starts = [low for low, high in zip(lows, highs, strict=True) if high - low == 9_000]  # (the 9 ms bursts)
    assert starts[:3] == [100_000, 208_000, 316_000], "the frame, then a repeat code every 108 ms while held"
    repeat = [(t - 208_000, v) for t, v in changes if 208_000 <= t < 300_000]
    assert repeat == [(0, 0), (9_000, 1), (11_250, 0), (round(11_812.5), 1)], "9 ms, 2.25 ms, a 562.5 us burst"
    assert starts[3] == round(316_000 + 11_812.5 + 4_500), "the next key 4.5 ms after the last repeat's burst"
    assert decode([c for c in changes if c[0] >= starts[3]], starts[3]) >> 16 & 0xFF == 0x1C

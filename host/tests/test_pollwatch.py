"""The poll watch (host/rig/hardware/pollwatch.py) on its own: a poll is named once, only when its
reads in a row with one answer reach the count over the span of virtual time; a changed
answer starts the count again; the note names the chip's modelled registers."""

from host.rig.hardware.pollwatch import PollWatch, poll_text, shim_poll_text
from sim_plant import buses as B
from sim_plant.catalogue.assembly import assemble


def poll(watch, n, t0_us, step_us, answer=b"\x00", key=("i2c0", 0x6A, 0x1E)):
    named = [watch.seen(t0_us + i * step_us, *key, answer) for i in range(n)]
    return [x for x in named if x is not None]


def test_a_poll_is_named_once_after_its_count_over_its_span_of_virtual_time():
    watch = PollWatch(reads=100, span_us=10_000)
    assert poll(watch, 99, 0, 200) == [], "99 reads: under the count"
    assert poll(PollWatch(reads=100, span_us=10_000), 500, 0, 10) == [], "500 reads within 5 ms: under the span"
    watch = PollWatch(reads=100, span_us=10_000)
    assert poll(watch, 300, 0, 200) == [(0, 100)], "named once, at the 100th read, since its first"


def test_a_changed_answer_or_another_register_starts_the_count_again():
    watch = PollWatch(reads=100, span_us=10_000)
    for i in range(300):
        answer = b"\x01" if i % 50 == 49 else b"\x00"  # (a bit that sets now and then: a poll that ends)
        assert watch.seen(i * 200, "i2c0", 0x6A, 0x1E, answer) is None
    assert poll(watch, 99, 0, 200, key=("i2c0", 0x6A, 0x1F)) == []


def test_the_note_says_what_the_chips_model_honours_at_that_register():
    p = assemble({"body": "bench", "parts": [{"kind": "lsm6dsox", "name": "imu", "bus": "i2c0"}]})
    device = p.bus_device("i2c0", 0x6A)
    text = poll_text(2_000_000, "i2c0", 0x6A, 0x1E, b"\x00", 500_000, 10_000, device)
    assert "read i2c0 0x6a register 0x1e 10000 times from virtual t=0.500000 s to t=2.000000 s" in text, text
    assert "the model honours STATUS_REG: XLDA, GDA" in text and "0x12 CTRL3_C: BOOT" in text, text
    unmodelled = poll_text(2_000_000, "i2c0", 0x6A, 0x5A, b"\x00", 0, 10_000, device)
    assert "plain memory: only a write changes it" in unmodelled, unmodelled
    assert "no chip of the plant answers there" in poll_text(1, "i2c0", 0x50, 0, b"", 0, 1, None)
    assert p.bus_transfer("i2c0", B.XFER, 0x6A, 1, b"\x0f")[2] == b"\x6c"


def test_a_shim_poll_names_its_pin_and_what_would_change_it_or_its_address():
    """A POLL message's note (host/rig/hardware/pollwatch.py, shim_poll_text): the pin by its board
    name, and what drives it by the wiring (a part, nothing, a probe, a plant input); an
    address with the shim's word on it; the firmware's stack when the message carries one."""
    from host.link import frames as F
    from host.rig.hardware.wiring import Wiring

    p = assemble({"body": "bench", "parts": [{"kind": "button", "name": "go"}, {"kind": "jumper", "name": "j"}]})
    pins = {"GO": 4, "LOOSE": 5, "PROBE": 6, "BACK": 7}
    wiring = Wiring({"GO": "go.out", "PROBE": "probe:scope", "BACK": "j.in"}, pins, "pins", sensors=p.outputs)
    for h, key in enumerate(("4", "5", "6", "7")):
        wiring.configure(h, F.CFG_PIN, F.PIN_IN, F.PULL_UP, key, -1)

    def note(h, value=1, words=b""):
        return shim_poll_text((2_500_000, 1_000_000, 12_000, F.POLL_PIN, 1, h, value, words), wiring, p)

    assert "read pin GO (4) with Pin.value() 12000 times from virtual t=1.000000 s to t=2.500000 s and got 1" in note(0)
    assert "button go drives it (go.out), and kept it at 1 (a scenario's set-control of go's pressed" in note(0)
    assert "pin 5 with Pin.value()" in note(1) and "wired to nothing in the rig, so nothing drives it" in note(1)
    assert "wired to probe:scope, which only the harness watches: nothing drives it" in note(2)
    assert "wired to j.in, an input of the plant: nothing drives it" in note(3)
    assert note(0, words=b"\nmain.py:30 <module>\nmain.py:12 wait").endswith(
        "; the firmware's stack, outermost first: main.py:30 <module> > main.py:12 wait"
    )
    mem = shim_poll_text((2_000_000, 900_000, 10_000, F.POLL_MEM, 16, 0x20000100, 0xBEEF, b"plain memory"), wiring, p)
    assert "read machine.mem16[0x20000100] 10000 times" in mem and "got 0xbeef each time; plain memory" in mem, mem

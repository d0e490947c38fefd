"""Parts wire and uart_wire on a bench body: a loopback bench (what the ``wires`` plant
kind was), zero-delay, PWM waveforms and UART bytes timed at the baud rate."""

import pytest

from sim_plant.catalogue.assembly import PartsError, assemble


def bench(*parts):
    return assemble({"body": "bench", "parts": list(parts)})


def wire(name):
    return {"kind": "wire", "name": name}


def test_a_plant_with_a_wire_is_zero_delay_and_one_without_is_not():
    assert bench(wire("w0")).zero_delay is True
    assert bench({"kind": "probe", "name": "led"}).zero_delay is False


def test_a_level_written_is_on_the_output_at_the_same_instant_in_write_order():
    plant = bench(wire("w0"), wire("w1"))
    plant.advance_to(100)
    plant.set_input("w1.in", 1)
    plant.set_input("w0.in", 1)
    assert plant.next_change_us() == 100
    changes = plant.advance_to(100)
    assert [tuple(c) for c in changes] == [(100, "w1.out", 1), (100, "w0.out", 1)]
    assert plant.output("w0.out") == 1 and plant.truth()["w1_edges"] == 1
    assert "x_m" not in plant.truth(), "a bench has no pose"


def test_a_burst_of_writes_at_one_instant_comes_out_limit_at_a_time():
    plant = bench(wire("w0"))
    for i in range(10):
        plant.set_input("w0.in", (i + 1) % 2)
    first, second = plant.advance_to(0, limit=4), plant.advance_to(0, limit=4)
    assert len(first) == 4 and len(second) == 4 and plant.t_us == 0
    assert len(plant.advance_to(0, limit=4)) == 2


def test_a_pwm_drives_the_output_with_its_waveform_to_the_microsecond():
    plant = bench(wire("w0"))
    plant.set_pwm("w0.in", 1000, 65535 // 4)  # 1 kHz, a quarter high
    changes = plant.advance_to(3000)
    assert [(c.t_us, c.value) for c in changes] == [
        (0, 1),
        (250, 0),
        (1000, 1),
        (1250, 0),
        (2000, 1),
        (2250, 0),
        (3000, 1),
    ]
    plant.set_pwm("w0.in", 1000, 0)
    assert [c.value for c in plant.advance_to(3000)] == [0] and plant.next_change_us() > 10**12


def test_a_snapshot_brings_a_waveform_back():
    plant = bench(wire("w0"))
    plant.set_pwm("w0.in", 500, 32768)
    snap = plant.snapshot()
    once = plant.advance_to(10_000)
    plant.restore(snap)
    assert plant.advance_to(10_000) == once


def test_a_uart_wire_brings_the_bytes_back_at_the_baud_rate():
    plant = bench({"kind": "uart_wire", "name": "u0"})
    assert plant.inputs["u0.line"] == "uart" and plant.outputs["u0.line"] == "bytes"
    plant.send_bytes("u0.line", b"ab", 115200)
    changes = plant.advance_to(1000)
    assert [(c.t_us, c.value) for c in changes] == [(87, b"a"), (174, b"b")]
    assert plant.output("u0.line") == b"", "a UART configured on the line reads nothing yet"


def test_a_wire_input_that_is_not_there_is_refused_by_name():
    plant = bench(wire("w0"))
    with pytest.raises(KeyError, match="no wire input 'w9.in'"):
        plant.set_pwm("w9.in", 1000, 100)


def test_a_wire_needs_no_body_and_two_of_one_name_are_refused():
    with pytest.raises(PartsError, match=r"#2 \(w0\) name"):
        bench(wire("w0"), wire("w0"))


def test_a_board_uart_carries_each_side_s_bytes_to_the_other_side_each_direction_on_its_own_line():
    plant = bench({"kind": "board_uart", "name": "link"}, {"kind": "uart_wire", "name": "u0"})
    plant.advance_to(1000)
    plant.send_bytes("link.a", b"ab", 115_200)  # 86.8 us a byte
    plant.send_bytes("link.b", b"x", 9_600)  # 1041.7 us a byte, at the same time the other way
    changes = [tuple(c) for c in plant.advance_to(3000)]
    assert changes == [(1087, "link.b", b"a"), (1174, "link.b", b"b"), (2042, "link.a", b"x")]
    assert plant.output("link.a") == b"" and plant.zero_delay is True


def _bytes_both_ways(step_us: int, alone: bool = True) -> tuple:
    """A board_uart's bytes (and, from 30 ms on, a PWM on a wire of the same timeline) as
    the plant gives them, advanced ``step_us`` at a time; (changes, next change, truth).
    ``alone``: False, the engine fires the wire at each instant, never its bytes at once."""
    plant = bench({"kind": "board_uart", "name": "link"}, wire("w"))
    if not alone:
        plant._alone = False  # (as a plant that reacts at each instant: _fire_alone is not asked)
    got = []
    for k in range(8):  # (a line each way every 10 ms; bytes of both lines at the same instants)
        t = k * 10_000
        while plant.t_us < t:
            got += plant.advance_to(min(t, plant.t_us + step_us))
        plant.send_bytes("link.a", b"%d\n" % (k * 37), 115_200)
        plant.send_bytes("link.b", b"x" * (k + 1), 57_600)
        if k == 3:
            plant.set_pwm("w.in", 1_000, 20_000)
    while plant.t_us < 90_000:
        got += plant.advance_to(min(90_000, plant.t_us + step_us))
    return [tuple(c) for c in got], plant.next_change_us(), plant.truth()


def test_a_board_uart_s_bytes_fired_at_once_are_those_fired_an_instant_at_a_time():
    each_instant = _bytes_both_ways(90_000, alone=False)
    for got in (_bytes_both_ways(90_000), _bytes_both_ways(1), _bytes_both_ways(1, alone=False)):
        first = next((i for i, (a, b) in enumerate(zip(got[0], each_instant[0], strict=False)) if a != b), None)
        assert got == each_instant, (
            f"expected the changes, next change and truth of the wire fired an instant at a time; got "
            f"{len(got[0])} changes against {len(each_instant[0])}, the first other at #{first}, "
            f"next change {got[1]} against {each_instant[1]}"
        )
    assert len(each_instant[0]) > 100 and any(c[1] == "w.out" for c in each_instant[0])


def test_a_button_sharing_a_chips_input_passes_the_pins_drive_on_and_is_read_once_let_go():
    """A button on a chip's line (``shares``, the 3pi+ 2040's button C on the display's DC):
    the pin's level goes on to the chip's input at the same instant; let go, the line is
    the button's (released 1 on its pull-up, pressed 0), and the chip's input keeps the
    pin's last drive."""
    plant = bench(wire("dc"), {"kind": "button", "name": "c", "shares": "dc.in", "presses": [[0.001, 0.002]]})
    assert plant.zero_delay is True and "c.out" in plant.inputs and "c.out" in plant.outputs
    plant.set_input("c.out", 1)
    got = [tuple(ch) for ch in plant.advance_to(0)]
    assert got == [(0, "dc.out", 1)], f"the line was high already (released, on its pull-up): {got}"
    plant.set_input("c.out", 0)
    got = [tuple(ch) for ch in plant.advance_to(10)]
    assert got == [(0, "dc.out", 0), (0, "c.out", 0)], got
    plant.set_input("c.out", -1)  # (the pin let go: an input with its pull-up)
    got = [tuple(ch) for ch in plant.advance_to(1500)]
    assert got == [(10, "c.out", 1), (1000, "c.out", 0)], f"released, then pressed at 1 ms: {got}"
    assert plant.output("dc.out") == 0, "the chip's input keeps the pin's last drive"


def test_a_button_sharing_no_such_input_is_refused_naming_the_inputs():
    with pytest.raises(PartsError) as e:
        bench(wire("dc"), {"kind": "button", "name": "c", "shares": "display.dc"})
    assert str(e.value) == (
        "[[plant.parts]] #2 (c) shares: expected inputs of the plant's parts (dc.in), got 'display.dc'"
    ), e.value


def test_a_battery_sharing_a_chips_input_passes_the_pins_drive_on_and_low_once_let_go():
    """A battery's divider on a chip's line (``shares``, the 3pi+ 2040's GP26: the down
    emitters' control): the pin's level goes on to the chip's input; let go, the chip's input
    is low (the divided voltage is under a logic high), and the ADC reads the divider all along."""
    battery = {
        "kind": "battery",
        "name": "bat",
        "full_v": 4.8,
        "empty_v": 4.0,
        "divider_ratio": 1 / 11,
        "shares": "em.in",
    }
    plant = bench(wire("em"), battery)
    assert "bat.adc" in plant.inputs and "bat.adc" in plant.outputs
    reading = plant.output("bat.adc")
    plant.set_input("bat.adc", 1)
    assert [tuple(ch) for ch in plant.advance_to(0)] == [(0, "em.out", 1)]
    plant.set_input("bat.adc", -1)
    assert [tuple(ch) for ch in plant.advance_to(50)] == [(0, "em.out", 0)]
    assert plant.output("bat.adc") == reading and abs(reading / 65535 * 3.3 * 11 - 4.8) < 0.01, reading

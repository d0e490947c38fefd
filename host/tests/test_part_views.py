"""The signals plot of a robot built from parts, from hand-made traces: every part draws
its declared view (ranges through the part's law, signed commands from each bridge's
pins, encoder counts decoded from A/B, a servo's asked angle, a battery's volts), nothing
chosen by the app's name; and the trace header keeps the body and parts it needs."""

from pathlib import Path

import numpy as np
import pytest

from host.artefacts.folder import TraceData
from host.report import part_views, views
from sim_plant.catalogue.assembly import assemble
from sim_plant.scripted import ScriptedPlant

CAR = {
    "body": "ackermann",
    "parts": [
        {"kind": "dc_motor", "name": "drive", "bridge": "drv8833", "drives": "rear"},
        {"kind": "servo", "name": "steer", "steers": True},
        {"kind": "hcsr04", "name": "sonar", "mount": {"x_m": 0.2}},
        {"kind": "battery", "name": "batt", "divider_ratio": 0.25},
        {"kind": "encoder", "name": "enc", "wheel": "left", "lines_per_rev": 10, "on": "wheel"},
        {"kind": "probe", "name": "led"},
    ],
}


def car_trace(events, truth=None, robot=CAR) -> TraceData:
    plant = assemble(robot)
    header = {"app": "anything", "parts": plant.describe(), "initial": {}, "t_end_us": 1_000_000}
    header["signals"] = {n: {"role": "x", "kind": k} for n, (_d, k) in plant.signals().items()}
    columns = {k: np.asarray(v, dtype=np.int64 if k == "t_us" else float) for k, v in (truth or {}).items()}
    return TraceData(Path("."), header, sorted(events, key=lambda e: e[0]), columns, [])


def lines_of(panels) -> dict:
    return {line.label: line for p in panels for line in p.lines}


def test_the_header_keeps_the_body_and_each_part_with_its_options():
    described = assemble(CAR).describe()
    assert described["body"] == "ackermann" and described["body_options"]["wheelbase_m"] == 0.16
    sonar = described["parts"][2]
    assert sonar["kind"] == "hcsr04" and sonar["mount"] == {"x_m": 0.2, "y_m": 0.0, "heading_deg": 0.0}
    assert sonar["options"]["max_range_m"] == 4.0
    scripted = ScriptedPlant(outputs={"x": "level"}, inputs={})
    assert scripted.describe() is None, "a plant of another kind: no parts"


def test_each_part_draws_its_view_through_its_own_law_with_the_truth_beside_it():
    events = [
        (100_000, "sonar.echo", 1),
        (100_000 + 5831, "sonar.echo", 0),  # 1.00 m
        (200_000, "sonar.echo", 1),
        (238_000, "sonar.echo", 0),  # a time-out: nothing in range
        (0, "steer.pwm", int(1500 / 20000 * 65535)),  # 1.5 ms: 90 degrees
        (300_000, "steer.pwm", int(2500 / 20000 * 65535)),  # 2.5 ms: 180
        (0, "batt.adc", 32768),  # 1.65 V at the ADC, x4 through the divider
    ]
    truth = {"t_us": [0, 500_000], "sonar_ping_range_m": [1.0, 1.0], "steer_angle_deg": [90, 180], "batt_v": [6.6, 6.6]}
    panels = part_views.part_panels(car_trace(events, truth))
    lines = lines_of(panels)
    assert lines["sonar: read by the firmware"].values[0] == pytest.approx(1.0, abs=0.001)
    assert np.isnan(lines["sonar: read by the firmware"].values[1])
    ranges = next(p for p in panels if p.title.startswith("Rangers"))
    assert ranges.notes == ["sonar: 1 of 2 readings found nothing in range (not drawn)"]
    assert "sonar_ping_range_m (truth)" in lines and "steer_angle_deg (truth)" in lines
    assert lines["steer: asked by the firmware's pulse"].values == pytest.approx([90, 180], abs=0.1)
    assert lines["batt: read by the firmware"].values == pytest.approx([6.6], abs=0.001)
    assert "batt_v (truth)" in lines


@pytest.mark.parametrize(
    ("bridge", "events", "expected"),
    [
        ("tb6612", [(0, "m.in1", 1), (0, "m.pwm", 65535), (10, "m.in1", 0), (10, "m.in2", 1)], [0, 1, 0, -1]),
        ("drv8833", [(0, "m.in1", 65535), (10, "m.in1", 0), (20, "m.in2", 32768)], [1, 0, -0.5]),
        ("dir_pwm", [(0, "m.pwm", 65535), (10, "m.dir", 1)], [-1, 1]),
    ],
)
def test_a_motor_command_is_signed_as_its_bridge_pins_make_it(bridge, events, expected):
    from sim_plant import catalogue

    part = catalogue.parts()["dc_motor"]("m", {}, {**catalogue.parts()["dc_motor"].defaults(), "bridge": bridge})
    recorded = part_views.Recorded(TraceData(Path("."), {"initial": {}}, events, {}, []))
    _t, duty = part_views.signed_command(recorded, part)
    assert duty == pytest.approx(expected, abs=1e-4)


def test_an_encoder_is_decoded_x4_from_its_channels_and_its_speed_from_its_options():
    events, a, b = [], 0, 0
    for k in range(40):  # 40 quadrature states forward (A leads B), one every 10 ms
        if k % 2 == 0:
            a = 1 - a
            events.append((k * 10_000, "enc.a", a))
        else:
            b = 1 - b
            events.append((k * 10_000, "enc.b", b))
    panels = part_views.part_panels(car_trace(events, {"t_us": [0, 400_000], "enc_edges": [0, 40]}))
    lines = lines_of(panels)
    count = lines["enc: decoded (x4 from A/B)"]
    assert count.values[-1] == 40 and list(count.values) == sorted(count.values)
    metres_per_edge = 2 * np.pi * 0.0325 / 40  # the body's wheel (its default), 10 lines x 4, on the wheel
    speed = next(line for label, line in lines.items() if label.startswith("enc: edges x"))
    assert speed.values[0] == pytest.approx(10 * metres_per_edge / 0.1)


def test_the_signals_plot_of_a_parts_robot_has_a_panel_per_view_and_no_generic_one():
    events = [(0, "drive.in1", 65535), (0, "led.in", 1), (0, "batt.adc", 30000), (0, "steer.pwm", 4915)]
    titles = [p.title.split(":")[0] for p in views.signal_panels(car_trace(events))]
    assert titles == ["Motors", "Servos", "Batteries", "Levels"], titles


def test_a_led_strip_draws_each_leds_colours_as_bars_on_a_row_of_its_own():
    from matplotlib.figure import Figure

    from host.report import plots

    plant = assemble({"body": "bench", "parts": [{"kind": "ws2812_strip", "name": "leds", "count": 2}]})
    header = {"app": "strip", "parts": plant.describe(), "initial": {}, "t_end_us": 1_000_000}
    events = [(400, "leds.led0", 0xFF0000), (400, "leds.led1", 0x00FF00), (500_000, "leds.led0", 0x101010)]
    truth = {"t_us": np.asarray([0, 500_000]), "leds_timing_faults": np.asarray([0.0, 1.0])}
    panels = part_views.part_panels(TraceData(Path("."), header, events, truth, []))
    (strip,) = [p for p in panels if p.title.startswith("LED strips")]
    assert strip.notes == ["leds: 1 streams out of the WS2812's timing (decoded as a chip would)"]
    led0, led1 = strip.lines
    assert (led0.label, led0.style) == ("leds.led0", "colours")
    assert list(led0.values) == [0, 0xFF0000, 0x101010] and list(led1.values) == [0, 0x00FF00]
    ax = Figure().subplots()
    plots._draw_panel(ax, strip, [], end_s=1.0)
    bars = ax.collections
    assert len(bars) == 5, "a bar per colour held: 3 on LED 0's row, 2 on LED 1's"
    assert tuple(bars[1].get_facecolor()[0][:3]) == (1.0, 0.0, 0.0)


def test_a_board_of_a_set_draws_its_own_pins_and_every_parts_truth():
    """A board's trace header names the signals its pins are wired to (``wired``): another
    board's motor, encoder and probe are not drawn as this board's (a command at zero, a
    level low for the whole run), their truth is (the plant is shared)."""
    events = [(0, "sonar.echo", 1), (5831, "sonar.echo", 0), (0, "drive.in1", 65535), (0, "led.in", 1)]
    events += [(k * 10_000, "enc.a" if k % 2 == 0 else "enc.b", (k // 2 + 1) % 2) for k in range(8)]
    truth = {"t_us": [0, 500_000], "sonar_ping_range_m": [1.0, 1.0], "enc_edges": [0, 8]}
    whole = lines_of(part_views.part_panels(car_trace(events, truth)))
    trace = car_trace(events, truth)
    trace.header["wired"] = ["sonar.echo", "sonar.trig"]
    board = lines_of(part_views.part_panels(trace))
    assert {"drive (drv8833)", "led.in (row 0)", "enc: decoded (x4 from A/B)"} <= set(whole), sorted(whole)
    assert set(board) == {"sonar: read by the firmware", "sonar_ping_range_m (truth)", "enc_edges (truth)"}, (
        f"expected the sonar's reading and every part's truth, got {sorted(board)}"
    )


def test_a_buzzers_tone_is_drawn_on_its_row_while_driven_whatever_its_duty_scale():
    """A PWM a buzzer takes (picozero's Speaker drives duty_u16 1023, a quiet tone) is on its
    row while its duty is above 0, within the row's 0.8, not its raw duty above every row."""
    bench = {"body": "bench", "parts": [{"kind": "buzzer", "name": "spk"}, {"kind": "probe", "name": "led"}]}
    events = [(100_000, "spk.in", 1023), (300_000, "spk.in", 0), (500_000, "spk.in", 65535)]
    lines = lines_of(part_views.part_panels(car_trace(events, robot=bench)))
    (label,) = [k for k in lines if k.startswith("spk.in")]
    assert label == "spk.in on while its duty > 0 (row 0)", sorted(lines)
    values = list(lines[label].values)
    assert values == [0.0, 0.8, 0.0, 0.8, 0.8], f"expected off, on, off, on (to the end): {values}"

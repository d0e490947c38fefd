"""The VCD writer: structure a wave viewer accepts, every change at its time, and GTKWave's
own reader (vcd2fst, fst2vcd) reading back what was written."""

from host.artefacts.vcd import write_gtkw, write_vcd
from host.tests.vcd_reader import gtkwave_round_trip, read_vcd

SIGNALS = {
    "enc_l.a": {"role": "sensor", "kind": "level"},
    "sonar.adc": {"role": "sensor", "kind": "u16"},
    "gps.uart": {"role": "sensor", "kind": "bytes"},
    "motor_l.pwm": {"role": "actuator", "kind": "duty"},
    "motor_l.in1": {"role": "actuator", "kind": "level"},
    "probe:control": {"role": "probe", "kind": "level"},
}
INITIAL = {"enc_l.a": 0, "sonar.adc": 20164, "gps.uart": ""}
EVENTS = [
    (0, "motor_l.in1", 1),
    (0, "motor_l.pwm", 30000),
    (0, "probe:control", 1),
    (1000, "enc_l.a", 1),
    (1000, "enc_l.a", 0),  # a glitch inside one microsecond: the last value stands
    (1000, "enc_l.a", 1),
    (20000, "sonar.adc", 1234),
    (20000, "gps.uart", "2441"),  # "$A": the last byte is 0x41
    (50000, "probe:control", 0),
    (50000, "motor_l.pwm", 65535),
]
TRUTH = [(0, {"t_us": 0, "x_m": 1.0, "y_m": 2.0}), (50000, {"t_us": 50000, "x_m": 1.015625, "y_m": 2.0})]


def write(tmp_path, **overrides):
    args = dict(top="rover", comment="app rover seed 7", signals=SIGNALS, initial=INITIAL, events=EVENTS, truth=TRUTH)
    args.update(overrides)
    path = tmp_path / "trace.vcd"
    write_vcd(path, **args)
    return path


def test_vcd_declares_each_signal_by_role_with_its_type_and_keeps_every_change_in_time_order(tmp_path):
    path = write(tmp_path)
    vcd = read_vcd(path.read_text())
    assert vcd.sections["$timescale"] == "1us", vcd.sections
    types = {p: (v.type, v.width) for p, v in vcd.vars.items()}
    assert types == {
        "rover.sensors.enc_l.a": ("wire", 1),
        "rover.sensors.sonar.adc": ("integer", 32),
        "rover.sensors.gps.uart": ("wire", 8),
        "rover.sensors.gps.uart_text": ("string", 1),
        "rover.actuators.motor_l.pwm": ("integer", 32),
        "rover.actuators.motor_l.in1": ("wire", 1),
        "rover.probes.control": ("wire", 1),
        "rover.truth.x_m": ("real", 64),
        "rover.truth.y_m": ("real", 64),
    }, types
    assert vcd.times == [0, 1000, 20000, 50000], vcd.times
    assert vcd.timeline("rover.sensors.enc_l.a") == [(0, 0), (1000, 1)]
    assert vcd.timeline("rover.sensors.sonar.adc") == [(0, 20164), (20000, 1234)]
    assert vcd.timeline("rover.sensors.gps.uart") == [(0, "x"), (20000, 0x41)]
    assert vcd.timeline("rover.actuators.motor_l.pwm") == [(0, 30000), (50000, 65535)]
    assert vcd.timeline("rover.probes.control") == [(0, 1), (50000, 0)]
    assert vcd.timeline("rover.truth.x_m") == [(0, 1.0), (50000, 1.015625)]


def test_an_output_the_firmware_has_not_driven_yet_is_unknown_until_it_does(tmp_path):
    vcd = read_vcd(write(tmp_path, events=EVENTS[3:]).read_text())
    assert vcd.timeline("rover.actuators.motor_l.in1") == [(0, "x")]
    assert vcd.timeline("rover.actuators.motor_l.pwm") == [(0, "x"), (50000, 65535)]


def test_identifier_codes_stay_unique_past_the_94_printable_characters(tmp_path):
    signals = {f"pin.p{i}": {"role": "pin", "kind": "level"} for i in range(300)}
    events = [(i + 1, f"pin.p{i}", 1) for i in range(300)]
    vcd = read_vcd(write(tmp_path, signals=signals, initial={}, events=events, truth=[]).read_text())
    codes = [v.code for v in vcd.vars.values()]
    assert len(set(codes)) == 300 and max(map(len, codes)) == 2
    assert all(vcd.timeline(f"rover.pins.pin.p{i}") == [(0, "x"), (i + 1, 1)] for i in range(300))


def test_gtkwave_reads_back_every_change_that_was_written(tmp_path):
    path = write(tmp_path)
    ours, theirs = read_vcd(path.read_text()), read_vcd(gtkwave_round_trip(path, tmp_path))
    assert set(theirs.vars) == set(ours.vars), (sorted(ours.vars), sorted(theirs.vars))
    for name in ours.vars:
        assert theirs.timeline(name) == ours.timeline(name), f"{name}: GTKWave read {theirs.timeline(name)}"


NMEA = "$GPGGA,1 2\r\n$GPRMC"  # two sentences, the second still arriving


def test_a_uart_is_also_text_the_line_being_received_or_the_one_just_ended(tmp_path):
    chunks = [(10, NMEA[:5]), (20, NMEA[5:10]), (30, NMEA[10:12]), (40, NMEA[12:])]
    events = [(t, "gps.uart", text.encode().hex()) for t, text in chunks]
    vcd = read_vcd(write(tmp_path, events=events).read_text())
    assert vcd.timeline("rover.sensors.gps.uart_text") == [
        (0, ""),
        (10, "$GPGG"),
        (20, "$GPGGA,1 2"),  # (a space in the text: written as an escape)
        (30, "$GPGGA,1 2"),  # the line ended: it stays until the next one starts
        (40, "$GPRMC"),
    ]
    assert vcd.timeline("rover.sensors.gps.uart")[-1] == (40, ord("C"))


def test_console_lines_and_budget_misses_are_events_in_time_order(tmp_path):
    notes = [(0, "console", "boot"), (120_000, "budget_miss", "a.b 61000 us"), (250_000, "console", "tick 0 done")]
    path = write(tmp_path, notes=notes)
    vcd = read_vcd(path.read_text())
    assert vcd.timeline("rover.events.console") == [(0, "boot"), (250_000, "tick 0 done")]
    assert vcd.timeline("rover.events.budget_miss") == [(0, ""), (120_000, "a.b 61000 us")]
    theirs = read_vcd(gtkwave_round_trip(path, tmp_path))
    assert theirs.timeline("rover.events.console") == [(0, "boot"), (250_000, "tick 0 done")], "GTKWave reads the text"


def test_the_gtkwave_save_file_shows_every_variable_grouped_by_role_then_part(tmp_path):
    path = tmp_path / "trace.vcd"
    paths = write_vcd(
        path,
        top="rover",
        comment="c",
        signals=SIGNALS,
        initial=INITIAL,
        events=EVENTS,
        truth=TRUTH,
        notes=[(5, "console", "boot")],
    )
    write_gtkw(tmp_path / "trace.gtkw", "trace.vcd", paths)
    lines = (tmp_path / "trace.gtkw").read_text().splitlines()
    assert '[dumpfile] "trace.vcd"' in lines, lines[:5]
    traced = [line for line in lines if line.startswith("rover.")]
    assert sorted(traced) == sorted(read_vcd(path.read_text()).vars), traced
    groups = [line[1:] for line in lines if line.startswith("-")]
    assert groups[0] == "sensors" and "actuators" in groups and groups.count("motor_l") == 2, groups
    assert groups[-2:] == ["events", "events"], groups  # begun and ended: the last group
    flags = {name: int(prev[1:], 16) for prev, name in zip(lines, lines[1:]) if prev.startswith("@")}
    ascii_flag, dec_flag, bin_flag = 0x800, 0x4, 0x8
    assert flags.get("rover.sensors.enc_l.a", bin_flag) & bin_flag, "a level as a bit"
    assert any(f & ascii_flag for name, f in flags.items() if "uart" in name), flags
    assert any(f & dec_flag for name, f in flags.items() if "adc" in name or "pwm" in name), flags


def test_a_truth_value_is_written_when_it_changes_and_a_repeated_console_line_each_time(tmp_path):
    truth = [(t, {"t_us": t, "x_m": 1.0 + (t >= 100_000), "y_m": 2.0}) for t in range(0, 250_000, 50_000)]
    notes = [(0, "console", "tick"), (50_000, "console", "tick")]
    path = write(tmp_path, truth=truth, notes=notes)
    vcd = read_vcd(path.read_text())
    assert vcd.timeline("rover.truth.y_m") == [(0, 2.0)], "an unchanged truth value is not written again"
    assert vcd.timeline("rover.truth.x_m") == [(0, 1.0), (100_000, 2.0)]
    body = path.read_text().split("$enddefinitions", 1)[1]
    code = vcd.vars["rover.events.console"].code
    assert body.count(f" {code}\n") == 2, f"expected the console line twice in the body:\n{body}"
    theirs = read_vcd(gtkwave_round_trip(path, tmp_path))
    assert theirs.timeline("rover.truth.x_m") == [(0, 1.0), (100_000, 2.0)], "GTKWave reads the same"

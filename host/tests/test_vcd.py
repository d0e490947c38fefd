"""The VCD writer: structure a wave viewer accepts, every change at its time, and GTKWave's
own reader (vcd2fst, fst2vcd) reading back what was written."""

from host.artefacts.vcd import write_vcd
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

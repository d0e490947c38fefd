"""The catalogue (sim_plant/catalogue): every part and body declares itself, the
registry finds each module's one class, bad tables are refused by name, a part's
declared signals and truth are the plant's, and docs/parts.md is the generated page."""

import pytest

from sim_plant import catalogue
from sim_plant.catalogue import docs
from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError
from sim_plant.option_table import Num

MOTORS = [
    {"kind": "dc_motor", "name": "motor_l", "drives": "left"},
    {"kind": "dc_motor", "name": "motor_r", "drives": "right"},
]
PARTS = sorted(catalogue.parts())


def plant_with(kind: str, **options):
    cls = catalogue.parts()[kind]
    entry = {"kind": kind, "name": "p", **options}
    if kind == "track":  # a track is one of a tracked body's two
        return assemble({"body": "tracked", "parts": [entry, {"kind": "track", "name": "t", "side": "right"}]})
    if cls.needs_body:
        extra = [] if kind == "dc_motor" else MOTORS
        entries = [entry, {**MOTORS[1]}] if kind == "dc_motor" else [*extra, entry]
        return assemble({"body": "differential", "parts": entries})
    return assemble({"body": "bench", "parts": [entry]})


def test_the_registry_finds_every_part_and_body_module():
    assert {"differential", "bench", "ackermann", "tracked"} <= set(catalogue.bodies())
    assert {"dc_motor", "encoder", "hcsr04", "analog_ranger", "ir_distance", "bumper", "button"} <= set(PARTS)
    assert {"line_sensor", "battery", "probe", "track", "echo_sounder"} <= set(PARTS)
    for kind, cls in {**catalogue.parts(), **catalogue.bodies()}.items():
        assert cls.__module__ == f"sim_plant.catalogue.{kind}", "one module per part, named after its kind"
        assert cls.doc and all(o.doc for o in cls.OPTIONS)


@pytest.mark.parametrize("kind", PARTS)
def test_a_parts_defaults_are_within_its_bounds_and_its_signals_and_truth_are_the_plants(kind):
    cls = catalogue.parts()[kind]
    for o in cls.OPTIONS:
        assert o.default is None or o.spec.problem(o.default) is None, o
    plant = plant_with(kind)
    part = next(p for p in plant.catalogue_parts if p.name == "p")
    for name, (direction, signal_kind) in part.signals().items():
        tables = {"in": [plant.inputs], "out": [plant.outputs], "io": [plant.inputs, plant.outputs]}[direction]
        for table in tables:
            assert table.get(name) == signal_kind, (name, direction, table)
    truth = plant.truth()
    for key in cls.TRUTH:
        assert key.format(name="p") in truth, (key, sorted(truth))


@pytest.mark.parametrize("kind", PARTS)
def test_every_option_of_a_part_out_of_its_bounds_is_refused_by_name(kind):
    for o in catalogue.parts()[kind].OPTIONS:
        bad = o.spec.hi * 10 + 1 if isinstance(o.spec, Num) else {"bad": 1}
        with pytest.raises(PartsError, match=rf"\[\[plant.parts\]\] #\d \(p\) {o.name}: expected"):
            plant_with(kind, **{o.name: bad})


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ({"body": "hovercraft"}, r"\[plant\] body: expected one of ackermann, bench, desk, differential"),
        ({"body": "differential", "track_m": -1}, r"\[plant\] track_m: expected a number of metres"),
        ({"body": "differential", "wheels": 3}, r"\[plant\] wheels: the differential has no such option"),
        ({"body": "differential", "parts": MOTORS[:1]}, r"needs a dc_motor that drives right"),
        ({"body": "differential", "parts": [*MOTORS, {"kind": "laser", "name": "x"}]}, r"#3 kind: expected one of"),
        ({"body": "differential", "parts": [*MOTORS, {"kind": "hcsr04", "name": "a b"}]}, r"#3 name: expected a name"),
        ({"body": "differential", "parts": [*MOTORS, {**MOTORS[0]}]}, r"#3 \(motor_l\) name: 'motor_l' is part #1"),
        (
            {"body": "differential", "parts": [*MOTORS, {"kind": "hcsr04", "name": "s", "mount": {"z_m": 1}}]},
            r"#3 \(s\) mount z_m: expected one of x_m, y_m, heading_deg",
        ),
        (
            {"body": "differential", "parts": [*MOTORS, {"kind": "hcsr04", "name": "s", "period_us": 5}]},
            r"#3 \(s\) period_us: the hcsr04 has no such option",
        ),
        (
            {"body": "bench", "parts": [{"kind": "hcsr04", "name": "s"}]},
            r"#1 \(s\) kind: a hcsr04 needs a body that moves",
        ),
        (
            {"body": "differential", "parts": [MOTORS[0], {**MOTORS[1], "drives": "left"}]},
            r"needs a dc_motor that drives right",  # (two on the left: a four-wheel car's side, no right)
        ),
        ({"body": "bench", "parts": [{"kind": "button", "name": "b", "presses": [[2, 1]]}]}, r"#1 \(b\) presses"),
        ({"body": "differential", "start_pose": [9, 1, 0]}, r"\[plant\] start_pose: .* outside the room"),
    ],
)
def test_a_bad_plant_table_is_refused_naming_the_field(table, message):
    with pytest.raises(PartsError, match=message):
        assemble(table)


def test_a_bench_has_no_pose_in_its_truth():
    plant = assemble({"body": "bench", "parts": [{"kind": "probe", "name": "led"}]})
    assert "x_m" not in plant.truth() and plant.truth()["led_changes"] == 0


def test_the_snapshot_restores_a_parts_plant():
    plant = assemble({"body": "differential", "parts": [*MOTORS, {"kind": "encoder", "name": "e"}]})
    plant.set_input("motor_l.in1", 1)
    plant.set_input("motor_l.pwm", 65535)
    snap = plant.snapshot()
    first = plant.advance_to(500_000)
    plant.restore(snap)
    assert plant.advance_to(500_000) == first and first


def test_docs_parts_md_is_the_generated_page():
    assert docs.PAGE.read_text() == docs.render(), "run: python -m sim_plant.catalogue.docs"

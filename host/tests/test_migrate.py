"""0.1 rig files (``[plant] kind``): ``load_rig`` stops at them with one message naming
today's form, and ``mpy-fil migrate`` writes that form beside the file, never over it (but
with ``--in-place``) and never through a link (host/core/safefs.py). Whether the written
rigs run as the apps did is ``hil_tests/test_migrate_01.py``'s."""

import shutil

import pytest

from host import cli
from host.core.errors import ConfigError
from host.core.paths import REPO
from host.rig.config.migrate import MigrationError, migrate_text
from host.rig.config.rigfile import load_rig

OLD = REPO / "host" / "tests" / "data" / "rig01" / "pico_bot" / "rig.toml"


@pytest.fixture
def old(tmp_path):
    """The pico_bot's 0.1 rig file beside its firmware, in a folder of the test's own."""
    shutil.copy(REPO / "examples" / "pico_bot" / "main.py", tmp_path / "main.py")
    shutil.copy(OLD, tmp_path / "rig.toml")
    return tmp_path / "rig.toml"


def run(capsys, *args) -> tuple[int, str, str]:
    try:
        code = cli.main(["migrate", *map(str, args)])
    except SystemExit as e:
        code = e.code
    out = capsys.readouterr()
    return code, out.out, out.err


def test_load_rig_names_the_new_form_of_a_0_1_rig_in_one_message(old):
    with pytest.raises(ConfigError) as e:
        load_rig(old)
    said = str(e.value)
    assert "\n" not in said and said.startswith(f"{old}: [plant] kind: kind = 'two_wheel' is 0.1's form"), said
    for text in (
        'body = "differential" with parts motor_l (dc_motor), motor_r (dc_motor), motor (standby), enc_l (encoder)',
        "start (button)",
        "signals renamed: bumper is bumper.out, button.start is start.out",
        f"`mpy-fil migrate {old}` writes it as rig.migrated.toml",
    ):
        assert text in said, f"expected {text!r} in: {said}"


def test_migrate_writes_the_new_form_beside_the_file_and_it_checks(old, capsys):
    before = old.read_bytes()
    code, out, err = run(capsys, old)
    new = old.with_name("rig.migrated.toml")
    assert code == 0, err
    assert out.startswith(f"wrote {new} from {old} (0.1's kind = 'two_wheel'): body = \"differential\""), out
    assert "signal button.start is start.out now" in out and f"then: mpy-fil check {new}" in out, out
    assert old.read_bytes() == before, "the input is never written"
    app = load_rig(new)
    assert app.wiring["BUTTON"] == "start.out" and app.worlds == {"box-ahead": {}, "open-room": {"obstacles": []}}
    text = new.read_text()
    assert "# the GP numbers main.py uses" in text and "[plant.options]" not in text, "comments kept, options moved"
    assert "console_baud = 0" in text and "presses = [[1.0, 1.2]]" in text, text


def test_migrate_never_writes_over_a_file_or_through_a_link(old, capsys, tmp_path):
    new = old.with_name("rig.migrated.toml")
    new.write_text("mine\n")
    code, _, err = run(capsys, old)
    assert code == 2 and "exists" in err and new.read_text() == "mine\n", err
    new.unlink()
    target = tmp_path / "elsewhere.toml"
    new.symlink_to(target)
    code, _, err = run(capsys, old)
    assert code == 2 and "link" in err and not target.exists(), err
    code, _, err = run(capsys, old, "--out", tmp_path.parent / "x.toml")
    assert code == 2 and "expected a file in" in err, err
    code, _, err = run(capsys, old, "--out", old)
    assert code == 2 and "--in-place" in err, err


def test_migrate_refuses_a_linked_input_and_replaces_it_only_in_place(old, capsys, tmp_path):
    link = tmp_path / "linked.toml"
    link.symlink_to(old)
    code, _, err = run(capsys, link)
    assert code == 2 and "link" in err, err
    code, out, err = run(capsys, old, "--in-place")
    assert code == 0 and out.startswith(f"wrote {old} from {old}"), err
    assert load_rig(old).name == "pico_bot" and 'body = "differential"' in old.read_text()
    code, _, err = run(capsys, old, "--in-place")
    assert code == 2 and "expected 0.1's [plant] kind" in err, "a file in today's form is left alone"


@pytest.mark.parametrize(
    ("change", "says"),
    [
        ('bridge = "tb6612"', 'bridge = "tb6612"\nmotor_rpm = 120'),
        ('encoder = "quadrature"', 'encoder = "quadrature"\nranger = "analog"'),
        ('kind = "two_wheel"', 'kind = "hexapod"'),
        ("[worlds.open-room]", '[worlds.open-room]\nbuttons = ["stop"]'),
    ],
)
def test_an_option_with_no_place_today_is_named_not_dropped(change, says):
    text = OLD.read_text().replace(change, says)
    with pytest.raises(MigrationError) as e:
        migrate_text(text)
    said = str(e.value)
    name = says.rpartition("\n")[2].partition(" =")[0] if "\n" in says else "kind"
    assert name in said and "\n" not in said, said


MINIMAL = """name = "bot"
[board]
name = "esp32_devkitc"
[plant]
kind = "{kind}"
{options}
[wiring]
[worlds.here]
{world}
"""


@pytest.mark.parametrize(
    ("kind", "options", "world", "parts"),
    [
        ("rover_room", "", "room_w_m = 6.0", 7),
        ("pool_cleaner", '[plant.options]\nsonar = "adc"\nsonar_period_us = 250000', "pool_width_m = 6.0", 6),
        ("vacuum_robot", "", 'world = "empty"', 7),
        ("duct_robot", "[plant.options]\nlink = true\nslots_per_rev = 16", 'world = "bench"', 9),
        ("lab_robot", "", 'world = "canyon"\nmissed_edge_p = 0.01', 8),
        (
            "two_wheel",
            '[plant.options]\nencoder = "single"\nbumper = false\nranger = "none"\nbuttons = ["a", "b"]',
            "v_max_m_s = 0.3",
            6,
        ),
        ("wires", "[plant.options]\nn = 3", "", 3),
    ],
)
def test_every_0_1_kind_migrates_to_a_rig_that_loads(tmp_path, kind, options, world, parts):
    (tmp_path / "main.py").write_text("")
    text, moved = migrate_text(MINIMAL.format(kind=kind, options=options, world=world))
    (tmp_path / "rig.toml").write_text(text)
    app = load_rig(tmp_path / "rig.toml")
    plant = app.make_plant(**app.worlds["here"])
    assert len(moved.plant["parts"]) == parts and len(plant.catalogue_parts) == parts, moved.summary()
    assert set(app.worlds["here"]) >= {k.partition(" =")[0] for k in world.splitlines() if k} - {"missed_edge_p"}

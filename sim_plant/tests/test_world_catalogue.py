"""Worlds are a catalogue (sim_plant/catalogue/places/): each of ours is an entry with its
options, any body takes any world by its kind (the tracked body in a duct, the
differential in a pool), and a rig file's ``[world]`` table gives the world apart from
the body; ``world = ...`` among the body's options still works (our apps' rig files)."""

import shutil

import pytest

from host.core.errors import ConfigError
from host.core.paths import REPO
from host.rig.config.rigfile import load_rig
from sim_plant import catalogue, world
from sim_plant.catalogue.assembly import assemble, with_world
from sim_plant.catalogue.base import PartsError
from sim_plant.duct import DUCT_START, bench_duct, straight_duct

MOTORS = [
    {"kind": "dc_motor", "name": "motor_l", "drives": "left"},
    {"kind": "dc_motor", "name": "motor_r", "drives": "right"},
]
TRACKS = [{"kind": "track", "name": "track_l", "side": "left"}, {"kind": "track", "name": "track_r", "side": "right"}]
OURS = {  # what the differential body's if/elif built for each named world, and its start
    "canyon": (world.canyon(), (0.3, 0.0, 0.0)),
    "duct": (world.one_right_branch_duct(), DUCT_START),
    "multi_branch_duct": (world.multi_branch_duct(), DUCT_START),
    "vacuum_room": (world.vacuum_room(), (0.5, 0.5, 0.0)),
    "pool": (world.pool(), (1.0, 1.0, 0.0)),
    "straight_duct": (straight_duct(), DUCT_START),
    "bench_duct": (bench_duct(), DUCT_START),
}


def built(table: dict):
    plant = assemble(table)
    plant.reset(seed=3)
    return plant


@pytest.mark.parametrize("kind", sorted(OURS))
def test_each_named_world_is_a_catalogue_entry_building_the_same_walls(kind):
    assert set(OURS) <= set(catalogue.worlds()), "every world the body named"
    plant = built({"body": "differential", "world": kind, "parts": MOTORS})
    walls, start = OURS[kind]
    assert plant.world.segments() == walls.segments() and plant.start_pose == start


def test_any_body_in_any_world():
    tracked = built({"body": "tracked", "world": "duct", "world_options": {"width_m": 0.6}, "parts": TRACKS})
    assert tracked.world.segments() == world.one_right_branch_duct(0.6).segments() and tracked.start_pose == DUCT_START
    pool = built({"body": "tracked", "parts": TRACKS})  # (its own pool and corner start, as before)
    assert pool.world.segments() == world.pool().segments() and pool.start_pose[0] > 24
    small = built({"body": "differential", "world": "pool", "world_options": {"length_m": 10.0}, "parts": MOTORS})
    assert small.world.segments() == world.pool(10.0).segments()
    car = built(
        {
            "body": "ackermann",
            "world": "canyon",
            "parts": [
                {"kind": "dc_motor", "name": "m", "drives": "rear"},
                {"kind": "servo", "name": "steer", "steers": True},
            ],
        }
    )
    assert car.world.segments() == world.canyon().segments()


def test_a_world_table_apart_from_the_body():
    plant = {"body": "differential", "parts": MOTORS}
    assert with_world(plant, {"kind": "duct", "width_m": 0.5}) == {
        **plant,
        "world": "duct",
        "world_options": {"width_m": 0.5},
    }
    assert with_world(plant, {"kind": "room", "room_w_m": 4.0}) == {**plant, "world": "room", "room_w_m": 4.0}
    with pytest.raises(PartsError, match=r"\[world\]: the world is given in \[plant\] too \(world\): give it once"):
        with_world({**plant, "world": "duct"}, {"kind": "duct"})
    with pytest.raises(PartsError, match=r"\[world\] world: not a world's option"):
        with_world(plant, {"kind": "room", "world": "duct"})
    with pytest.raises(PartsError, match=r"\[world\] kind: expected a world's kind"):
        with_world(plant, {"width_m": 0.5})
    with pytest.raises(PartsError, match=r"\[plant\] world_options width_m: expected a number of metres from 0.05"):
        assemble(with_world(plant, {"kind": "duct", "width_m": 0.01}))
    with pytest.raises(PartsError, match=r"\[plant\] world: expected one of room, furnished, .*duct.*got 'moon'"):
        assemble(with_world(plant, {"kind": "moon"}))


def test_a_rig_file_with_a_world_table_and_an_old_one_with_the_world_in_the_body(tmp_path):
    shutil.copytree(REPO / "examples" / "pico_bot", tmp_path / "bot")
    rig = tmp_path / "bot" / "rig.toml"
    text = rig.read_text()
    room = (
        "room_w_m = 3.0\nroom_h_m = 2.0\nobstacles = [[1.6, 1.0, 0.3, 0.3]]      # a box ahead: [cx, cy, w, h] in m\n"
    )
    assert room in text, "the example's room, as the test expects it"
    rig.write_text(
        text.replace(room, "").replace("[[plant.parts]]", '[world]\nkind = "room"\n' + room + "\n[[plant.parts]]", 1)
    )
    app = load_rig(rig)
    plant = app.make_plant()
    plant.reset(seed=1)
    assert plant.world.segments() == world.room(3.0, 2.0, [world.box(1.6, 1.0, 0.3, 0.3)]).segments()
    rig.write_text(rig.read_text().replace('body = "differential"', 'body = "differential"\nworld = "duct"', 1))
    with pytest.raises(ConfigError, match=r"rig.toml: \[world\]: the world is given in \[plant\] too \(world\)"):
        load_rig(rig)
    old = load_rig(REPO / "firmware" / "apps" / "duct" / "rig.toml").make_plant()  # world = "duct" in [plant]
    old.reset(seed=1)
    assert old.world.segments() == world.one_right_branch_duct().segments()

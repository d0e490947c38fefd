"""Our robots' plants as their rig files describe them (``firmware/apps/<app>/rig*.toml``),
for the plant tests: options over the file's ``[plant]`` table, a body's by name and a
part's as ``"<part name>.<option>"``."""

from pathlib import Path

import tomllib

from sim_plant.catalogue.assembly import PartsPlant, assemble

APPS = Path(__file__).resolve().parents[2] / "firmware" / "apps"


def plant_from_rig(app: str, rig: str = "rig.toml", extra_parts=(), **options) -> PartsPlant:
    """``extra_parts``: part tables added after the rig file's."""
    with open(APPS / app / rig, "rb") as f:
        table = tomllib.load(f)["plant"]
    return assemble({**table, "parts": [*table.get("parts", []), *extra_parts], **options})


def pool_cleaner(rig: str = "rig.toml", **options) -> PartsPlant:
    """The pool cleaner of ``rig`` (``rig-adc.toml``: its ADC sonar option)."""
    return plant_from_rig("pool_cleaner", rig, **options)


def duct_robot(world=None, **options) -> PartsPlant:
    """The duct robot of its rig file; ``world`` a world's name, or a
    :class:`~sim_plant.world.World` of a test's own (the robot starts at ``start_pose``)."""
    if isinstance(world, str):
        options["world"] = world
    plant = plant_from_rig("duct", **options)
    return plant if world is None or isinstance(world, str) else in_world(plant, world)


def in_world(plant: PartsPlant, world) -> PartsPlant:
    """``plant`` rebuilt in ``world`` (a World, where a rig file names one), from the pose
    its body gives."""
    pose = plant.start_pose
    plant.body.world_and_pose = lambda *rng: (world, pose)  # (a body that draws its world takes the generator)
    plant.reset(0)
    return plant

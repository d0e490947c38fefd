"""Our robots' plants as their rig files describe them (``firmware/apps/<app>/rig*.toml``),
for the plant tests: options over the file's ``[plant]`` table, a body's by name and a
part's as ``"<part name>.<option>"``."""

from pathlib import Path

from sim_plant.catalogue.assembly import PartsPlant, assemble_file

APPS = Path(__file__).resolve().parents[2] / "firmware" / "apps"


def plant_from_rig(app: str, rig: str = "rig.toml", **options) -> PartsPlant:
    return assemble_file(APPS / app / rig, **options)


def pool_cleaner(rig: str = "rig.toml", **options) -> PartsPlant:
    """The pool cleaner of ``rig`` (``rig-adc.toml``: its ADC sonar option)."""
    return plant_from_rig("pool_cleaner", rig, **options)

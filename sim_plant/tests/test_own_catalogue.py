"""A user's own catalogue entries (docs/own-parts.md), in this process: a folder of the rig
file's, a ``"module:Class"`` kind and an installed package's entry points each add parts,
bodies, worlds, views and judges the plant, the report and campaigns find as ours; a wrong
source is refused by name. (host/tests/test_package.py runs the page's robot from the
installed wheel in a repository of its own.)"""

import sys
import textwrap

import pytest

from sim_plant import catalogue
from sim_plant.catalogue.assembly import assemble
from sim_plant.catalogue.base import PartsError

MOTORS = [
    {"kind": "dc_motor", "name": "motor_l", "drives": "left"},
    {"kind": "dc_motor", "name": "motor_r", "drives": "right"},
]
LAMP = """
from sim_plant.catalogue.base import Opt, PartType, Sig
from sim_plant.option_table import Num
from .common import Constant


class Lamp(PartType):
    kind = "lamp"
    doc = "A lamp the firmware reads as a level."
    OPTIONS = (Opt("lit", Num("", 0, 1, whole=True), 1, "lit or not"),)
    SIGNALS = (Sig("out", "out", "level", "high while lit"),)

    def add(self, build):
        build.parts.append(Constant({f"{self.name}.out": self.options["lit"]}, {f"{self.name}.out": "level"}))
"""
COMMON = """
from sim_plant.catalogue.potentiometer import Constant  # (a helper module: no entry)
"""
FIELD = """
from sim_plant.catalogue.base import Judge, Opt, ReportView, WorldType
from sim_plant.option_table import Num
from sim_plant.world import room


class Field(WorldType):
    kind = "field"
    doc = "An empty field."
    OPTIONS = (Opt("side_m", Num("metres", 1, 20), 4.0, "its side"),)

    def build(self):
        side = self.options["side_m"]
        return room(side, side, name="field"), (side / 2, side / 2, 0.0)


class LampView(ReportView):
    kind = "lamp_view"
    doc = "The lamp, drawn."

    def panels(self, trace, kit):
        return [kit.Panel("lamp", "level")]


class Lit(Judge):
    kind = "lit"
    doc = "Passes when the console says lit."
    FIGURES = ("t_end_s",)

    def judge(self, rig, reached, task):
        return "lit" in rig.console, {"t_end_s": 1.0}, ""
"""


@pytest.fixture
def own(tmp_path, monkeypatch):
    """A user's folder of entries; the catalogue's additions undone after the test."""
    monkeypatch.setattr(catalogue, "_added", {})
    folder = tmp_path / "rig" / "parts"
    folder.mkdir(parents=True)
    for name, text in (("lamp.py", LAMP), ("common.py", COMMON), ("field.py", FIELD)):
        (folder / name).write_text(textwrap.dedent(text))
    before = set(sys.modules)
    yield folder
    for name in set(sys.modules) - before:
        if name.startswith(("_mpy_fil_own_", "mybot")):
            del sys.modules[name]


def test_a_rig_files_folder_adds_parts_worlds_views_and_judges(own):
    table = {"catalogue": ["parts/"], "body": "differential", "world": "field", "world_options": {"side_m": 6.0}}
    plant = assemble({**table, "parts": [*MOTORS, {"kind": "lamp", "name": "lamp", "lit": 0}]}, base=own.parent)
    plant.reset(seed=1)
    assert plant.outputs["lamp.out"] == "level" and plant.output("lamp.out") == 0
    assert plant.start_pose == (3.0, 3.0, 0.0), "the world's own start"
    assert plant.describe()["catalogue"] == [str(own)], "the header keeps the source for a later report"
    assert {"lamp"} <= set(catalogue.parts()) and "field" in catalogue.worlds()
    assert "lamp_view" in catalogue.views() and catalogue.judges()["lit"].FIGURES == ("t_end_s",)
    assert "common" not in catalogue.parts(), "a helper module is no entry"
    with pytest.raises(PartsError, match=r"\[\[plant.parts\]\] #3 \(lamp\) lit: expected a whole number from 0 to 1"):
        assemble({**table, "parts": [*MOTORS, {"kind": "lamp", "name": "lamp", "lit": 2}]}, base=own.parent)
    with pytest.raises(PartsError, match=r"\[plant\] world_options side_m: expected a number of metres from 1 to 20"):
        assemble({**table, "world_options": {"side_m": 90}, "parts": MOTORS}, base=own.parent)


def test_a_module_class_kind_and_an_entry_point_add_entries(own, tmp_path, monkeypatch):
    package = tmp_path / "site" / "mybot"
    package.mkdir(parents=True)
    (package / "__init__.py").write_text("")
    (package / "common.py").write_text(textwrap.dedent(COMMON))
    (package / "lamp.py").write_text(textwrap.dedent(LAMP))
    monkeypatch.syspath_prepend(str(tmp_path / "site"))
    plant = assemble({"body": "bench", "parts": [{"kind": "mybot.lamp:Lamp", "name": "lamp"}]})
    assert type(plant.catalogue_parts[0]).__module__ == "mybot.lamp"
    assert plant.describe()["parts"][0]["kind"] == "mybot.lamp:Lamp", "a later report imports it again"
    assert "lamp" not in catalogue.parts(), "a module:Class kind adds no name"

    info = tmp_path / "site" / "mybot-1.0.dist-info"  # (what pip writes for a package with the entry point)
    info.mkdir()
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: mybot\nVersion: 1.0\n")
    (info / "entry_points.txt").write_text("[mpy_fil.catalogue]\nmybot = mybot\n")
    catalogue._installed.cache_clear()
    try:
        assert catalogue.parts()["lamp"].__module__ == "mybot.lamp", "the installed package's module"
    finally:
        monkeypatch.undo()
        catalogue._installed.cache_clear()
    assert "lamp" not in catalogue.parts()


@pytest.mark.parametrize(
    ("table", "message"),
    [
        ({"catalogue": ["nowhere/"]}, r"\[plant\] catalogue: no folder .*nowhere"),
        ({"catalogue": ["no_such_module_xyz"]}, r"\[plant\] catalogue: cannot import 'no_such_module_xyz'"),
        ({"catalogue": "parts/"}, r"\[plant\] catalogue: expected a list of folders or module names"),
        ({"parts": [{"kind": "sim_plant.world:room", "name": "x"}]}, r"'sim_plant.world:room': expected a PartType"),
        ({"parts": [{"kind": "sim_plant.world:Nope", "name": "x"}]}, r"'sim_plant.world:Nope': cannot import it"),
    ],
)
def test_a_wrong_source_is_refused_by_name(own, table, message):
    with pytest.raises(PartsError, match=message):
        assemble({"body": "bench", **table}, base=own.parent)


def test_a_kind_of_ours_taken_again_is_refused_naming_both(own):
    (own / "lamp.py").write_text(textwrap.dedent(LAMP).replace('kind = "lamp"', 'kind = "dc_motor"'))
    with pytest.raises(
        PartsError, match=r"\[plant\] catalogue: .*kind 'dc_motor' is sim_plant.catalogue.dc_motor's too"
    ):
        assemble({"catalogue": ["parts/"], "body": "bench"}, base=own.parent)
    assert catalogue.parts()["dc_motor"].__module__ == "sim_plant.catalogue.dc_motor", "ours, still"

"""Part ``bumper``: a switch over an arc of the body's edge, centred on its mount's
heading (0 front, 180 rear), closed while the body touches a wall inside the arc; active
low (a switch to ground on a pull-up) by default, with contact bounce when asked
(:mod:`sim_plant.contacts`)."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.contacts import Bumper as Switch
from sim_plant.option_table import Flag, Num


class Bumper(PartType):
    kind = "bumper"
    doc = "A bumper switch over an arc of the body's edge (centred on the mount's heading_deg)."
    OPTIONS = (
        Opt(
            "half_arc_deg",
            Num("degrees", 0, 180, above=True),
            70.0,
            "half the arc it covers, either side of its centre",
        ),
        Opt("active_low", Flag(), True, "true: reads 0 while pressed (a switch to ground); false: 1 while pressed"),
        Opt(
            "bounce_us", Num("microseconds", 0, 1_000_000, whole=True), 0, "contact bounce after each press and release"
        ),
    )
    SIGNALS = (Sig("out", "out", "level", "the switch's level"),)
    TRUTH = ("contacts", "{name}.out_pressed")
    VIEWS = (
        View(
            "contacts",
            "the switch's level against the body's contacts",
            signals=("out",),
            truth=("contacts", "{name}.out_pressed"),
        ),
    )
    needs_body = True

    def add(self, build: Build) -> None:
        o = self.options
        build.bumpers.append(
            Switch(
                f"{self.name}.out",
                center_deg=self.mount[2],
                half_arc_deg=o["half_arc_deg"],
                active_low=o["active_low"],
                bounce_us=o["bounce_us"],
            )
        )

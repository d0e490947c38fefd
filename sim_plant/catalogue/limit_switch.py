"""Part ``limit_switch``: a lever microswitch at one point of the body's edge (at its
mount's heading: 0 front, 180 rear), closed while that point touches a wall: a bumper whose
arc is a few degrees wide, with the lever's own defaults (:mod:`sim_plant.catalogue.bumper`,
:mod:`sim_plant.contacts`)."""

from sim_plant.catalogue.base import Opt
from sim_plant.catalogue.bumper import Bumper
from sim_plant.option_table import Flag, Num


class LimitSwitch(Bumper):
    kind = "limit_switch"
    doc = "A lever limit switch at one point of the body's edge (the mount's heading_deg), closed at a wall."
    OPTIONS = (
        Opt("half_arc_deg", Num("degrees", 0, 45, above=True), 5.0, "half the lever's reach, either side of its point"),
        Opt("active_low", Flag(), True, "true: reads 0 while closed (a switch to ground); false: 1 while closed"),
        Opt(
            "bounce_us", Num("microseconds", 0, 1_000_000, whole=True), 200, "contact bounce after each close and open"
        ),
    )

"""Body ``desk``: a breadboard that stays where it is in a room of its own size, so that
parts that sense the room (an ``hcsr04``, an IMU at rest) have something to sense: a
ranger looks at the walls and the boxes (``obstacles``) from the desk's ``start_pose``.
Nothing drives it; a Wokwi project's ranger (``docs/wokwi.md``) is one of these with a
box at the distance the diagram gives."""

from sim_plant.catalogue.base import BodyType, Build, Opt
from sim_plant.catalogue.bench import _Desk
from sim_plant.drivetrain import Body
from sim_plant.option_table import BOX, POSE, ROOM_SIDE, Rows
from sim_plant.world import box, room


class _Still(_Desk):
    """The desk's drive: a body at its pose that never moves."""

    def __init__(self, pose):
        self.body = Body(*(float(v) for v in pose))


class Desk(BodyType):
    kind = "desk"
    doc = "A still breadboard in a room (walls and boxes): rangers and IMUs sense it; nothing drives it."
    OPTIONS = (
        Opt("room_w_m", ROOM_SIDE, 10.0, "the room's width (x)"),
        Opt("room_h_m", ROOM_SIDE, 10.0, "the room's height (y)"),
        Opt("obstacles", Rows(BOX, 1000), [], "boxes in the room, [cx_m, cy_m, w_m, h_m] each"),
        Opt("start_pose", POSE, None, "where the desk stands, [x_m, y_m, heading_rad]; the room's middle by default"),
    )

    def world_and_pose(self):
        o = self.options
        world = room(o["room_w_m"], o["room_h_m"], [box(*b) for b in o["obstacles"]], name="desk")
        pose = o["start_pose"] or (o["room_w_m"] / 2, o["room_h_m"] / 2, 0.0)
        return world, tuple(pose)

    def drive(self, build: Build, pose):
        return _Still(pose)

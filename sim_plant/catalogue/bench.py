"""Body ``bench``: no body and no pose, a breadboard on the desk. Buttons, probes, a
battery divider and wires from board outputs to board inputs (``wire``, ``uart_wire``)
sit on it; parts that sense or act on a moving body are refused."""

from sim_plant.catalogue.base import BodyType, Build
from sim_plant.drivetrain import Body
from sim_plant.engine import Part
from sim_plant.world import room


class _Desk(Part):
    """The drive of a bench: nothing moves (a body that stays at the origin)."""

    def __init__(self):
        self.body = Body(0.0, 0.0, 0.0)

    def encoder_rad_s(self) -> tuple:
        return ()


class Bench(BodyType):
    kind = "bench"
    doc = "No body, no pose: parts on a breadboard (buttons, probes, a battery divider, loopback wires)."
    OPTIONS = ()
    moves = False

    def world_and_pose(self):
        return room(1.0, 1.0, [], name="bench"), (0.0, 0.0, 0.0)

    def drive(self, build: Build, pose):
        return _Desk()

"""Body ``differential``: a disc with two driven wheels on its centre axis (most hobby
robots), in a room with box obstacles, a room furnished along a route from the plant's
seed (:mod:`sim_plant.furniture`), or one of our worlds. The ``dc_motor`` parts that
drive ``left`` and ``right`` move it; ``bumper`` parts are arcs of its edge."""

from sim_plant.catalogue.base import BodyType, Build, Opt, PartsError, WorldKind, WorldOptions, catalogue_world
from sim_plant.contacts import ContactMonitor
from sim_plant.drivetrain import DiffDriveTrain, SlipDriveTrain, WheelSlip
from sim_plant.furniture import DEFAULT_ROUTE, furnished_room
from sim_plant.option_table import BOX, FRACTION, PLACE, POINT, POSE, ROOM_SIDE, Num, Row, Rows, length
from sim_plant.world import box, room

CIRCLE = Row((PLACE, PLACE, length(0.001, 5)), "[x_m, y_m, r_m]")


class Differential(BodyType):
    kind = "differential"
    doc = "A disc body with two driven wheels on its centre axis (differential drive)."
    OPTIONS = (
        Opt(
            "world",
            WorldKind(),
            "room",
            "the room below; furnished: that room with furniture across route, drawn per seed; or one of our worlds"
            " or a catalogue world (a user's own too)",
        ),
        Opt("world_options", WorldOptions(), {}, "a catalogue world's options (its kind's OPTIONS)"),
        Opt("room_w_m", ROOM_SIDE, 3.0, "the room's width (x)"),
        Opt("room_h_m", ROOM_SIDE, 2.0, "the room's height (y)"),
        Opt("obstacles", Rows(BOX, 1000), [], "boxes in the room, [cx_m, cy_m, w_m, h_m] each"),
        Opt(
            "route",
            Rows(POINT, 100, least=2),
            [list(p) for p in DEFAULT_ROUTE],
            "the furnished room's route, [x_m, y_m] points: furniture across every leg, the start at the first",
        ),
        Opt("start_pose", POSE, None, "where it starts; the world's own start by default ([0.4, 1.0, 0] in the room)"),
        Opt("body_radius_m", length(0.01, 5), 0.08, "the disc's radius (its contacts with the walls)"),
        Opt(
            "outline",
            Rows(CIRCLE, 16),
            [],
            "the body as circles [x_m, y_m, r_m] from the wheel axle's middle, instead of the disc",
        ),
        Opt("wheel_radius_m", length(0.001, 1), 0.0325, "each wheel's radius"),
        Opt("track_m", length(0.01, 10), 0.15, "distance between the wheels"),
        Opt(
            "v_max_m_s",
            Num("metres per second", 0, 20, above=True),
            0.4,
            "rim speed at full duty (a motor's rpm sets its own)",
        ),
        Opt("spin_slip", FRACTION, 0.0, "share of travel the backward wheel's encoder misses while spinning"),
        Opt(
            "wheel_slip_sd",
            Num("", 0, 1),
            0.0,
            "wheel slip: every slip_period_us each wheel's encoder sees its floor travel times (1 + s), s ~ N(0, this)",
        ),
        Opt(
            "slip_period_us",
            Num("microseconds", 1_000, 1_000_000_000, whole=True),
            100_000,
            "how often the slip is redrawn",
        ),
        Opt("tape", Rows(POINT), [], "a tape line on the floor, [x_m, y_m] points (line sensors see it)"),
        Opt("tape_width_m", length(0.001, 1), 0.019, "the tape's width"),
    )

    draws_world = True

    def world_and_pose(self, rng):
        o = self.options
        if o["world"] == "furnished":
            if o["obstacles"]:
                raise PartsError("[plant] obstacles: only in the room world, not in furnished")
            route = [tuple(float(v) for v in p) for p in o["route"]]
            world = furnished_room(rng, route, room_w_m=o["room_w_m"], room_h_m=o["room_h_m"])
            return world, tuple(float(v) for v in (o["start_pose"] or (*route[0], 0.0)))
        if o["world"] == "room":
            world = room(o["room_w_m"], o["room_h_m"], [box(*b) for b in o["obstacles"]], name="room")
            pose = o["start_pose"] or (0.4, 1.0, 0.0)
            x, y, _ = pose
            r = o["body_radius_m"]
            if not (r <= x <= o["room_w_m"] - r and r <= y <= o["room_h_m"] - r):
                raise PartsError(f"[plant] start_pose: {list(pose)} puts the robot outside the room")
        else:
            if o["obstacles"]:
                raise PartsError(f"[plant] obstacles: only in the room world, not in {o['world']}")
            world, start = catalogue_world(o["world"], o["world_options"], rng)
            pose = o["start_pose"] or start
        return world, tuple(float(v) for v in pose)

    def drive(self, build: Build, pose):
        missing = [side for side in ("left", "right") if side not in build.motors]
        if missing:
            raise PartsError(
                f"[plant] body: the differential body needs a dc_motor that drives {' and '.join(missing)}"
            )
        if "rear" in build.motors:
            raise PartsError("[plant] body: a differential body's motors drive left or right, not rear")
        (bridge_l, motor_l), (bridge_r, motor_r) = build.motors["left"], build.motors["right"]
        drive_cls = SlipDriveTrain if self.options["wheel_slip_sd"] > 0 else DiffDriveTrain
        return drive_cls(
            bridges=(bridge_l, bridge_r),
            motors=(motor_l, motor_r),
            wheel_radius_m=self.options["wheel_radius_m"],
            track_m=self.options["track_m"],
            start_pose=pose,
            standby=build.standby,
            spin_slip=self.options["spin_slip"],
        )

    def contact_monitor(self, build: Build):
        circles = [tuple(float(v) for v in c) for c in self.options["outline"]]
        return ContactMonitor(circles or [(0.0, 0.0, self.options["body_radius_m"])], build.bumpers)

    def recorders(self, build: Build, world) -> list:
        o = self.options
        sd = o.get("wheel_slip_sd", 0.0)  # (a body built on this one may not have it)
        return [WheelSlip(sd, o["slip_period_us"])] if sd > 0 else []

    def react(self, plant, t_us: int) -> bool:
        """A new wheel slip re-plans the encoders."""
        for part in plant.parts:
            if isinstance(part, WheelSlip) and part.changed:
                part.changed = False
                return True
        return False

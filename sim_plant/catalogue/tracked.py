"""Body ``tracked``: a machine on two tracks that run at one speed, forwards or
backwards, steered by stopping one track (:mod:`sim_plant.physics.tracked`: the measured stop law
of seed 000 or the ideal pivot), in a pool (:func:`sim_plant.world.pool`) or any catalogue
world (``world``, ``world_options``). Its outline is
three circles of radius ``body_width_m / 2`` in a row (a capsule ``body_length_m`` long).
The ``track`` parts that stop ``left`` and ``right`` steer it; a ``bumper`` part mounted
at 0 deg covers the front circle, at 180 deg the rear one. With ``reverse_at_bumpers``
the machine's own logic reverses both tracks when the leading bumper closes (the WEDA
B400's); ``coverage_cell_m`` sets the grid the swept floor is counted on."""

import math

from sim_plant.catalogue.base import BodyType, Build, Opt, PartsError, WorldKind, WorldOptions, catalogue_world
from sim_plant.contacts import ContactMonitor
from sim_plant.option_table import HEADING, POSE, Flag, Num, OneOf, length
from sim_plant.physics.coverage import CoverageGrid, CoverageRecorder
from sim_plant.physics.tracked import IdealPivotLaw, MeasuredStopLaw, TrackDrive
from sim_plant.pool import BODY_LENGTH_M, BODY_WIDTH_M
from sim_plant.world import POOL_LENGTH_M, POOL_WIDTH_M, pool

SIDES = ("left", "right")
START_OFF_END_M = 0.01
"""The default start (seed 000 §7.3.3): in the corner, the front bumper 1 cm off the end
wall x = pool_length_m, the right side 2 cm off the side wall y = 0."""
START_OFF_SIDE_M = 0.02


class Tracked(BodyType):
    kind = "tracked"
    doc = "A tracked machine steered by stopping one track (the WEDA B400's law), in a pool."
    OPTIONS = (
        Opt(
            "world",
            WorldKind(own=()),
            "pool",
            "a rectangular pool, walls all round (its size below); or any catalogue world (world_options)",
        ),
        Opt("world_options", WorldOptions(), {}, "a catalogue world's options (not the pool's: pool_length_m below)"),
        Opt("pool_length_m", length(0.1, 1000), POOL_LENGTH_M, "the pool's length (x)"),
        Opt("pool_width_m", length(0.1, 1000), POOL_WIDTH_M, "the pool's width (y)"),
        Opt(
            "start_pose", POSE, None, "where it starts; in the corner facing the end wall x = pool_length_m by default"
        ),
        Opt("body_length_m", length(0.01, 10), BODY_LENGTH_M, "the outline's length"),
        Opt("body_width_m", length(0.01, 10), BODY_WIDTH_M, "the outline's width"),
        Opt("track_m", length(0.01, 10), 0.4, "distance between the tracks (W)"),
        Opt("speed_m_s", Num("metres per second", 0, 20, above=True), 0.3, "both tracks' speed"),
        Opt("steering", OneOf(("measured", "ideal")), "measured", "the stop law: seed 000 eq. 7.1, or a pivot"),
        Opt("steer_scatter_rel", Num("fraction", 0, 10), 0.13, "relative sd of each stop's turn (measured law)"),
        Opt("reverse_at_bumpers", Flag(), True, "the machine reverses itself when its leading bumper closes"),
        Opt("reversal_pause_ms", Num("milliseconds", 0, 1_000_000), 1000.0, "stopped before running the other way"),
        Opt("kick_mean_rad", HEADING, -0.0174, "mean heading kick at a reversal"),
        Opt("kick_sd_rad", Num("radians", 0, 10), 0.0348, "its standard deviation"),
        Opt("coverage_cell_m", length(0.02, 10), 0.1, "the cell of the swept-floor grid"),
    )

    def _radius_m(self) -> float:
        return self.options["body_width_m"] / 2

    draws_world = True  # (a catalogue world may draw per seed; the pool draws nothing)

    def world_and_pose(self, rng=None):
        o = self.options
        if o["body_length_m"] < o["body_width_m"]:
            raise PartsError(f"[plant] body_length_m: expected at least body_width_m ({o['body_width_m']})")
        if o["world"] != "pool":
            world, start = catalogue_world(o["world"], o["world_options"], rng)
            return world, tuple(float(v) for v in (o["start_pose"] or start))
        world = pool(o["pool_length_m"], o["pool_width_m"])
        pose = o["start_pose"]
        if pose is None:
            x = o["pool_length_m"] - o["body_length_m"] / 2 - START_OFF_END_M
            pose = (x, self._radius_m() + START_OFF_SIDE_M, 0.0)
        return world, tuple(float(v) for v in pose)

    def drive(self, build: Build, pose):
        missing = [side for side in SIDES if side not in build.tracks]
        if missing:
            raise PartsError(f"[plant] body: the tracked body needs a track that stops {' and '.join(missing)}")
        o = self.options
        law = MeasuredStopLaw(scatter_rel=o["steer_scatter_rel"]) if o["steering"] == "measured" else IdealPivotLaw()
        return TrackDrive(
            law=law,
            speed_m_s=o["speed_m_s"],
            track_m=o["track_m"],
            start_pose=pose,
            reversal_pause_ms=o["reversal_pause_ms"],
            kick_mean_rad=o["kick_mean_rad"],
            kick_sd_rad=o["kick_sd_rad"],
            stop_names=tuple(build.tracks[side] for side in SIDES),
        )

    def contact_monitor(self, build: Build):
        r = self._radius_m()
        half = self.options["body_length_m"] / 2 - r
        for bumper in build.bumpers:  # the front circle (2) for a bumper facing forwards, the rear (0) else
            bumper.circles = (2,) if math.cos(bumper.center_rad) > 0 else (0,)
        return ContactMonitor([(-half, 0.0, r), (0.0, 0.0, r), (half, 0.0, r)], build.bumpers)

    def recorders(self, build: Build, world) -> list:
        return [CoverageRecorder(CoverageGrid(world, self.options["coverage_cell_m"], self._radius_m()))]

    def react(self, plant, t_us: int) -> bool:
        """The machine's own bumper logic: the leading bumper reverses the tracks."""
        if not self.options["reverse_at_bumpers"]:
            return False
        drive = plant.drive
        for bumper in plant.parts[0].bumpers:
            if bumper.pressed:
                facing = 1 if bumper.circles == (2,) else -1
                if facing == drive.direction:
                    return drive.start_reversal(t_us, -facing)
        return False

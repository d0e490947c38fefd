"""Part ``track``: one track of a ``tracked`` body and the line that stops it (seed 000:
a parallel-port bit per track, 1 stops it; :class:`sim_plant.physics.tracked.TrackDrive`)."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig, View
from sim_plant.option_table import OneOf


class Track(PartType):
    kind = "track"
    doc = "One track of a tracked body, and the line that stops it (1: stopped)."
    OPTIONS = (Opt("side", OneOf(("left", "right")), "left", "the track it is"),)
    SIGNALS = (Sig("stop", "in", "level", "1 stops the track, 0 lets it run"),)
    TRUTH = ("track_stopped",)
    VIEWS = (
        View("level", "the stop line against which tracks are stopped", signals=("stop",), truth=("track_stopped",)),
    )
    needs_body = True

    def add(self, build: Build) -> None:
        side = self.options["side"]
        if side in build.tracks:
            raise ValueError(f"side: the {side} track has a stop line already")
        if "speed_m_s" not in build.body:
            raise ValueError("kind: a track needs a tracked body")
        build.tracks[side] = f"{self.name}.stop"

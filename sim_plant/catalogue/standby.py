"""Part ``standby``: a motor driver's standby pin, shared by both channels (the TB6612's
STBY): low at reset, both motors off until the board raises it
(:class:`sim_plant.drivetrain.DiffDriveTrain`'s ``standby``)."""

from sim_plant.catalogue.base import Build, PartType, Sig, View


class Standby(PartType):
    kind = "standby"
    doc = "A motor driver's standby pin (TB6612 STBY): both motors off while it is low (it is at reset)."
    SIGNALS = (Sig("stby", "in", "level", "STBY: 1 runs both channels, 0 stops them"),)
    VIEWS = (View("level", "the standby pin over time", signals=("stby",)),)
    needs_body = True

    def add(self, build: Build) -> None:
        if build.standby is not None:
            raise ValueError(f"kind: the motors have a standby pin already ({build.standby})")
        build.standby = f"{self.name}.stby"

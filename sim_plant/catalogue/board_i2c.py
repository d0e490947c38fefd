"""Part ``board_i2c``: one board's I2C bus wired to another board's ``machine.I2CTarget``,
in a rig with several boards (``docs/multi-board.md``). The controller's transfers on
``controller_bus`` to an address the target board's firmware has taken (``I2CTarget(id, addr)``) go
to that firmware, at their instant: it answers from its memory or its IRQ handler as the
port's interrupt would, the controller waiting meanwhile (``host.rig.loop.boardset``). An
address no target has taken goes to the plant's chips on that bus, as any transfer does.
The part has no signals: the set of boards routes the transfers (the plant holds nothing)."""

from sim_plant.buses import BusName
from sim_plant.catalogue.base import Build, Opt, PartType
from sim_plant.option_table import Name


class BoardI2c(PartType):
    kind = "board_i2c"
    doc = "One board's I2C bus wired to another board's machine.I2CTarget (a rig with several boards)."
    OPTIONS = (
        Opt("controller", Name(), None, "the board whose firmware is the controller (its [[boards]] name)"),
        Opt("controller_bus", BusName(), "i2c0", "the controller's bus, as its firmware creates it (I2C(0) is i2c0)"),
        Opt("target", Name(), None, "the board whose firmware is the target (machine.I2CTarget)"),
    )
    SIGNALS = ()
    zero_delay = True

    def check(self) -> None:
        """(Which boards it names: the rig file's reader checks, host.rig.config.boardfile.)"""
        if self.options["controller"] is not None and self.options["controller"] == self.options["target"]:
            raise ValueError(
                f"target: expected another board than the controller, got {self.options['target']!r} for both"
            )

    def add(self, build: Build) -> None:
        pass  # (nothing in the plant: host.rig.loop.boardset routes the controller's transfers)

"""Part ``board_uart``: a UART link between two boards of a rig with several boards
(``docs/multi-board.md``; :mod:`sim_plant.physics.wire` is its engine). One board's UART
is wired to ``<name>.a``, the other's to ``<name>.b``: each TX goes to the other's RX,
every byte arriving when its stop bit ends at the sender's baud rate (10 bits a byte),
one after another on each direction's line. ``drop_p`` and ``flip_p``: each byte lost, or
one of its bits flipped, on its way with that chance (the same for the same seed; truth
``<name>_a_lost``, ``<name>_a_damaged``: of what the UART on ``.a`` sent, and ``_b_``)."""

from sim_plant.catalogue.base import Build, Opt, PartType, Sig
from sim_plant.option_table import Num
from sim_plant.physics.wire import WirePart


class BoardUart(PartType):
    kind = "board_uart"
    doc = "A UART between two boards: TX of each to RX of the other, bytes timed at the sender's baud rate."
    OPTIONS = (
        Opt("drop_p", Num("probability", 0, 1), 0.0, "each byte lost on its way (a framing error): its chance"),
        Opt("flip_p", Num("probability", 0, 1), 0.0, "each byte with one bit flipped on its way: its chance"),
    )
    TRUTH = ("{name}_a_lost", "{name}_a_damaged", "{name}_b_lost", "{name}_b_damaged")
    SIGNALS = (
        Sig("a", "in", "uart", "one board's UART: what it sends goes to b, (out, bytes) what b sent"),
        Sig("b", "in", "uart", "the other board's UART: what it sends goes to a, (out, bytes) what a sent"),
    )
    zero_delay = False  # (a byte arrives a byte time after it is sent: never at the write's instant)
    reads_empty = True
    """A UART line carries bytes as events: a UART configured on it reads nothing yet."""

    def add(self, build: Build) -> None:
        a, b = f"{self.name}.a", f"{self.name}.b"
        faults = (self.options["drop_p"], self.options["flip_p"])
        WirePart.on(build.parts).add(crossed=((a, b),), faults={a: faults, b: faults} if any(faults) else None)

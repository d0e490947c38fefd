"""Part ``board_uart``: a UART link between two boards of a rig with several boards
(``docs/multi-board.md``; :mod:`sim_plant.physics.wire` is its engine). One board's UART
is wired to ``<name>.a``, the other's to ``<name>.b``: each TX goes to the other's RX,
every byte arriving when its stop bit ends at the sender's baud rate (10 bits a byte),
one after another on each direction's line."""

from sim_plant.catalogue.base import Build, PartType, Sig
from sim_plant.physics.wire import WirePart


class BoardUart(PartType):
    kind = "board_uart"
    doc = "A UART between two boards: TX of each to RX of the other, bytes timed at the sender's baud rate."
    OPTIONS = ()
    SIGNALS = (
        Sig("a", "in", "uart", "one board's UART: what it sends goes to b, (out, bytes) what b sent"),
        Sig("b", "in", "uart", "the other board's UART: what it sends goes to a, (out, bytes) what a sent"),
    )
    zero_delay = True
    reads_empty = True
    """A UART line carries bytes as events: a UART configured on it reads nothing yet."""

    def add(self, build: Build) -> None:
        WirePart.on(build.parts).add(crossed=((f"{self.name}.a", f"{self.name}.b"),))

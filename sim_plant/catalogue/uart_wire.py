"""Part ``uart_wire``: a UART's TX wired to its RX on a bench (:mod:`sim_plant.physics.wire` is
its engine). A UART wired to ``<name>.line`` receives what it sends, each byte at the time
its stop bit ends at the sender's baud rate (10 bits a byte), one after another."""

from sim_plant.catalogue.base import Build, PartType, Sig
from sim_plant.physics.wire import WirePart


class UartWire(PartType):
    kind = "uart_wire"
    doc = "A UART's TX wired to its RX: what it sends comes back, timed at its baud rate."
    OPTIONS = ()
    SIGNALS = (Sig("line", "in", "uart", "the bytes a UART sends, and (out, bytes) the bytes it receives back"),)
    zero_delay = True
    reads_empty = True
    """A UART line carries bytes as events: a UART configured on it reads nothing yet."""

    def add(self, build: Build) -> None:
        WirePart.on(build.parts).add(uarts=(f"{self.name}.line",))

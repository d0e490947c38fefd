"""An RP2040 PIO block, emulated on the host in virtual time (``docs/shim.md``, "PIO").

:mod:`.machine` executes one state machine's instructions cycle by cycle as the RP2040
datasheet (section 3.4) describes them; :mod:`.runner` runs it across stretches of
constant pin inputs, skipping whole periods of a loop that has come back to a state it
was in (a wait on a pin, a stalled FIFO, a polling loop cost nothing until a pin changes);
:mod:`.block` is one PIO: its 32-word instruction memory, its IRQ flags, the GPIO levels
it reads and the levels its state machines drive.
"""

from sim_plant.pio.block import PioBlock
from sim_plant.pio.machine import PioConfig, PioStall

__all__ = ["PioBlock", "PioConfig", "PioStall"]

# rp2 module for RP2040 firmware in the loop: the PIO's names, so code that sets up
# state machines imports and runs; a PIO program does not run here (docs/shim.md).
# Only an rp2 board has it: elsewhere `import rp2` fails, as on an ESP32.
import sys

if sys.platform != "rp2":
    raise ImportError(
        "no module named 'rp2': the loop has it for an RP2040 board only; name a board rpi_pico* "
        'or set [board] family = "rpi_pico" in the rig file (docs/rig-file.md, docs/shim.md)'
    )

import _hil


class PIO:
    IN_LOW = 0
    IN_HIGH = 1
    OUT_LOW = 2
    OUT_HIGH = 3
    SHIFT_LEFT = 0
    SHIFT_RIGHT = 1
    JOIN_NONE = 0
    JOIN_TX = 1
    JOIN_RX = 2
    IRQ_SM0 = 0x100
    IRQ_SM1 = 0x200
    IRQ_SM2 = 0x400
    IRQ_SM3 = 0x800

    def __init__(self, id):
        self._id = id

    def state_machine(self, id, *args, **kw):
        return StateMachine(self._id * 4 + id, *args, **kw)

    def irq(self, handler=None, trigger=0, hard=False):
        return None

    def remove_program(self, program=None):
        pass


def asm_pio(**settings):
    """The program's settings, kept; its body (PIO assembly) is not assembled or run."""

    def program(fn):
        return ("pio", fn.__name__, settings)

    return program


def asm_pio_encode(instr, sideset_count, sideset_opt=False):
    return 0


class StateMachine:
    """A state machine that takes its program and settings and runs nothing: what is put
    in its TX FIFO is dropped; get() has nothing to give (docs/shim.md)."""

    def __init__(self, id, program=None, freq=-1, **kw):
        self._id = id
        self._active = 0
        self.puts = 0
        if program is not None:
            self.init(program, freq, **kw)

    def init(self, program, freq=-1, **kw):
        self._program = program

    def active(self, value=None):
        if value is None:
            return self._active
        self._active = 1 if value else 0

    def restart(self):
        pass

    def exec(self, instr):
        pass

    def put(self, value, shift=0):
        self.puts += 1 if isinstance(value, int) else len(value)

    def get(self, buf=None, shift=0):
        raise OSError("PIO programs do not run in the loop: StateMachine(%d).get() has nothing to read" % self._id)

    def rx_fifo(self):
        return 0

    def tx_fifo(self):
        return 0

    def irq(self, handler=None, trigger=0, hard=False):
        return None


def bootsel_button():
    _hil.observe()
    return 0

# Two side-looking NMEA depth sounders on one UART (seed 000: a NAVMAN 100 per side,
# RS-232 at 4800 8N1, one $SDDPT sentence every 500 ms), multiplexed by a select line
# (the code's parallel-port bit 2: 0 = sonar 0, the left one). Called once per control
# quantum, it reads whatever the UART holds, so a sentence split across two quanta is
# joined, and hands over the newest complete depth.
from machine import UART, Pin

from nmea import NO_ECHO, NmeaLines, dpt_depth_m

BAUD = 4800


class DepthSounders:
    def __init__(self, uart_id, select_pin):
        self._uart = UART(uart_id, BAUD, bits=8, parity=None, stop=1, rxbuf=256)
        self._select = Pin(select_pin, Pin.OUT, value=0)
        self._lines = NmeaLines()
        self.selected = 0
        self.sentences = 0
        self.superseded = 0  # sentences replaced by a newer one in the same quantum

    def select(self, sonar):
        """0: left sonar, 1: right; the sounder switches at its next sentence."""
        if sonar != self.selected:
            self.selected = sonar
            self._select.value(sonar)

    def poll(self):
        """None (no new sentence), NO_ECHO, or the depth in metres."""
        if not self._uart.any():
            return None
        depth = None
        for sentence in self._lines.feed(self._uart.read()):
            d = dpt_depth_m(sentence)
            if d is not None:
                if depth is not None:
                    self.superseded += 1
                depth = d
                self.sentences += 1
        return depth

    @property
    def bad(self):
        return self._lines.bad


__all__ = ["NO_ECHO", "DepthSounders"]

# Quadrature decoding by the seed's state table (seed 004 §1.2, Table 1): the phase of
# the two channels is 0..3 for AB = 00, 10, 11, 01; a step to the next phase counts +1
# (forwards, A leads B), a step to the previous one -1, and a jump of two phases means
# an edge was missed ("if determining the encoder phase is not performed within a
# certain amount of time then the software will miss some encoder ticks"). Pure Python:
# the IRQ handlers in drivers.py call Quadrature.edge, CPython tests call it too.

PHASE = (0, 3, 1, 2)  # Table 1, indexed by A * 2 + B: 00 -> 0, 01 -> 3, 10 -> 1, 11 -> 2


class Quadrature:
    """Counts of one encoder. ``count`` is the position in counts (one per phase step),
    ``errors`` the two-phase jumps. A jump is counted as an error and as two steps in
    the direction of the last step: a jump comes from two edges closer together than
    the handler's latency, which happens at speed, where the direction does not change
    between two edges (the seed names the error, not what to count)."""

    def __init__(self, a=0, b=0):
        self.phase = PHASE[a * 2 + b]
        self.count = 0
        self.errors = 0
        self.idle = 0  # handler calls that found no new phase (its edge was taken already)
        self._dir = 1

    def edge(self, a, b):
        """The channels' levels after an edge: step the count by the phase change."""
        phase = PHASE[a * 2 + b]
        step = (phase - self.phase) & 3
        self.phase = phase
        if step == 1:
            self.count += 1
            self._dir = 1
        elif step == 3:
            self.count -= 1
            self._dir = -1
        elif step == 2:
            self.errors += 1
            self.count += 2 * self._dir
        else:
            self.idle += 1

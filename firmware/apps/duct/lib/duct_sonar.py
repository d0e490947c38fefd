# The three amplitude sonars as the firmware reads them (seed 002 App. C, §5.6): 8-bit
# ADC counts that rise as the wall comes closer; readings under the zero-clamp threshold
# are set to 0 (the peak detector's slow discharge would otherwise delay a branch); a
# single sample far from both neighbours is an outlier and is replaced by the previous
# value (the seed's reading 26 and the corner reflection at reading 106).

ZERO_CLAMP = 34  # counts: below this the side is open (a wall beyond ~0.22 m)
OUTLIER_JUMP = 40  # counts: a jump this big that does not last one more sample
GAINS100 = (100, 95, 105)  # per-channel calibration, x100: F, L, R (left and right matched)


class SonarFilter:
    """One channel: clamp, calibration and single-sample outlier rejection. ``push``
    gives the value one sample late when a jump is pending (it is accepted when the next
    sample confirms it)."""

    def __init__(self, gain100=100):
        self.gain100 = gain100
        self.value = 0  # the accepted value
        self.pending = None  # a jump waiting for confirmation
        self.rejected = 0

    def push(self, raw):
        v = raw * self.gain100 // 100
        if v > 255:
            v = 255
        if v < ZERO_CLAMP:
            v = 0
        if self.pending is not None:
            p, self.pending = self.pending, None
            if abs(v - p) < OUTLIER_JUMP:
                self.value = v  # the jump lasted: accept it
                return v
            self.rejected += 1  # it did not: p was an outlier
        if abs(v - self.value) >= OUTLIER_JUMP:
            self.pending = v
            return self.value
        self.value = v
        return v

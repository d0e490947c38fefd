# Seed 002's per-wheel speed loop (App. D): slot counts from an external interrupt per
# wheel, compared every 8 timer interrupts with the set speed, the duty corrected by the
# integer P law with Kp = 0.25 stored as 25 / 100 ("K_p was multiplied by 100 and the
# result from the control algorithm divided by 100"), and the counts zeroed.
#
# Incremental form: duty += Kp * (set - actual). The seed's equation D.1 reads as a
# positional law (R = Kp * e), but a positional P law on speed always keeps a steady-state
# error, and the seed says Kp = 0.25 keeps none; applied to the duty as an increment the
# law integrates, which also fits Kp = 1 oscillating (docs/duct.md).
#
# Division truncates toward zero, as C's integer division on the AVR did: -7 * 25 / 100
# is -1, not Python's floor -2. So an error of -3..+3 ticks leaves the duty alone either
# way and the loop has no bias downwards.
# What the truncation leaves alone at rest: |e| <= 3 ticks at Kp 0.25 and 0.3, <= 4 at
# 0.2, <= 9 at 0.1 (the Kp sweep in docs/duct.md).

KP100 = 25  # Kp = 0.25
DUTY_TOP = 20  # duty steps: 0..20 (5 % each) of the 20 kHz PWM


def p_step(kp100, error):
    """The duty increment for ``error`` ticks: kp100 * error / 100, truncated toward 0."""
    if error >= 0:
        return (kp100 * error) // 100
    return -((kp100 * -error) // 100)


class WheelLoop:
    """One wheel: slot counts in, signed duty out. The encoder has one channel, so the
    direction of travel is the commanded one; the loop works on magnitudes."""

    def __init__(self, kp100=KP100):
        self.kp100 = kp100
        self.set_ticks = 0  # signed set speed, ticks per control period
        self.duty = 0  # 0..DUTY_TOP, the magnitude
        self.sign = 1
        self.last = 0  # the last period's count

    def set(self, ticks):
        if ticks == 0 or (ticks > 0) != (self.sign > 0):
            self.duty = 0  # a stop or a reversal starts the ramp from zero (§5.5)
        self.set_ticks = ticks
        if ticks:
            self.sign = 1 if ticks > 0 else -1

    def update(self, count):
        """One control period: ``count`` slots went past. Returns the signed duty."""
        self.last = count
        target = self.set_ticks if self.set_ticks >= 0 else -self.set_ticks
        if target == 0:
            self.duty = 0
            return 0
        d = self.duty + p_step(self.kp100, target - count)
        self.duty = 0 if d < 0 else (DUTY_TOP if d > DUTY_TOP else d)
        return self.duty * self.sign

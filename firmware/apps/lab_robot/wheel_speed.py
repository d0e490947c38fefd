# Wheel speed loop: a feed-forward duty from the motor's law plus a PI on the speed
# measured from the encoder counts of each control step. The speed measured over a step
# is what the previous step's target gave, so that is the target it is compared with.
# Pure Python: runs on the board and under CPython.

DEADBAND_DUTY = 0.05  # the motor does not turn below this duty
MM_S_PER_DUTY = 500.0 / 0.95  # 500 mm/s at full duty, linear above the dead band
INTEGRAL_LIMIT = 0.2  # duty


class WheelSpeed:
    def __init__(self, kp=0.0002, ki=0.004):
        self._kp = kp  # duty per mm/s of error
        self._ki = ki  # duty per mm of accumulated error
        self._integral = 0.0
        self._target = 0.0
        self.speed_mm_s = 0.0

    def update(self, target_mm_s, travel_mm, dt_ms):
        """Duty (-1..1) for the target speed, given the wheel's travel in the last step."""
        self.speed_mm_s = travel_mm * 1000 / dt_ms if dt_ms > 0 else 0.0
        err = self._target - self.speed_mm_s
        self._target = target_mm_s
        if target_mm_s == 0:
            self._integral = 0.0
            return 0.0
        i = self._integral + err * dt_ms / 1000 * self._ki
        self._integral = max(-INTEGRAL_LIMIT, min(INTEGRAL_LIMIT, i))
        ff = DEADBAND_DUTY + abs(target_mm_s) / MM_S_PER_DUTY
        duty = (ff if target_mm_s > 0 else -ff) + self._kp * err + self._integral
        return max(-1.0, min(1.0, duty))

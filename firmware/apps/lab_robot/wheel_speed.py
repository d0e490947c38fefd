# Wheel speed loop: a feed-forward duty from the motor's law plus a PI on the speed
# measured from the encoder counts of each control step. Pure Python.

DEADBAND_DUTY = 0.05  # the motor does not turn below this duty
MM_S_PER_DUTY = 500.0 / 0.95  # 500 mm/s at full duty, linear above the dead band


class WheelSpeed:
    def __init__(self, kp=0.0008, ki=0.004):
        self._kp = kp  # duty per mm/s of error
        self._ki = ki  # duty per mm of accumulated error
        self._integral = 0.0
        self.speed_mm_s = 0.0

    def update(self, target_mm_s, travel_mm, dt_ms):
        """Duty (-1..1) for the target speed, given the wheel's travel in the last step."""
        self.speed_mm_s = travel_mm * 1000 / dt_ms if dt_ms > 0 else 0.0
        if target_mm_s == 0:
            self._integral = 0.0
            return 0.0
        err = target_mm_s - self.speed_mm_s
        self._integral = max(-0.2, min(0.2, self._integral + err * dt_ms / 1000 * self._ki))
        ff = DEADBAND_DUTY + abs(target_mm_s) / MM_S_PER_DUTY
        duty = (ff if target_mm_s > 0 else -ff) + self._kp * err + self._integral
        return max(-1.0, min(1.0, duty))

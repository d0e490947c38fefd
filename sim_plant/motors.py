"""DC motors behind the H-bridge interfaces boards really use.

A bridge turns its input pins into a signed effective duty in [-1, 1] (and whether the
motor is braked or left to coast); a :class:`DcMotor` turns that duty into a wheel speed.

==========================  ======================  ====================================
bridge                      pins (suffixes)         truth table
==========================  ======================  ====================================
:class:`DirPinsPwmBridge`   ``in1 in2 pwm`` and an  TB6612FNG / L298N: IN1=1, IN2=0
                            optional shared         forward at the PWM duty; 0/1
                            ``stby``                reverse; 1/1 short brake; 0/0 coast;
                                                    STBY low (TB6612) coasts both motors
:class:`DirPwmBridge`       ``dir pwm`` and an      LMD18200 (seed 002): DIR sets the
                            optional ``brake``      direction, PWM the magnitude; BRAKE
                                                    high brakes
:class:`TwoPwmBridge`       ``in1 in2`` (both PWM)  DRV8833: the effective duty is
                                                    d1 - d2 (IN1 PWM / IN2 low drives
                                                    forward, fast decay; IN1 high / IN2
                                                    PWM drives forward at 1 - d2, slow
                                                    decay); both high brake, both low
                                                    coast
==========================  ======================  ====================================

PWM inputs are ``duty_u16`` (0..65535) as ``machine.PWM.duty_u16`` sets them; direction
pins are levels.
"""

import math

DUTY_FULL = 65535


def _duty(value) -> float:
    return min(max(int(value), 0), DUTY_FULL) / DUTY_FULL


class Bridge:
    """Base: ``pins`` maps full signal names to pin roles."""

    pins: dict[str, str] = {}
    kinds: dict[str, str] = {}
    FIXED_STATE = ("pins", "kinds")

    def __init__(self, prefix: str, roles: tuple[str, ...], kinds: dict[str, str]):
        self.pins = {f"{prefix}.{role}": role for role in roles}
        self.kinds = {f"{prefix}.{role}": kinds[role] for role in roles}
        self.state = dict.fromkeys(roles, 0)
        self.standby = False  # a shared standby pin, set by the drive

    def set_pin(self, role: str, value) -> None:
        self.state[role] = int(value)

    def effective(self) -> tuple[float, bool]:
        """(signed duty in [-1, 1], braking)."""
        raise NotImplementedError


class DirPinsPwmBridge(Bridge):
    """TB6612FNG / L298N channel: IN1, IN2 direction pins and a PWM enable."""

    def __init__(self, prefix: str):
        super().__init__(prefix, ("in1", "in2", "pwm"), {"in1": "level", "in2": "level", "pwm": "duty"})

    def effective(self) -> tuple[float, bool]:
        s = self.state
        if self.standby:
            return 0.0, False
        in1, in2 = s["in1"] != 0, s["in2"] != 0
        if in1 == in2:
            return 0.0, in1  # 1/1 short brake, 0/0 coast
        duty = _duty(s["pwm"])
        return (duty if in1 else -duty), False


class DirPwmBridge(Bridge):
    """LMD18200-style sign/magnitude bridge: DIR, PWM and (optional) BRAKE."""

    def __init__(self, prefix: str, *, brake_pin: bool = False):
        roles = ("dir", "pwm", "brake") if brake_pin else ("dir", "pwm")
        super().__init__(prefix, roles, {"dir": "level", "pwm": "duty", "brake": "level"})

    def effective(self) -> tuple[float, bool]:
        s = self.state
        if s.get("brake", 0):
            return 0.0, True
        duty = _duty(s["pwm"])
        return (duty if s["dir"] else -duty), False


class TwoPwmBridge(Bridge):
    """DRV8833-style channel: two PWM inputs, effective duty d1 - d2."""

    def __init__(self, prefix: str):
        super().__init__(prefix, ("in1", "in2"), {"in1": "duty", "in2": "duty"})

    def effective(self) -> tuple[float, bool]:
        d1, d2 = _duty(self.state["in1"]), _duty(self.state["in2"])
        return d1 - d2, d1 >= 1.0 and d2 >= 1.0


class GangedBridges(Bridge):
    """The bridges of the motors on one side of a four-wheel skid-steer car (two motors a
    side, their wheels tied through the ground): the side is driven at the mean of their
    effective duties, braked when all of them brake. Its pins are its members' own
    (``motor_lf.in1``, ``motor_lr.in1``, ...)."""

    FIXED_STATE = ("pins", "kinds", "members")

    def __init__(self, bridges):
        self.members = list(bridges)
        self.pins = {name: name for b in self.members for name in b.pins}
        self.kinds = {name: kind for b in self.members for name, kind in b.kinds.items()}
        self.state = dict.fromkeys(self.pins, 0)

    @property
    def standby(self) -> bool:
        return self.members[0].standby

    @standby.setter
    def standby(self, value: bool) -> None:
        for b in self.members:
            b.standby = value

    def set_pin(self, role: str, value) -> None:
        self.state[role] = int(value)
        for b in self.members:
            if role in b.pins:
                b.set_pin(b.pins[role], value)

    def effective(self) -> tuple[float, bool]:
        each = [b.effective() for b in self.members]
        return sum(d for d, _ in each) / len(each), all(braking for _, braking in each)


class DcMotor:
    """Signed duty -> wheel speed, with a dead band, saturation and a gain.

    ==========================  =======================================================
    attribute                   meaning
    ==========================  =======================================================
    ``max_wheel_rad_s``         wheel speed at saturation (before ``gain``)
    ``deadband_duty``           |duty| at or below which the wheel does not turn
                                (static friction; seed 003 §5.2 "at low speed the
                                motor was not able to supply the required torque")
    ``saturation_duty``         |duty| from which the speed no longer rises
    ``gain``                    per-wheel gain (mismatch between two motors/wheels)
    ``time_constant_ms``        first-order speed lag; 0 follows the duty at once
    ``coast_time_constant_ms``  lag when coasting (bridge off); defaults to 3 x the above
    ==========================  =======================================================

    Between the dead band and saturation the speed is linear in the duty.
    """

    FIXED_STATE = True  # configuration only

    def __init__(
        self,
        *,
        max_wheel_rad_s: float,
        deadband_duty: float = 0.0,
        saturation_duty: float = 1.0,
        gain: float = 1.0,
        time_constant_ms: float = 0.0,
        coast_time_constant_ms: float | None = None,
    ):
        if not 0.0 <= deadband_duty < saturation_duty <= 1.0:
            raise ValueError(
                f"DcMotor: need 0 <= deadband_duty ({deadband_duty}) < saturation_duty ({saturation_duty}) <= 1"
            )
        if max_wheel_rad_s <= 0 or gain < 0 or time_constant_ms < 0:
            raise ValueError("DcMotor: max_wheel_rad_s must be > 0, gain and time_constant_ms >= 0")
        self.max_wheel_rad_s = float(max_wheel_rad_s)
        self.deadband_duty = float(deadband_duty)
        self.saturation_duty = float(saturation_duty)
        self.gain = float(gain)
        self.time_constant_ms = float(time_constant_ms)
        self.coast_time_constant_ms = (
            3.0 * self.time_constant_ms if coast_time_constant_ms is None else float(coast_time_constant_ms)
        )

    def steady_rad_s(self, duty: float) -> float:
        """Wheel speed the motor settles at for a signed duty."""
        mag = abs(duty)
        if mag <= self.deadband_duty:
            return 0.0
        frac = min(1.0, (mag - self.deadband_duty) / (self.saturation_duty - self.deadband_duty))
        w = self.gain * self.max_wheel_rad_s * frac
        return w if duty > 0 else -w

    def lag_factor(self, dt_us: int, coasting: bool) -> float:
        """Fraction of the way to the target covered in ``dt_us`` (1 with no lag)."""
        tau_ms = self.coast_time_constant_ms if coasting else self.time_constant_ms
        if tau_ms <= 0.0:
            return 1.0
        return 1.0 - math.exp(-dt_us / (tau_ms * 1000.0))

"""Seed 003's HC-SR04 ultrasonic ranger on an SG90 servo, as the pins a board sees.

The board raises TRIG for at least 10 us; when TRIG falls the module sends its burst and
raises ECHO, which stays high for the round trip of the sound to the nearest obstacle in
its cone, or for the 38 ms timeout when nothing is in range (seed 003 §3.3, from the
Elegoo datasheet):

=====================  ==========  ============================================================
constant               value       source
=====================  ==========  ============================================================
``SPEED_OF_SOUND_M_S`` 343         "At 20 degree Celsius the speed of sound is 343m/s"
``US_PER_CM``          58.31       D = T C / 2: 2 / 343 m/s = 58.31 us per cm of range
``TIMEOUT_US``         38_000      "Echo pulse will timeout after 38ms of no object detected"
``MIN_RANGE_M``        0.04        "Min Range 4cm" (nearer obstacles read 4 cm)
``MAX_RANGE_M``        4.0         "Max Range 4m" (farther ones time out)
``CONE_DEG``           15          "Measuring Angle 15 degree": nearest point within +-7.5 deg
``TRIGGER_MIN_US``     10          "Trigger Input Signal 10us TTL pulse"
``START_DELAY_US``     213         T_a = 13 us start-up + T_b = 8 cycles at 40 kHz = 0.2 ms
=====================  ==========  ============================================================

A trigger while ECHO is high is ignored, as on the module. The datasheet's 10 us trigger
is the default; ``trigger_min_us`` sets another (modules answer shorter pulses, and
popular drivers send 5 us). The servo is an SG90 driven by
a 50 Hz PWM (``duty_u16``): pulse 0.5..2.5 ms for 0..180 deg (the usual SG90 span; the
seed gives none), turning at 0.12 s per 60 deg (seed 003 §3.3); 90 deg looks straight
ahead. A ping taken while the servo still turns sees along its current angle.
"""

import math

from sim_plant.engine import Part
from sim_plant.plant import NEVER_US, Change
from sim_plant.sonars import sensor_pose

SPEED_OF_SOUND_M_S = 343.0
US_PER_CM = 2.0 / SPEED_OF_SOUND_M_S * 1e4
TIMEOUT_US = 38_000
MIN_RANGE_M = 0.04
MAX_RANGE_M = 4.0
CONE_DEG = 15.0
TRIGGER_MIN_US = 10
START_DELAY_US = 13 + 200


def echo_width_us(range_m: float) -> int:
    """ECHO high time for an obstacle at ``range_m`` (seed 003: 58.31 us per cm)."""
    return round(range_m * 100.0 * US_PER_CM)


class Servo:
    """SG90 position servo: angle follows the commanded pulse at a fixed slew rate.

    ==================  =======  ======================================================
    attribute           default  meaning
    ==================  =======  ======================================================
    ``pwm_freq_hz``     50       PWM frequency the board runs the servo at
    ``min_pulse_us``    500      pulse for 0 deg
    ``max_pulse_us``    2500     pulse for ``range_deg``
    ``range_deg``       180
    ``deg_per_s``       500      60 deg per 0.12 s (seed 003, "SG90, takes 0.12 sec / 60 degrees")
    ``start_deg``       90       straight ahead
    ==================  =======  ======================================================

    A duty of 0 (no pulses) leaves the servo where it is.
    """

    def __init__(
        self,
        name: str = "servo.pwm",
        *,
        pwm_freq_hz: float = 50.0,
        min_pulse_us: float = 500.0,
        max_pulse_us: float = 2500.0,
        range_deg: float = 180.0,
        deg_per_s: float = 60.0 / 0.12,
        start_deg: float = 90.0,
    ):
        self.name = name
        self.period_us = 1e6 / pwm_freq_hz
        self.min_pulse_us = float(min_pulse_us)
        self.max_pulse_us = float(max_pulse_us)
        self.range_deg = float(range_deg)
        self.deg_per_us = deg_per_s / 1e6
        self.t0_us = 0
        self.angle0_deg = float(start_deg)
        self.target_deg = float(start_deg)

    def angle_at(self, t_us: int) -> float:
        span = self.target_deg - self.angle0_deg
        step = self.deg_per_us * (t_us - self.t0_us)
        if abs(span) <= step:
            return self.target_deg
        return self.angle0_deg + math.copysign(step, span)

    def settle_us(self) -> int:
        """Time at which the servo reaches its target."""
        return self.t0_us + math.ceil(abs(self.target_deg - self.angle0_deg) / self.deg_per_us)

    def set_duty(self, t_us: int, duty_u16: int) -> None:
        if int(duty_u16) <= 0:
            target = self.angle_at(t_us)
        else:
            pulse_us = int(duty_u16) / 65535 * self.period_us
            frac = (pulse_us - self.min_pulse_us) / (self.max_pulse_us - self.min_pulse_us)
            target = min(max(frac, 0.0), 1.0) * self.range_deg
        self.angle0_deg = self.angle_at(t_us)
        self.t0_us = t_us
        self.target_deg = target


class HcSr04(Part):
    """Trigger input ``trig``, echo output ``echo``; mounted at ``mount`` on the body,
    on ``servo`` if given (the servo's 90 deg points along the mount's axis)."""

    def __init__(
        self,
        *,
        trig: str = "sonar.trig",
        echo: str = "sonar.echo",
        mount=(0.0, 0.0, 0.0),
        servo: Servo | None = None,
        noise_sd_m: float = 0.003,
        max_range_m: float = MAX_RANGE_M,
        min_range_m: float = MIN_RANGE_M,
        cone_deg: float = CONE_DEG,
        trigger_min_us: int = TRIGGER_MIN_US,
    ):
        self.trig = trig
        self.echo = echo
        self.mount = tuple(float(v) for v in mount)
        self.servo = servo
        self.noise_sd_m = float(noise_sd_m)
        self.max_range_m = float(max_range_m)
        self.min_range_m = float(min_range_m)
        self.half_cone_rad = math.radians(cone_deg) / 2.0
        self.trigger_min_us = int(trigger_min_us)  # shorter TRIG pulses are ignored
        self.inputs = {trig: "level"}
        if servo is not None:
            self.inputs[servo.name] = "duty"
        self.outputs = {echo: "level"}
        self.trig_level = 0
        self.trig_rise_us = 0
        self.echo_level = 0
        self.rise_us = NEVER_US
        self.fall_us = NEVER_US
        self.next_us = NEVER_US
        self.pings = 0
        self.last = {"ping_t_us": None, "ping_range_m": None, "ping_angle_deg": None}

    def initial_outputs(self) -> dict:
        return {self.echo: 0}

    def busy(self) -> bool:
        return self.rise_us != NEVER_US or self.echo_level == 1

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        if self.servo is not None and name == self.servo.name:
            self.servo.set_duty(t_us, value)
            return False
        level = 1 if int(value) else 0
        if level and not self.trig_level:
            self.trig_rise_us = t_us
        elif not level and self.trig_level and t_us - self.trig_rise_us >= self.trigger_min_us and not self.busy():
            self._ping(t_us, plant)
        self.trig_level = level
        return False

    def _ping(self, t_us: int, plant) -> None:
        sx, sy, axis = sensor_pose(plant.pose_at(t_us), self.mount)
        angle_deg = 90.0
        if self.servo is not None:
            angle_deg = self.servo.angle_at(t_us)
            axis += math.radians(angle_deg - 90.0)
        world = plant.world.near(sx, sy, self.max_range_m)
        true_m = world.cone_nearest(sx, sy, axis, self.half_cone_rad, self.max_range_m)
        if math.isfinite(true_m):
            range_m = max(true_m + plant.rng.normal(0.0, self.noise_sd_m), self.min_range_m)
            width = echo_width_us(range_m) if range_m <= self.max_range_m else TIMEOUT_US
        else:
            width = TIMEOUT_US
        self.pings += 1
        self.last = {"ping_t_us": t_us, "ping_range_m": true_m, "ping_angle_deg": angle_deg}
        self.rise_us = t_us + START_DELAY_US
        self.fall_us = self.rise_us + width
        self.next_us = self.rise_us

    def fire(self, t_us: int, plant, out: list) -> None:
        if t_us >= self.fall_us:
            self.echo_level = 0
            self.fall_us = NEVER_US
            self.next_us = NEVER_US
            out.append(Change(t_us, self.echo, 0))
        elif t_us >= self.rise_us:
            self.echo_level = 1
            self.rise_us = NEVER_US
            self.next_us = self.fall_us
            out.append(Change(t_us, self.echo, 1))

    def truth(self, t_us: int, plant) -> dict:
        truth = dict(self.last)
        if self.servo is not None:
            truth["servo_deg"] = self.servo.angle_at(t_us)
            truth["servo_target_deg"] = self.servo.target_deg
        return truth

"""Body ``ackermann``: a car. One ``dc_motor`` (``drives = "rear"``) turns the rear axle;
a ``servo`` with ``steers = true`` turns the front wheels through a linkage. The pose is
the rear axle's centre, moving as a bicycle would (``w = v tan(steer) / wheelbase``);
the body is a disc half-way along the wheelbase. The room, its boxes and our worlds are
the ``differential`` body's."""

import math

from sim_plant.catalogue.base import Build, Opt, PartsError
from sim_plant.catalogue.differential import Differential
from sim_plant.contacts import ContactMonitor
from sim_plant.drivetrain import Body
from sim_plant.engine import Part
from sim_plant.option_table import Num, length
from sim_plant.plant import NEVER_US

STEP_US = 5_000  # the motor's lag and the steering's travel are followed in steps of this
SETTLED_RAD_S = 1e-3


class CarDrive(Part):
    """The rear motor and the steering servo: the body's arc from the wheel speed and the
    front wheels' angle, held within each step while either is still moving."""

    FIXED_STATE = ("bridge", "motor", "inputs", "outputs")

    def __init__(self, bridge, motor, servo, o: dict, pose):
        self.bridge, self.motor, self.servo = bridge, motor, servo
        self.inputs = {**bridge.kinds, **(servo.inputs if servo is not None else {})}
        self.wheel_radius_m, self.wheelbase_m = float(o["wheel_radius_m"]), float(o["wheelbase_m"])
        self.center_deg, self.ratio = float(o["steer_center_deg"]), float(o["steer_ratio"])
        self.max_steer_deg = float(o["max_steer_deg"])
        self.body = Body(*pose)
        self.wheel_rad_s = [0.0, 0.0]  # both rear wheels (encoders, the battery's load)
        self.motors = [motor, motor]
        self.target_rad_s = 0.0
        self.driven = False
        self.next_us = NEVER_US

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        if self.servo is not None and name == self.servo.signal:
            self.servo.set_input(name, value, t_us, plant)
            return True
        role = self.bridge.pins.get(name)
        if role is None or self.bridge.state[role] == int(value):
            return False
        self.bridge.set_pin(role, value)
        return True

    def settle(self, t_us: int, plant) -> bool:
        duty, braking = self.bridge.effective()
        self.target_rad_s = self.motor.steady_rad_s(duty)
        self.driven = braking or duty != 0.0
        steering = self.servo is not None and self.servo.next_us != NEVER_US
        if self.target_rad_s == self.wheel_rad_s[0] and not steering:
            return False
        if self.motor.time_constant_ms <= 0.0:
            self.wheel_rad_s = [self.target_rad_s] * 2
            self._apply(t_us)
            if not steering:
                return True
        if self.next_us == NEVER_US:
            self.next_us = t_us + STEP_US
        return False

    def fire(self, t_us: int, plant, out: list) -> None:
        w, target = self.wheel_rad_s[0], self.target_rad_s
        w += (target - w) * self.motor.lag_factor(STEP_US, coasting=not self.driven)
        if abs(target - w) < SETTLED_RAD_S:
            w = target
        self.wheel_rad_s = [w, w]
        if self.servo is not None and self.servo.next_us != NEVER_US:
            self.servo.step(t_us)
        self._apply(t_us)
        moving = w != target or (self.servo is not None and self.servo.next_us != NEVER_US)
        self.next_us = t_us + STEP_US if moving else NEVER_US

    def steer_rad(self) -> float:
        if self.servo is None:
            return 0.0
        deg = (self.servo.angle_deg - self.center_deg) * self.ratio
        return math.radians(max(-self.max_steer_deg, min(self.max_steer_deg, deg)))

    def _apply(self, t_us: int) -> None:
        v = self.wheel_rad_s[0] * self.wheel_radius_m
        self.body.set_arc(t_us, v, v * math.tan(self.steer_rad()) / self.wheelbase_m)

    def encoder_rad_s(self) -> tuple[float, float]:
        return tuple(self.wheel_rad_s)

    def truth(self, t_us: int, plant) -> dict:
        v = self.wheel_rad_s[0] * self.wheel_radius_m
        steer = self.steer_rad()
        truth = {
            "v_m_s": v,
            "w_rad_s": v * math.tan(steer) / self.wheelbase_m,
            "steer_deg": math.degrees(steer),
            "wheel_rad_s": tuple(self.wheel_rad_s),
            "distance_m": self.body.distance_at(t_us),
        }
        if self.servo is not None:
            truth.update(self.servo.truth(t_us, plant))
        return truth


class Ackermann(Differential):
    kind = "ackermann"
    doc = "A car: a rear drive motor and front wheels a steering servo turns (Ackermann steering)."
    OPTIONS = tuple(
        o for o in Differential.OPTIONS if o.name not in ("track_m", "body_radius_m", "wheel_slip_sd", "slip_period_us")
    ) + (
        Opt("body_radius_m", length(0.01, 5), 0.12, "the disc (half-way along the wheelbase) that touches walls"),
        Opt("wheelbase_m", length(0.01, 10), 0.16, "front axle to rear axle"),
        Opt("steer_center_deg", Num("degrees", 0, 360), 90.0, "the servo's angle with the wheels straight"),
        Opt(
            "steer_ratio",
            Num("wheel degrees per servo degree", -10, 10),
            1.0,
            "the linkage; positive: a servo angle above the centre steers left",
        ),
        Opt("max_steer_deg", Num("degrees", 1, 60), 30.0, "the front wheels turn no further (their stops)"),
    )

    def drive(self, build: Build, pose):
        motors = dict(build.motors)
        if list(motors) != ["rear"]:
            got = ", ".join(sorted(motors)) or "none"
            raise PartsError(f"[plant] body: the ackermann body needs one dc_motor that drives 'rear', got {got}")
        steering = [p for p in build.parts if getattr(p, "steers", False)]
        if len(steering) > 1:
            raise PartsError("[plant] body: the ackermann body takes one servo with steers = true")
        for servo in steering:
            build.parts.remove(servo)  # the drive owns it: its travel moves the body
            servo.owned = True
        bridge, motor = motors["rear"]
        return CarDrive(bridge, motor, steering[0] if steering else None, self.options, pose)

    def contact_monitor(self, build: Build):
        o = self.options
        return ContactMonitor([(o["wheelbase_m"] / 2, 0.0, o["body_radius_m"])], build.bumpers)

"""Seed 003's vacuum cleaner robot ("RoboClean") in a room with convex furniture.

A disc 25 cm across (Table 3.2: chassis 25 x 25 cm) with two TT gear motors (1:48) on the
centre axis and a rear caster, so it can spin in place; an H-bridge per motor (the seed
names none: an L298N-style IN1/IN2 + enable PWM is assumed), F249 slotted-disk IR speed
sensors on the wheels (single channel, §3.4), and an HC-SR04 on an SG90 servo at the front
(:mod:`sim_plant.hcsr04`). The seed has no bumper; ``bumper=True`` adds one.

Signals:

==================  ======  ===========================================================
name                kind    meaning
==================  ======  ===========================================================
``motor_l.in1``     level   L298N IN1/IN2 of the left motor
``motor_l.in2``     level
``motor_l.pwm``     duty    ENA
``motor_r.in1``     level
``motor_r.in2``     level
``motor_r.pwm``     duty    ENB
``enc_l``           level   left slotted disk, toggles twice per slot
``enc_r``           level
``sonar.trig``      level   HC-SR04 TRIG
``sonar.echo``      level   HC-SR04 ECHO
``servo.pwm``       duty    SG90 control at 50 Hz
``bumper``          level   0 while pressed (only with ``bumper=True``)
==================  ======  ===========================================================

Not in the seed, chosen here (seed 003 notes §1): wheel diameter 65 mm (the usual wheel of
a TT motor), wheel spacing 0.18 m, rim speed 0.35 m/s at full duty, 20 slots per disk (the
disk sold with the F249 module), a dead band of 25 % duty ("At low speed the motor was not
able to supply the required torque", §5.2).

Worlds (``world``): ``"vacuum_room"``, a 5 x 4 m room with three pieces of furniture;
``"empty"``, a ``room_w_m`` x ``room_h_m`` room with nothing in it (the seed's go-to-goal
tests); ``"furnished"``, that room with convex furniture across the legs of ``route``
(start and goals, m), drawn from the plant's seed at each reset
(:mod:`sim_plant.furniture`); or a :class:`~sim_plant.world.World`. The robot starts at
``start_pose``, by default (0.5, 0.5, 0), or at the route's first point facing +x.
"""

from sim_plant.contacts import ContactMonitor, front_bumper
from sim_plant.coverage import CoverageGrid, CoverageRecorder
from sim_plant.drivetrain import DiffDriveTrain
from sim_plant.encoders import SlottedDiskEncoder
from sim_plant.engine import RobotPlant
from sim_plant.furniture import DEFAULT_ROUTE, furnished_room
from sim_plant.hcsr04 import HcSr04, Servo
from sim_plant.motors import DirPinsPwmBridge
from sim_plant.world import World, rectangle, vacuum_room

BODY_RADIUS_M = 0.125
WORLDS = ("vacuum_room", "empty", "furnished")


class VacuumRobot(RobotPlant):
    def __init__(
        self,
        *,
        world="vacuum_room",
        room_w_m=5.0,
        room_h_m=4.0,
        route=DEFAULT_ROUTE,
        start_pose=None,
        wheel_diameter_m=0.065,
        track_m=0.18,
        v_max_m_s=0.35,
        deadband_duty=0.25,
        motor_gains=(1.0, 1.0),
        motor_time_constant_ms=0.0,
        slots_per_rev=20,
        sonar_noise_sd_m=0.003,
        bumper=False,
        bumper_bounce_us=0,
        coverage_cell_m=0.05,
    ):
        if not isinstance(world, World) and world not in WORLDS:
            raise ValueError(f"world: expected one of {', '.join(WORLDS)} or a World, got {world!r}")
        self.world_name = world if isinstance(world, str) else None
        self.room_w_m, self.room_h_m = float(room_w_m), float(room_h_m)
        self.route = tuple((float(x), float(y)) for x, y in route)
        if world == "vacuum_room":
            self.world = vacuum_room()
        elif world == "empty":
            self.world = rectangle(self.room_w_m, self.room_h_m, name=f"empty room {room_w_m:g} x {room_h_m:g} m")
        elif world != "furnished":
            self.world = world
        if start_pose is None:
            start_pose = (*self.route[0], 0.0) if world == "furnished" else (0.5, 0.5, 0.0)
        self._set_wheels(
            start_pose=start_pose,
            wheel_radius_m=float(wheel_diameter_m) / 2,
            track_m=track_m,
            v_max_m_s=v_max_m_s,
            deadband_duty=deadband_duty,
            motor_gains=motor_gains,
            motor_time_constant_ms=motor_time_constant_ms,
            bumper=bumper,
            bumper_bounce_us=bumper_bounce_us,
        )
        self.slots_per_rev = int(slots_per_rev)
        self.sonar_noise_sd_m = float(sonar_noise_sd_m)
        self.coverage_cell_m = float(coverage_cell_m)
        super().__init__()

    def _build(self) -> None:
        if self.world_name == "furnished":  # a layout per seed
            self.world = furnished_room(self.rng, self.route, room_w_m=self.room_w_m, room_h_m=self.room_h_m)
        motors = self._wheel_motors()
        self.drive = DiffDriveTrain(
            bridges=(DirPinsPwmBridge("motor_l"), DirPinsPwmBridge("motor_r")),
            motors=motors,
            wheel_radius_m=self.wheel_radius_m,
            track_m=self.track_m,
            start_pose=self.start_pose,
        )
        self.encoders = [
            SlottedDiskEncoder(("enc_l",), wheel=0, lines_per_rev=self.slots_per_rev),
            SlottedDiskEncoder(("enc_r",), wheel=1, lines_per_rev=self.slots_per_rev),
        ]
        bumpers = [front_bumper(70.0, self.bumper_bounce_us)] if self.bumper else []
        self.parts = [
            ContactMonitor([(0.0, 0.0, BODY_RADIUS_M)], bumpers),
            HcSr04(mount=(0.10, 0.0, 0.0), servo=Servo(), noise_sd_m=self.sonar_noise_sd_m),
            CoverageRecorder(CoverageGrid(self.world, self.coverage_cell_m, BODY_RADIUS_M)),
        ]

"""Seed 004's dead-reckoning lab robot: a two-wheeled differential robot with quadrature
wheel encoders, in an open arena (the 2 m square path) or the S-curve "canyon" (wall
following).

The seed (an Aria/MobileSim lab report) gives the encoder principle (Table 1, phases AB =
00, 10, 11, 01) and the odometry equations but no robot numbers; the ones below are
harness choices for a small robot. Motors sit behind DRV8833-style two-PWM bridges; two
analog sonars (front and left, for left-wall following, ``ArActionWallFollow::leftSide``)
are read through a 12-bit ADC every 100 ms (SonarBot polls every 100 ms).

Signals:

==================  ======  ===========================================================
name                kind    meaning
==================  ======  ===========================================================
``motor_l.in1``     duty    DRV8833 AIN1 (PWM)
``motor_l.in2``     duty    DRV8833 AIN2 (PWM)
``motor_r.in1``     duty    BIN1
``motor_r.in2``     duty    BIN2
``enc_l.a``         level   left encoder, channel A (leads B going forwards)
``enc_l.b``         level
``enc_r.a``         level
``enc_r.b``         level
``sonar_f.adc``     u16     front sonar (MaxBotix law), new sample every 100 ms
``sonar_l.adc``     u16     left-looking sonar
``bumper``          level   0 while pressed (only with ``bumper=True``)
==================  ======  ===========================================================

=======================  =========  ==================================================
parameter                default    meaning
=======================  =========  ==================================================
``wheel_radius_m``       0.035
``track_m``              0.20       w, "distance between the contact points of the wheels"
``v_max_m_s``            0.5
``deadband_duty``        0.05
``lines_per_rev``        10         lines on the motor-shaft disk (4 counts each)
``gear_ratio``           2.0        motor turns per wheel turn: 80 counts per wheel turn
``polarity``             (1, 1)     -1 for an encoder mounted mirrored
=======================  =========  ==================================================
"""

import math

from sim_plant.contacts import ContactMonitor, front_bumper
from sim_plant.drivetrain import DiffDriveTrain
from sim_plant.encoders import QuadratureEncoder
from sim_plant.engine import RobotPlant
from sim_plant.motors import TwoPwmBridge
from sim_plant.sonars import MAXBOTIX_V_PER_M, Adc, AnalogRangeSonar, BeamRangeModel
from sim_plant.world import World, canyon, rectangle

BODY_RADIUS_M = 0.14


def _canyon_start() -> tuple[float, float, float]:
    x = 0.4
    return x, 1.5 * math.sin(math.pi * x / 4), math.atan(1.5 * math.pi / 4 * math.cos(math.pi * x / 4))


WORLDS = {
    "arena": (lambda: rectangle(4.0, 4.0, name="arena 4 x 4 m"), (1.0, 1.0, 0.0)),
    "canyon": (canyon, _canyon_start()),
}


class LabRobot(RobotPlant):
    def __init__(
        self,
        *,
        world="arena",
        start_pose=None,
        wheel_radius_m=0.035,
        track_m=0.20,
        v_max_m_s=0.5,
        deadband_duty=0.05,
        motor_gains=(1.0, 1.0),
        motor_time_constant_ms=0.0,
        lines_per_rev=10,
        gear_ratio=2.0,
        polarity=(1, 1),
        spin_slip=0.0,
        sonar_period_us=100_000,
        sonar_noise_m=0.01,
        bumper=False,
        bumper_bounce_us=0,
    ):
        if isinstance(world, World):
            self.world, default_start = world, (0.0, 0.0, 0.0)
        elif world in WORLDS:
            make, default_start = WORLDS[world]
            self.world = make()
        else:
            raise ValueError(f"world: one of {sorted(WORLDS)} or a World, got {world!r}")
        self._set_wheels(
            start_pose=start_pose or default_start,
            wheel_radius_m=wheel_radius_m,
            track_m=track_m,
            v_max_m_s=v_max_m_s,
            deadband_duty=deadband_duty,
            motor_gains=motor_gains,
            motor_time_constant_ms=motor_time_constant_ms,
            bumper=bumper,
            bumper_bounce_us=bumper_bounce_us,
        )
        self.lines_per_rev = int(lines_per_rev)
        self.gear_ratio = float(gear_ratio)
        self.polarity = tuple(polarity)
        self.spin_slip = float(spin_slip)
        self.sonar_period_us = int(sonar_period_us)
        self.sonar_noise_m = float(sonar_noise_m)
        super().__init__()

    def _build(self) -> None:
        motors = self._wheel_motors()
        self.drive = DiffDriveTrain(
            bridges=(TwoPwmBridge("motor_l"), TwoPwmBridge("motor_r")),
            motors=motors,
            wheel_radius_m=self.wheel_radius_m,
            track_m=self.track_m,
            start_pose=self.start_pose,
            spin_slip=self.spin_slip,
        )
        enc = {"lines_per_rev": self.lines_per_rev, "gear_ratio": self.gear_ratio}
        self.encoders = [
            QuadratureEncoder(("enc_l.a", "enc_l.b"), wheel=0, polarity=self.polarity[0], **enc),
            QuadratureEncoder(("enc_r.a", "enc_r.b"), wheel=1, polarity=self.polarity[1], **enc),
        ]
        bumpers = [front_bumper(70.0, self.bumper_bounce_us)] if self.bumper else []
        sonar = {"noise_sd_m": self.sonar_noise_m, "min_m": 0.15, "max_m": 5.0}
        adc = {"period_us": self.sonar_period_us, "volts_per_m": MAXBOTIX_V_PER_M}
        self.parts = [
            ContactMonitor([(0.0, 0.0, BODY_RADIUS_M)], bumpers),
            AnalogRangeSonar(
                "sonar_f.adc",
                BeamRangeModel((BODY_RADIUS_M, 0.0, 0.0), **sonar),
                phase_us=20_000,
                adc=Adc(12, 3.3),
                **adc,
            ),
            AnalogRangeSonar(
                "sonar_l.adc",
                BeamRangeModel((0.0, BODY_RADIUS_M, math.pi / 2), **sonar),
                phase_us=70_000,
                adc=Adc(12, 3.3),
                **adc,
            ),
        ]

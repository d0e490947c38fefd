"""A first plant: a round differential-drive rover in a rectangular room.

The robot is a disc (vacuum-cleaner shape) with two driven wheels behind TB6612-style
H-bridges (IN1/IN2 direction pins + PWM), a quadrature encoder on each wheel, one
front-looking analog sonar read through an ADC, and a front bumper switch.

Wheel speeds follow the commanded duty at once (no motor lag); between input changes
they are constant, so the pose follows exact arcs and encoder edges fall at exactly
computable times. Built from the shared parts: :class:`~sim_plant.drivetrain.DiffDriveTrain`,
:class:`~sim_plant.encoders.QuadratureEncoder`, :class:`~sim_plant.sonars.AnalogRangeSonar`,
:class:`~sim_plant.contacts.ContactMonitor`, :func:`~sim_plant.world.rectangle`.

Parameters (units in the names):

=======================  =========  ==================================================
name                     default    meaning
=======================  =========  ==================================================
``room_w_m, room_h_m``   5.0, 4.0   room interior, walls at x=0, x=w, y=0, y=h
``body_radius_m``        0.17       disc radius; the bumper is the front 140 degrees
``wheel_radius_m``       0.033      driven wheel radius
``track_m``              0.23       distance between the wheels
``v_max_m_s``            0.5        wheel rim speed at full duty
``deadband_duty``        0.08       duty fraction below which a wheel does not turn
``encoder_cpr``          20         quadrature cycles per wheel revolution (80 edges)
``sonar_period_us``      500_000    a new sonar range every 500 ms
``sonar_phase_us``       20_000     first sample time
``sonar_noise_m``        0.01       standard deviation of the range noise
``sonar_min_m``          0.03       closest range the sonar reports
``sonar_max_m``          4.0        farthest range (reported when nothing is nearer)
``adc_bits``             12         ADC resolution; ``read_u16`` scales it to 16 bits
``adc_vref``             3.3        ADC full-scale volts
``bumper_bounce_us``     0          contact bounce window of the bumper (0: clean)
=======================  =========  ==================================================

Sonar volts follow the MaxBotix LV analog law, Vcc/512 per inch at 3.3 V.
"""

import math

from sim_plant.contacts import Bumper, ContactMonitor
from sim_plant.coverage import CoverageGrid, CoverageRecorder
from sim_plant.drivetrain import DiffDriveTrain
from sim_plant.encoders import QuadratureEncoder
from sim_plant.engine import RobotPlant
from sim_plant.motors import DcMotor, DirPinsPwmBridge
from sim_plant.sonars import MAXBOTIX_V_PER_M, Adc, AnalogRangeSonar, BeamRangeModel
from sim_plant.world import rectangle

SONAR_V_PER_M = MAXBOTIX_V_PER_M
BUMPER_HALF_ARC_RAD = math.radians(70)
COVERAGE_CELL_M = 0.1


class RoverRoom(RobotPlant):
    def __init__(
        self,
        *,
        room_w_m=5.0,
        room_h_m=4.0,
        start_pose=(1.0, 2.0, 0.0),
        body_radius_m=0.17,
        wheel_radius_m=0.033,
        track_m=0.23,
        v_max_m_s=0.5,
        deadband_duty=0.08,
        encoder_cpr=20,
        sonar_period_us=500_000,
        sonar_phase_us=20_000,
        sonar_noise_m=0.01,
        sonar_min_m=0.03,
        sonar_max_m=4.0,
        adc_bits=12,
        adc_vref=3.3,
        bumper_bounce_us=0,
    ):
        self.room_w_m = float(room_w_m)
        self.room_h_m = float(room_h_m)
        for name, size in (("room_w_m", self.room_w_m), ("room_h_m", self.room_h_m)):
            if not size > 2 * body_radius_m:
                raise ValueError(
                    f"{name}: expected a room wider than the robot ({2 * body_radius_m:g} m), got {size:g}"
                )
        self.start_pose = tuple(float(v) for v in start_pose)
        self.body_radius_m = body_radius_m
        self.wheel_radius_m = wheel_radius_m
        self.track_m = track_m
        self.v_max_m_s = v_max_m_s
        self.deadband_duty = deadband_duty
        self.encoder_cpr = encoder_cpr
        self.sonar_period_us = sonar_period_us
        self.sonar_phase_us = sonar_phase_us
        self.sonar_noise_m = sonar_noise_m
        self.sonar_min_m = sonar_min_m
        self.sonar_max_m = sonar_max_m
        self.adc_bits = adc_bits
        self.adc_vref = adc_vref
        self.bumper_bounce_us = bumper_bounce_us
        self.world = rectangle(self.room_w_m, self.room_h_m, name="rover room")
        super().__init__()

    def _build(self) -> None:
        motor = {"max_wheel_rad_s": self.v_max_m_s / self.wheel_radius_m, "deadband_duty": self.deadband_duty}
        self.drive = DiffDriveTrain(
            bridges=(DirPinsPwmBridge("motor_l"), DirPinsPwmBridge("motor_r")),
            motors=(DcMotor(**motor), DcMotor(**motor)),
            wheel_radius_m=self.wheel_radius_m,
            track_m=self.track_m,
            start_pose=self.start_pose,
        )
        self.encoders = [
            QuadratureEncoder(("enc_l.a", "enc_l.b"), wheel=0, lines_per_rev=self.encoder_cpr),
            QuadratureEncoder(("enc_r.a", "enc_r.b"), wheel=1, lines_per_rev=self.encoder_cpr),
        ]
        sonar = BeamRangeModel(
            noise_sd_m=self.sonar_noise_m, min_m=self.sonar_min_m, max_m=self.sonar_max_m, offset_m=self.body_radius_m
        )
        self.parts = [
            ContactMonitor(
                [(0.0, 0.0, self.body_radius_m)],
                [Bumper("bumper", circles=(0,), center_deg=0.0, half_arc_deg=70.0, bounce_us=self.bumper_bounce_us)],
            ),
            AnalogRangeSonar(
                "sonar.adc",
                sonar,
                period_us=self.sonar_period_us,
                phase_us=self.sonar_phase_us,
                volts_per_m=SONAR_V_PER_M,
                adc=Adc(self.adc_bits, self.adc_vref),
            ),
            CoverageRecorder(CoverageGrid(self.world, COVERAGE_CELL_M, self.body_radius_m)),
        ]

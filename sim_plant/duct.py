"""Seed 002's duct inspection robot in a rectilinear duct network.

A two-wheeled differential-drive robot, 200 mm wide and 280 mm long, with its driven
wheels at the front and a jockey wheel at the rear (§3.2-3.3), LMD18200 H-bridges (DIR
+ PWM, §3.3.3), slotted-disk encoders on the motor shafts read by external interrupts
(single channel, no direction, §3.3.3), and three amplitude sonars, front, left and right,
read by an 8-bit ADC (:mod:`sim_plant.amplitude_sonar`). The real robot had no bump
sensors; ``bumper=True`` adds the front bumper the thesis recommends as future work.

Signals:

==================  ======  ===========================================================
name                kind    meaning
==================  ======  ===========================================================
``motor_l.dir``     level   direction of the left wheel, 1 forwards
``motor_l.pwm``     duty    magnitude (LMD18200 sign/magnitude drive)
``motor_r.dir``     level
``motor_r.pwm``     duty
``enc_l``           level   left slotted disk (motor shaft), toggles twice per slot
``enc_r``           level
``sonar_f.adc``     u16     front amplitude sonar (8-bit reading scaled to 16 bits)
``sonar_l.adc``     u16     left
``sonar_r.adc``     u16     right
``bumper``          level   0 while pressed (only with ``bumper=True``)
``link.uart``       bytes   the master link, both ways: the robot's record stream in,
                            the master's polls and commands out (``link=True``)
==================  ======  ===========================================================

The seed gives no wheel size, slot count, gear ratio, track or top speed (notes §8 item
7); the defaults below are harness choices, picked so that the robot crawls at 0.1-0.3
m/s with a handful of encoder edges per 50 ms quantum:

=======================  =======  ==================================================
parameter                default  meaning
=======================  =======  ==================================================
``wheel_diameter_m``     0.060
``track_m``              0.18     wheel spacing (inside the 200 mm body)
``v_max_m_s``            0.4      rim speed at full duty
``deadband_duty``        0.10     |duty| that only overcomes the drive's losses
                                  (the rig file sets 0.22 and 0.70 m/s: docs/duct.md)
``motor_gains``          (1, 1)   per-wheel gain; seed 002's simulation tried a
                                  constant 10 % error on one wheel (eq. B.8)
``slots_per_rev``        8        slots on the motor-shaft disk
``gear_ratio``           6        motor turns per wheel turn
``spin_slip``            0.3      share of travel the backward wheel's encoder misses
                                  while spinning (§5.7)
``sonar_gains``          (1.0, 1.05, 0.95)  front, left, right: "small differences in
                                  components" (App. C) that the firmware calibrates
``link``                 False    a master on the UART that drains the record
                                  stream (:mod:`sim_plant.duct_link`)
``snag_p``               0        chance that the tether snags at a spin
                                  (:mod:`sim_plant.tether`)
=======================  =======  ==================================================
"""

import math

from sim_plant.amplitude_sonar import AmplitudeChannel, AmplitudeSonarArray
from sim_plant.contacts import ContactMonitor, front_bumper
from sim_plant.drivetrain import DiffDriveTrain
from sim_plant.duct_link import RecordReader
from sim_plant.encoders import SlottedDiskEncoder
from sim_plant.engine import RobotPlant
from sim_plant.motors import DirPwmBridge
from sim_plant.tether import TetherSnag
from sim_plant.world import DUCT_WIDTH_M, World, duct_network, multi_branch_duct, one_right_branch_duct


def straight_duct(length_m: float = 1.5, width_m: float = DUCT_WIDTH_M) -> World:
    """A straight duct along +x from 0 to ``length_m``, closed at both ends: from the
    default start (x = 0.3 m) the robot drives about 1 m to the end (seed 002 §5.4, "a
    straight line test through a duct of roughly 1m")."""
    return duct_network([(0.0, 0.0, length_m, width_m)], name=f"straight duct {length_m:g} m")


def bench_duct() -> World:
    """A long straight duct for the speed-loop step tests (seed 002 App. D.5)."""
    return straight_duct(8.0)


WORLDS = {
    "one_right_branch": one_right_branch_duct,
    "multi_branch": multi_branch_duct,
    "straight_1m": straight_duct,
    "bench": bench_duct,
}
BODY_CIRCLES = ((-0.04, 0.0, 0.10), (-0.12, 0.0, 0.10))
"""Body outline 200 x 280 mm, wheels at the front: two circles of r = 100 mm covering
x = -0.22 .. +0.06 m from the axle."""
SONAR_MOUNTS = {
    "sonar_f.adc": (0.04, 0.0, 0.0),
    "sonar_l.adc": (-0.10, 0.09, math.pi / 2),
    "sonar_r.adc": (-0.10, -0.09, -math.pi / 2),
}
"""Front sonar at the front edge; side sonars mid-body, set 10 mm in from the sides so that
walls nearer than the 30 mm minimum range are still seen (App. C.4.1)."""


class DuctRobot(RobotPlant):
    def __init__(
        self,
        *,
        world="one_right_branch",
        start_pose=(0.3, 0.2, 0.0),
        wheel_diameter_m=0.060,
        track_m=0.18,
        v_max_m_s=0.4,
        deadband_duty=0.10,
        motor_gains=(1.0, 1.0),
        motor_time_constant_ms=0.0,
        slots_per_rev=8,
        gear_ratio=6.0,
        spin_slip=0.3,
        sonar_gains=(1.0, 1.05, 0.95),
        sonar_options=None,
        bumper=False,
        bumper_bounce_us=0,
        link=False,
        link_options=None,
        snag_p=0.0,
        snag_options=None,
    ):
        if isinstance(world, World):
            self.world = world
        elif world in WORLDS:
            self.world = WORLDS[world]()
        else:
            raise ValueError(f"world: one of {sorted(WORLDS)} or a World, got {world!r}")
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
        self.gear_ratio = float(gear_ratio)
        self.spin_slip = float(spin_slip)
        self.sonar_gains = tuple(sonar_gains)
        self.sonar_options = dict(sonar_options or {})
        self.link = bool(link)
        self.link_options = dict(link_options or {})
        self.snag_p = float(snag_p)
        self.snag_options = dict(snag_options or {})
        super().__init__()

    def _build(self) -> None:
        motors = self._wheel_motors()
        self.drive = DiffDriveTrain(
            bridges=(DirPwmBridge("motor_l"), DirPwmBridge("motor_r")),
            motors=motors,
            wheel_radius_m=self.wheel_radius_m,
            track_m=self.track_m,
            start_pose=self.start_pose,
            spin_slip=self.spin_slip,
        )
        enc = {"lines_per_rev": self.slots_per_rev, "gear_ratio": self.gear_ratio}
        self.encoders = [SlottedDiskEncoder(("enc_l",), wheel=0, **enc), SlottedDiskEncoder(("enc_r",), wheel=1, **enc)]
        bumpers = [front_bumper(60.0, self.bumper_bounce_us)] if self.bumper else []
        channels = [
            AmplitudeChannel(name, mount, gain) for (name, mount), gain in zip(SONAR_MOUNTS.items(), self.sonar_gains)
        ]
        self.parts = [ContactMonitor(BODY_CIRCLES, bumpers), AmplitudeSonarArray(channels, **self.sonar_options)]
        if self.link:
            self.parts.append(RecordReader(**self.link_options))
        if self.snag_p > 0:
            self.parts.append(TetherSnag(p_snag=self.snag_p, **self.snag_options))

"""Seed 002's duct inspection robot: its worlds and figures, for its rig file
(``firmware/apps/duct/rig.toml``: a ``differential`` body with ``dc_motor``, ``encoder``,
``amplitude_sonar``, ``record_link`` and ``tether`` parts, docs/parts.md) and its tests.

A two-wheeled differential-drive robot, 200 mm wide and 280 mm long, with its driven
wheels at the front and a jockey wheel at the rear (§3.2-3.3), LMD18200 H-bridges (DIR
+ PWM, §3.3.3), slotted-disk encoders on the motor shafts read by external interrupts
(single channel, no direction, §3.3.3), and three amplitude sonars, front, left and right,
read by an 8-bit ADC (:mod:`sim_plant.physics.amplitude_sonar`). The real robot had no bump
sensors; a ``bumper`` part adds the front bumper the thesis recommends as future work.

Signals (the rig file's part names):

==================  ======  ===========================================================
name                kind    meaning
==================  ======  ===========================================================
``motor_l.dir``     level   direction of the left wheel, 1 forwards
``motor_l.pwm``     duty    magnitude (LMD18200 sign/magnitude drive)
``motor_r.dir``     level
``motor_r.pwm``     duty
``enc_l.out``       level   left slotted disk (motor shaft), toggles twice per slot
``enc_r.out``       level
``sonar_f.adc``     u16     front amplitude sonar (8-bit reading scaled to 16 bits)
``sonar_l.adc``     u16     left
``sonar_r.adc``     u16     right
``link.uart``       bytes   the master link, both ways: the robot's record stream in,
                            the master's polls and commands out
==================  ======  ===========================================================

The seed gives no wheel size, slot count, gear ratio, track or top speed (notes §8 item
7); the rig file's figures are harness choices (docs/duct.md, "The drive").
"""

from sim_plant.world import DUCT_WIDTH_M, World, duct_network

DUCT_START = (0.3, 0.2, 0.0)
"""Where the robot starts in every duct world: 0.3 m in, on the duct's centre line."""


def straight_duct(length_m: float = 1.5, width_m: float = DUCT_WIDTH_M) -> World:
    """A straight duct along +x from 0 to ``length_m``, closed at both ends: from the
    default start (x = 0.3 m) the robot drives about 1 m to the end (seed 002 §5.4, "a
    straight line test through a duct of roughly 1m")."""
    return duct_network([(0.0, 0.0, length_m, width_m)], name=f"straight duct {length_m:g} m")


def bench_duct() -> World:
    """A long straight duct for the speed-loop step tests (seed 002 App. D.5)."""
    return straight_duct(8.0)


BODY_CIRCLES = ((-0.04, 0.0, 0.10), (-0.12, 0.0, 0.10))
"""Body outline 200 x 280 mm, wheels at the front: two circles of r = 100 mm covering
x = -0.22 .. +0.06 m from the axle (the rig file's ``outline``)."""

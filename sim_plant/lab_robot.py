"""Seed 004's dead-reckoning lab robot: a two-wheeled differential robot with quadrature
wheel encoders, in an open arena (the 2 m square path) or the S-curve "canyon" (wall
following).

The seed (an Aria/MobileSim lab report) gives the encoder principle (Table 1, phases AB =
00, 10, 11, 01) and the odometry equations but no robot numbers; the ones below are
harness choices for a small robot. Motors sit behind DRV8833-style two-PWM bridges; three
MaxBotix-style analog sonars (front, left, and left 45 degrees forward, for left-wall
following, ``ArActionWallFollow::leftSide``) are read through a 12-bit ADC. They take a
new range every ``sonar_period_us`` on their own, or with ``sonar_rx=True`` when the
board raises their shared RX line (the sonar chain's trigger), ``sonar_ranging_us``
later: then the board sets the pace (SonarBot polls every 100 ms).

Signals:

===================  ======  ===========================================================
name                 kind    meaning
===================  ======  ===========================================================
``motor_l.in1``      duty    DRV8833 AIN1 (PWM)
``motor_l.in2``      duty    DRV8833 AIN2 (PWM)
``motor_r.in1``      duty    BIN1
``motor_r.in2``      duty    BIN2
``enc_l.a``          level   left encoder, channel A (leads B going forwards)
``enc_l.b``          level
``enc_r.a``          level
``enc_r.b``          level
``sonar_f.adc``      u16     front sonar (MaxBotix law)
``sonar_l.adc``      u16     left-looking sonar (abeam)
``sonar_lf.adc``     u16     left-front sonar, 45 degrees off the heading
``sonar.rx``         level   in, with ``sonar_rx=True``: a rising edge starts a ranging
``jumper``           level   the program jumper: 0 when fitted (to ground), 1 when open
``bumper``           level   0 while pressed (only with ``bumper=True``)
===================  ======  ===========================================================

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
``spin_slip``            0          share of a backwards wheel's travel its encoder misses
                                    while the robot spins
``wheel_slip_sd``        0          wheel slip: every ``slip_period_us`` each wheel's
                                    encoder sees its floor travel times (1 + s), s drawn
                                    from N(0, wheel_slip_sd)
``slip_period_us``       100_000
``missed_edge_p``        0          chance per encoder edge that the next edge comes at
                                    the same instant (closer than the board's IRQ
                                    latency): the board sees a two-phase jump
``sonar_rx``             False      sonars range when the board raises ``sonar.rx``
``sonar_ranging_us``     49_000     from the RX edge to the new reading (LV-EZ: 49 ms)
``program_jumper``       False      the program jumper is fitted (``jumper`` reads 0)
=======================  =========  ==================================================

Ground truth adds ``enc_l_missed``, ``enc_r_missed`` (edges made to coincide) and
``wheel_slip`` (each wheel's current slip).
"""

import math

from sim_plant.contacts import ContactMonitor, front_bumper
from sim_plant.drivetrain import DiffDriveTrain
from sim_plant.encoders import QuadratureEncoder
from sim_plant.engine import Part, RobotPlant
from sim_plant.motors import TwoPwmBridge
from sim_plant.plant import NEVER_US
from sim_plant.sonars import MAXBOTIX_V_PER_M, Adc, AnalogRangeSonar, BeamRangeModel
from sim_plant.world import World, canyon, rectangle

BODY_RADIUS_M = 0.14
MISS_GAPS = 4096
"""Gaps between missed edges drawn at reset (used in turn, then again from the first)."""

WORLDS = {
    "arena": (lambda: rectangle(4.0, 4.0, name="arena 4 x 4 m"), (1.0, 1.0, 0.0)),
    # 0.4 m off the left wall, the one it follows, 0.3 m from the closed end
    "canyon": (canyon, (0.3, 0.2, 0.0)),
}


class LabDriveTrain(DiffDriveTrain):
    """The differential drive with wheel slip: each wheel's encoder sees its travel over
    the floor times ``1 + slip[i]`` (spin slip comes on top)."""

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.slip = [0.0, 0.0]

    def encoder_rad_s(self) -> tuple[float, float]:
        wl, wr = super().encoder_rad_s()
        return wl * (1.0 + self.slip[0]), wr * (1.0 + self.slip[1])


class WheelSlip(Part):
    """Draws each wheel's slip every ``period_us`` (the drive then re-plans the encoders)."""

    def __init__(self, sd: float, period_us: int):
        if sd < 0 or period_us <= 0:
            raise ValueError(f"wheel_slip_sd must be >= 0 and slip_period_us > 0, got {sd}, {period_us}")
        self.sd = float(sd)
        self.period_us = int(period_us)
        self.next_us = 0
        self.changed = False

    def fire(self, t_us: int, plant, out: list) -> None:
        plant.drive.slip = [float(s) for s in plant.rng.normal(0.0, self.sd, 2)]
        self.changed = True
        self.next_us = t_us + self.period_us

    def truth(self, t_us: int, plant) -> dict:
        return {"wheel_slip": tuple(plant.drive.slip)}


class MissingEdgeEncoder(QuadratureEncoder):
    """A quadrature encoder whose edges now and then come two at once, as they do for a
    board when two edges fall closer together than its interrupt latency.

    After every ``gaps[i]`` edges (drawn at reset, each >= 2) the next edge is emitted
    at the same instant as the current one, if the wheel has turned the same way for
    the last two edges (a board only misses edges at speed). ``missed`` counts them.
    The disk's phase is not moved: the edge after comes when it would have, so the
    counts still follow the wheel's travel."""

    def __init__(self, names, *, gaps: tuple, **kwargs):
        super().__init__(names, **kwargs)
        self.gaps = gaps
        self.gap_no = 0
        self.until_miss = gaps[0]
        self.missed = 0
        self.last_dir = 0
        self.doubled = False  # the next edge is due at the instant of the last one

    def emit(self, t_us: int, out: list) -> None:
        super().emit(t_us, out)
        direction = 1 if self.rate > 0.0 else -1
        same = direction == self.last_dir
        self.last_dir = direction
        if self.doubled:
            self.doubled = False
        elif self.until_miss > 1:
            self.until_miss -= 1
        elif same:
            self.gap_no = (self.gap_no + 1) % len(self.gaps)
            self.until_miss = self.gaps[self.gap_no]
            self.missed += 1
            self.doubled = True
            self.next_us = t_us

    @staticmethod
    def _phase(p: float, n: int) -> float:
        # after an edge that came early the count is one edge ahead of the disk until
        # the disk reaches it: keep the disk's phase (the next edge comes when it would
        # have; turning back, the early edge is taken back at once)
        return n - 1 if p < n - 1 else (n + 2 if p > n + 2 else p)

    def set_speed(self, t_us: int, wheel_rad_s: float) -> None:
        before = self.rate
        super().set_speed(t_us, wheel_rad_s)
        if self.doubled:
            if before * self.rate > 0.0:
                self.next_us = t_us  # still due now: it turns the same way
            else:  # stopped or turned back at that instant: the edge never comes
                self.doubled = False
                self.missed -= 1

    def truth(self) -> dict:
        return {**super().truth(), f"{self.names[0].split('.')[0]}_missed": self.missed}


class TriggeredSonar(AnalogRangeSonar):
    """An analog sonar that ranges once per trigger (:class:`SonarRx`): one new reading
    the ranging time after the RX edge, then nothing until the next edge."""

    def __init__(self, name: str, model, **kwargs):
        super().__init__(name, model, **kwargs)
        self.period_us = None  # the board sets the pace
        self.next_us = NEVER_US

    def fire(self, t_us: int, plant, out: list) -> None:
        self.sample(t_us, plant, out)
        self.next_us = NEVER_US


class SonarRx(Part):
    """The sonars' shared RX line (a MaxBotix chain's trigger): each rising edge starts a
    ranging of every sonar, read ``ranging_us`` later."""

    FIXED_STATE = ("inputs", "outputs", "sonars")

    def __init__(self, name: str, sonars: list, ranging_us: int):
        if ranging_us <= 0:
            raise ValueError(f"sonar_ranging_us must be > 0, got {ranging_us}")
        self.inputs = {name: "level"}
        self.sonars = sonars
        self.ranging_us = int(ranging_us)
        self.level = 0

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        level = 1 if value else 0
        if level and not self.level:
            for sonar in self.sonars:
                sonar.next_us = t_us + self.ranging_us
        self.level = level
        return False


class Jumper(Part):
    """A jumper from a board input to ground: the pin reads 0 when it is fitted."""

    FIXED_STATE = True

    def __init__(self, name: str, fitted: bool):
        self.outputs = {name: "level"}
        self.level = 0 if fitted else 1

    def initial_outputs(self) -> dict:
        return {next(iter(self.outputs)): self.level}


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
        wheel_slip_sd=0.0,
        slip_period_us=100_000,
        missed_edge_p=0.0,
        sonar_period_us=100_000,
        sonar_noise_m=0.01,
        sonar_rx=False,
        sonar_ranging_us=49_000,
        program_jumper=False,
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
        if not 0.0 <= missed_edge_p < 0.5:
            raise ValueError(f"missed_edge_p must be within 0 .. 0.5, got {missed_edge_p}")
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
        self.wheel_slip_sd = float(wheel_slip_sd)
        self.slip_period_us = int(slip_period_us)
        self.missed_edge_p = float(missed_edge_p)
        self.sonar_period_us = int(sonar_period_us)
        self.sonar_noise_m = float(sonar_noise_m)
        self.sonar_rx = bool(sonar_rx)
        self.sonar_ranging_us = int(sonar_ranging_us)
        self.program_jumper = bool(program_jumper)
        super().__init__()

    def _build(self) -> None:
        self.drive = LabDriveTrain(
            bridges=(TwoPwmBridge("motor_l"), TwoPwmBridge("motor_r")),
            motors=self._wheel_motors(),
            wheel_radius_m=self.wheel_radius_m,
            track_m=self.track_m,
            start_pose=self.start_pose,
            spin_slip=self.spin_slip,
        )
        self.encoders = [self._encoder(side, i) for i, side in enumerate("lr")]
        bumpers = [front_bumper(70.0, self.bumper_bounce_us)] if self.bumper else []
        sonars = [self._sonar(name, mount, phase) for name, mount, phase in self._sonar_mounts()]
        self.parts = [ContactMonitor([(0.0, 0.0, BODY_RADIUS_M)], bumpers), *sonars]
        if self.sonar_rx:
            self.parts.append(SonarRx("sonar.rx", sonars, self.sonar_ranging_us))
        self.parts.append(Jumper("jumper", self.program_jumper))
        if self.wheel_slip_sd > 0:
            self.parts.append(WheelSlip(self.wheel_slip_sd, self.slip_period_us))

    @staticmethod
    def _sonar_mounts() -> list:
        r, diag = BODY_RADIUS_M, BODY_RADIUS_M * math.sqrt(0.5)
        return [
            ("sonar_f.adc", (r, 0.0, 0.0), 20_000),
            ("sonar_l.adc", (0.0, r, math.pi / 2), 70_000),
            ("sonar_lf.adc", (diag, diag, math.pi / 4), 45_000),
        ]

    def _sonar(self, name: str, mount, phase_us: int) -> AnalogRangeSonar:
        model = BeamRangeModel(mount, noise_sd_m=self.sonar_noise_m, min_m=0.15, max_m=5.0)
        kind = TriggeredSonar if self.sonar_rx else AnalogRangeSonar
        adc = {"period_us": self.sonar_period_us, "volts_per_m": MAXBOTIX_V_PER_M, "adc": Adc(12, 3.3)}
        return kind(name, model, phase_us=phase_us, **adc)

    def _encoder(self, side: str, wheel: int) -> QuadratureEncoder:
        names = (f"enc_{side}.a", f"enc_{side}.b")
        enc = {"wheel": wheel, "polarity": self.polarity[wheel]}
        enc.update(lines_per_rev=self.lines_per_rev, gear_ratio=self.gear_ratio)
        if self.missed_edge_p <= 0:
            return QuadratureEncoder(names, **enc)
        gaps = tuple(int(g) + 1 for g in self.rng.geometric(self.missed_edge_p, MISS_GAPS))
        return MissingEdgeEncoder(names, gaps=gaps, **enc)

    def _react(self, t: int) -> bool:
        for part in self.parts:
            if isinstance(part, WheelSlip) and part.changed:
                part.changed = False
                return True
        return False

"""The WEDA B400 pool cleaner in its pool (seeds 000/001).

A tracked machine, 0.90 x 0.48 m (L x W, seed 001), track separation W = 0.4 m, both
tracks at +-0.3 m/s, steered by stopping one track (:mod:`sim_plant.tracks`), reversed
by its own bumper logic at the end walls. Two side-looking echo sounders measure the
distance to the long walls (:mod:`sim_plant.echosounder`); bumpers at both ends.

Signals:

====================  ======  ==============================================================
name                  kind    meaning
====================  ======  ==============================================================
``track_l.stop``      level   1 stops the left track (seed 000: LPT 0x378 bit 1)
``track_r.stop``      level   1 stops the right track (bit 0)
``sonar.select``      level   0: left sonar (sonar 0) on the UART, 1: right (bit 2)
``sonar.uart``        bytes   NMEA ``$SDDPT`` sentences, 4800 baud, one per 500 ms
``bumper_front``      level   0 while the front bumper is pressed (seed 000 "bumper1")
``bumper_rear``       level   0 while the rear bumper is pressed ("bumper2")
====================  ======  ==============================================================

With ``sonar="adc"`` the sonars are two analog outputs instead (``sonar_l.adc``,
``sonar_r.adc``, u16, a new sample every 500 ms, ``ADC_V_PER_M`` volts per metre on a
12-bit 3.3 V ADC, 0 V for no reading) and there is no select line: the harness's
"ADC sonar", with the same transducer model as the NMEA one.

The robot's reference point is the middle of the track axis; x runs along the pool
(25 m), y across it (8 m). Facing +x, the left sonar looks at the wall y = 8 m. The body is
three circles of radius W_body/2 in a row (a capsule 0.90 m long).
"""

from sim_plant.contacts import Bumper, ContactMonitor
from sim_plant.coverage import CoverageGrid, CoverageRecorder
from sim_plant.echosounder import NavmanSideSounder, NmeaDepthSounder
from sim_plant.engine import RobotPlant
from sim_plant.sonars import Adc, AnalogRangeSonar
from sim_plant.tracks import IdealPivotLaw, MeasuredStopLaw, TrackDrive
from sim_plant.world import POOL_LENGTH_M, POOL_WIDTH_M, pool

BODY_LENGTH_M = 0.90
"""Seed 001: "30 x 48 x 90 [cm] (H x W x L)"."""
BODY_WIDTH_M = 0.48
ADC_V_PER_M = 0.33
"""ADC-sonar option: 10 m full scale at 3.3 V (a harness choice; the seed's sonar is serial)."""
BUMPER_HALF_ARC_DEG = 60.0
"""The end bumpers close for walls met within 60 deg of square on (a side wall scraped at a
shallow angle does not reverse the machine)."""


class PoolCleaner(RobotPlant):
    """Parameters: ``steering`` "measured" (eq. 7.1) or "ideal" (pivot); ``sonar`` "nmea"
    or "adc"; ``sonar_options`` go to :class:`~sim_plant.echosounder.NavmanSideSounder`;
    ``bytes_per_change`` to :class:`~sim_plant.echosounder.NmeaDepthSounder`;
    ``sonar_faults``: ``(t0_s, t1_s, kind)`` windows for both sounders, ``"wrong"`` or
    ``"none"`` readings, or ``"silent"`` (no sentence; 0 V on the ADC option)."""

    def __init__(
        self,
        *,
        pool_length_m=POOL_LENGTH_M,
        pool_width_m=POOL_WIDTH_M,
        start_pose=(0.46, 0.5, 0.0),
        speed_m_s=0.3,
        track_m=0.4,
        steering="measured",
        steer_scatter_rel=0.13,
        reversal_pause_ms=1000.0,
        kick_mean_rad=-0.0174,
        kick_sd_rad=0.0348,
        sonar="nmea",
        sonar_period_us=500_000,
        sonar_phase_us=100_000,
        sonar_options=None,
        bytes_per_change=1,
        switch_settle_s=0.0,
        bumper_bounce_us=0,
        coverage_cell_m=0.1,
        sonar_faults=(),
    ):
        if steering not in ("measured", "ideal"):
            raise ValueError(f"steering: 'measured' or 'ideal', got {steering!r}")
        if sonar not in ("nmea", "adc"):
            raise ValueError(f"sonar: 'nmea' or 'adc', got {sonar!r}")
        self.start_pose = tuple(float(v) for v in start_pose)
        self.speed_m_s = float(speed_m_s)
        self.track_m = float(track_m)
        self.steering = steering
        self.steer_scatter_rel = float(steer_scatter_rel)
        self.reversal_pause_ms = float(reversal_pause_ms)
        self.kick_mean_rad = float(kick_mean_rad)
        self.kick_sd_rad = float(kick_sd_rad)
        self.sonar = sonar
        self.sonar_period_us = int(sonar_period_us)
        self.sonar_phase_us = int(sonar_phase_us)
        self.sonar_options = dict(sonar_options or {})
        self.bytes_per_change = int(bytes_per_change)
        self.switch_settle_s = float(switch_settle_s)
        self.bumper_bounce_us = int(bumper_bounce_us)
        self.coverage_cell_m = float(coverage_cell_m)
        self.sonar_faults = tuple((float(t0), float(t1), str(kind)) for t0, t1, kind in sonar_faults)
        self.world = pool(pool_length_m, pool_width_m)
        super().__init__()

    def _build(self) -> None:
        law = MeasuredStopLaw(scatter_rel=self.steer_scatter_rel) if self.steering == "measured" else IdealPivotLaw()
        self.drive = TrackDrive(
            law=law,
            speed_m_s=self.speed_m_s,
            track_m=self.track_m,
            start_pose=self.start_pose,
            reversal_pause_ms=self.reversal_pause_ms,
            kick_mean_rad=self.kick_mean_rad,
            kick_sd_rad=self.kick_sd_rad,
        )
        self.encoders = []
        r = BODY_WIDTH_M / 2
        half = BODY_LENGTH_M / 2 - r
        bounce = {"bounce_us": self.bumper_bounce_us}
        contact = ContactMonitor(
            [(-half, 0.0, r), (0.0, 0.0, r), (half, 0.0, r)],
            [
                Bumper("bumper_front", circles=(2,), center_deg=0.0, half_arc_deg=BUMPER_HALF_ARC_DEG, **bounce),
                Bumper("bumper_rear", circles=(0,), center_deg=180.0, half_arc_deg=BUMPER_HALF_ARC_DEG, **bounce),
            ],
        )
        silent = [(t0, t1) for t0, t1, kind in self.sonar_faults if kind == "silent"]
        faults = [(t0, t1, kind) for t0, t1, kind in self.sonar_faults if kind != "silent"]
        if self.sonar == "adc":  # an analog output cannot fall silent: it reads 0 V
            faults += [(t0, t1, "none") for t0, t1 in silent]
        options = {**self.sonar_options, "faults": [*self.sonar_options.get("faults", ()), *faults]}
        left = NavmanSideSounder((0.0, r, 1.5707963267948966), **options)
        right = NavmanSideSounder((0.0, -r, -1.5707963267948966), **options)
        if self.sonar == "nmea":
            sonars = [
                NmeaDepthSounder(
                    "sonar.uart",
                    [left, right],
                    select="sonar.select",
                    period_us=self.sonar_period_us,
                    phase_us=self.sonar_phase_us,
                    bytes_per_change=self.bytes_per_change,
                    switch_settle_s=self.switch_settle_s,
                    silent=silent,
                )
            ]
        else:
            adc = {"period_us": self.sonar_period_us, "phase_us": self.sonar_phase_us, "volts_per_m": ADC_V_PER_M}
            sonars = [
                AnalogRangeSonar("sonar_l.adc", left, adc=Adc(12, 3.3), **adc),
                AnalogRangeSonar("sonar_r.adc", right, adc=Adc(12, 3.3), **adc),
            ]
        self.parts = [contact, *sonars, CoverageRecorder(CoverageGrid(self.world, self.coverage_cell_m, r))]

    def _react(self, t: int) -> bool:
        """The machine's own bumper logic: the leading bumper reverses the tracks."""
        contact = self.parts[0]
        front, rear = contact.bumpers
        drive = self.drive
        if front.pressed and drive.direction > 0:
            return drive.start_reversal(t, -1)
        if rear.pressed and drive.direction < 0:
            return drive.start_reversal(t, 1)
        return False

    def carry_to(self, pose) -> None:
        """Someone lifts the machine and sets it down at ``pose`` (x, y, theta) now: the
        thesis's operator puts it on the pool edge after the start-up measurement (seed
        000 §6.3). For test scenarios; the firmware is not told. The coverage path jumps
        (no swath is drawn between the two places)."""
        t = self._t_us
        body = self.drive.body
        body.constraints = ()
        body.rebase(t, tuple(float(v) for v in pose))
        self.part(CoverageRecorder).jump(t, self)
        self.parts[0].check_us = t  # what it touches where it was set down, at once
        self._motion_changed(t)

    def truth(self) -> dict:
        truth = super().truth()
        truth["theta_deg"] = truth["theta_rad"] * 57.29577951308232
        return truth

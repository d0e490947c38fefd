"""The pool cleaner's side-looking echo sounder (seeds 000/001): a NAVMAN 100 depth
sounder laid on its side, talking NMEA 0183 over RS-232.

:class:`NavmanSideSounder` is the transducer model, from the thesis (seed 000):

=============================  ==========  =================================================
attribute                      default     source
=============================  ==========  =================================================
``beam_half_angle_deg``        4.5         "opening angle of 9 degrees" (§3.3, App. C): the
                                           echo comes from the nearest point of the wall the
                                           axis points at that lies in the beam
``max_incidence_deg``          15          "for values of the angle over 15 degrees, it
                                           becomes arduous to use the sensor" (§7.1): no
                                           reading beyond
``min_range_m``                0.8         "for distances shorter than 0.8 meters, the sonar
                                           was effectively not able to give measurements at
                                           all" (§7.1)
``dropout_table``              Table 7.1   no-reading rate 5/8, 4/8, 1/8, 2/8, 0, 0 at 0.8,
                                           0.9, 1.0, 1.1, 1.2, 1.3 m, linear in between
``fine_step_m``                0.1         "precision of one decimeter between 2-20 meters"
``coarse_step_m``              1.0         "and 1 meter between 20-150 meters" (seed 001)
``coarse_from_m``              20
``max_range_m``                150         "Displays depth to 150 meters" (App. C)
``noise_sd_m``                 0.1         scatter of Table 7.1 at 1.2-1.3 m (sd 0.08-0.1
                                           m); the design model's "variance .3" is
                                           available by passing 0.3 or 0.548
``end_zone_m``                 1.5         near an end wall "the measure is corrupted"
``end_corrupt_p``              0.8         (§5.4, Fig. 5.9): probability of a corrupted
                                           reading, at the wall, falling linearly to 0 at
                                           ``end_zone_m`` (zone and rate not in the seed)
``warmup_s``                   0           "At the start of a session the sonar generates
``warmup_noise_sd_m``          0.3         noisy data" (seed 001 §5): extra noise until then
``faults``                     ()          fault injection: ``(t0_s, t1_s, kind)`` windows;
                                           ``"wrong"`` readings drawn uniformly from
``wrong_range_m``              0.8, 15     (seed 000 §3.4.4: "other instruments used in
                                           the nearby ... any filtering techniques was
                                           useless"; §7.3.3 "wrong sonar measures"),
                                           ``"none"`` no reading at all (an empty field)
=============================  ==========  =================================================

A corrupted reading is, with equal odds, the end wall heard through a side lobe (its
distance along the track) or the echo of the corner (the hypotenuse of the side and end
distances): "readings coming from the close by wall and the far away parallel wall"
(seed 001).

:class:`NmeaDepthSounder` is the output: one ``$SDDPT`` sentence per ``period_us``
(500 ms, seed 000 §4.3 "every 500 ms") on a UART at 4800 baud, 8N1 (seed 000
``COMPARMS 0xc3``): 10 bits per byte, 2083 us per byte, about 40 ms per sentence. A
missing reading sends an empty depth field. With two transducers, a ``select`` input
picks the one on the line (seed 000 ``Set_Sonar``: parallel-port bit 2; 0 = sonar 0,
the left one), taking effect at the next sentence.

How bytes become :class:`~sim_plant.plant.Change` s (``bytes_per_change``): 1 (default)
gives one Change per byte, at the time its stop bit ends; N groups N bytes into one
Change at the end of the last of them; 0 sends the whole sentence as one Change when its
last byte ends.
"""

import math

from sim_plant.engine import Part
from sim_plant.plant import NEVER_US, Change
from sim_plant.sonars import sensor_pose

DROPOUT_TABLE_7_1 = ((0.8, 5 / 8), (0.9, 4 / 8), (1.0, 1 / 8), (1.1, 2 / 8), (1.2, 0.0), (1.3, 0.0))
"""Seed 000, Table 7.1: share of "no reading" entries among 8 trials at each real distance."""


def nmea_checksum(body: str) -> int:
    """XOR of the characters between '$' and '*'."""
    cs = 0
    for ch in body.encode("ascii"):
        cs ^= ch
    return cs


def dpt_sentence(depth_m: float | None, offset_m: float = 0.0, talker: str = "SD") -> bytes:
    """``$SDDPT,<depth>,<offset>*hh\\r\\n``; an empty depth field when there is no reading."""
    depth = "" if depth_m is None else f"{depth_m:.1f}"
    body = f"{talker}DPT,{depth},{offset_m:.1f}"
    return f"${body}*{nmea_checksum(body):02X}\r\n".encode("ascii")


def fault_windows(faults, kinds) -> tuple:
    """``(t0_s, t1_s, kind)`` windows as ``(t0_us, t1_us, kind)``, checked."""
    out = []
    for t0_s, t1_s, kind in faults:
        if kind not in kinds:
            raise ValueError(f"faults: kind {kind!r} is not one of {', '.join(kinds)}")
        if not t0_s < t1_s:
            raise ValueError(f"faults: window ({t0_s}, {t1_s}) s must start before it ends")
        out.append((int(t0_s * 1e6), int(t1_s * 1e6), kind))
    return tuple(out)


def active_fault(windows, t_us: int) -> str | None:
    for t0, t1, kind in windows:
        if t0 <= t_us < t1:
            return kind
    return None


def interpolate(table, x: float) -> float:
    if x <= table[0][0]:
        return table[0][1]
    for (x0, y0), (x1, y1) in zip(table, table[1:]):
        if x <= x1:
            return y0 + (y1 - y0) * (x - x0) / (x1 - x0)
    return table[-1][1]


class NavmanSideSounder:
    """Transducer model of the NAVMAN 100 used sideways (see the module table)."""

    def __init__(
        self,
        mount,
        *,
        beam_half_angle_deg: float = 4.5,
        max_incidence_deg: float = 15.0,
        min_range_m: float = 0.8,
        dropout_table=DROPOUT_TABLE_7_1,
        fine_step_m: float = 0.1,
        coarse_step_m: float = 1.0,
        coarse_from_m: float = 20.0,
        max_range_m: float = 150.0,
        noise_sd_m: float = 0.1,
        end_zone_m: float = 1.5,
        end_corrupt_p: float = 0.8,
        warmup_s: float = 0.0,
        warmup_noise_sd_m: float = 0.3,
        faults=(),
        wrong_range_m=(0.8, 15.0),
    ):
        self.mount = tuple(float(v) for v in mount)
        self.beam_half_angle_rad = math.radians(beam_half_angle_deg)
        self.max_incidence_rad = math.radians(max_incidence_deg)
        self.min_range_m = float(min_range_m)
        self.dropout_table = tuple(dropout_table)
        self.fine_step_m = float(fine_step_m)
        self.coarse_step_m = float(coarse_step_m)
        self.coarse_from_m = float(coarse_from_m)
        self.max_range_m = float(max_range_m)
        self.max_m = self.max_range_m
        self.noise_sd_m = float(noise_sd_m)
        self.end_zone_m = float(end_zone_m)
        self.end_corrupt_p = float(end_corrupt_p)
        self.warmup_us = int(warmup_s * 1e6)
        self.faults = fault_windows(faults, ("wrong", "none"))
        self.wrong_range_m = (float(wrong_range_m[0]), float(wrong_range_m[1]))
        self.warmup_noise_sd_m = float(warmup_noise_sd_m)

    def dropout_p(self, range_m: float) -> float:
        """Probability of no reading at a true range (Table 7.1; 1 below ``min_range_m``)."""
        if range_m < self.min_range_m - 1e-9:
            return 1.0
        return interpolate(self.dropout_table, range_m)

    def quantise(self, range_m: float) -> float:
        step = self.coarse_step_m if range_m >= self.coarse_from_m else self.fine_step_m
        return round(round(range_m / step) * step, 6)

    def geometry(self, pose, world) -> tuple[float, float, float]:
        """(range along the axis, incidence rad, nearest echo in the beam) from the pose.

        The echo comes from the wall the axis points at, from its point nearest to the
        sensor inside the beam: the foot of the perpendicular while the incidence is
        within the beam's half-angle, the beam's edge beyond."""
        sx, sy, axis = sensor_pose(pose, self.mount)
        along_m, incidence = world.ray(sx, sy, axis, self.max_range_m)
        if not math.isfinite(along_m):
            return along_m, incidence, along_m
        off_beam = max(0.0, incidence - self.beam_half_angle_rad)
        return along_m, incidence, along_m * math.cos(incidence) / math.cos(off_beam)

    def measure(self, t_us: int, pose, world, rng, extra_sd_m: float = 0.0) -> tuple[float, float | None]:
        fault = active_fault(self.faults, t_us)
        if fault == "none":
            return self.geometry(pose, world)[0], None
        if fault == "wrong":  # draws only inside the window: runs without faults are unchanged
            lo, hi = self.wrong_range_m
            return self.geometry(pose, world)[0], self.quantise(lo + (hi - lo) * float(rng.random()))
        along_m, incidence, beam_m = self.geometry(pose, world)
        if not math.isfinite(beam_m) or not incidence <= self.max_incidence_rad:
            return along_m, None
        u_drop, u_corrupt, u_kind, z = rng.random(), rng.random(), rng.random(), rng.standard_normal()
        if u_drop < self.dropout_p(beam_m):
            return along_m, None
        sx, sy, _ = sensor_pose(pose, self.mount)
        end_m = min(world.ray(sx, sy, pose[2])[0], world.ray(sx, sy, pose[2] + math.pi)[0])
        if end_m < self.end_zone_m and u_corrupt < self.end_corrupt_p * (1.0 - end_m / self.end_zone_m):
            reported = end_m if u_kind < 0.5 else math.hypot(end_m, beam_m)
        else:
            reported = beam_m
        sd = self.noise_sd_m
        if t_us < self.warmup_us:
            sd = math.hypot(sd, self.warmup_noise_sd_m)
        if extra_sd_m:
            sd = math.hypot(sd, extra_sd_m)
        reported += sd * z
        if reported < self.fine_step_m / 2:
            return along_m, None
        return along_m, self.quantise(reported)


class NmeaDepthSounder(Part):
    """NMEA 0183 ``$SDDPT`` sentences on a UART, from one or more transducers.

    ``switch_settle_s``/``settle_noise_sd_m``: after the select line changes, readings
    carry extra noise for that long ("measures are not always reliable at the beginning
    of the working section of the sonar", seed 000 §7.3.3; 0 = off).
    ``silent``: ``(t0_s, t1_s)`` windows in which no sentence is sent (a sounder or cable
    dropout; fault injection).
    """

    def __init__(
        self,
        name: str,
        transducers,
        *,
        select: str | None = None,
        period_us: int = 500_000,
        phase_us: int = 100_000,
        baud: int = 4800,
        bits_per_byte: int = 10,
        bytes_per_change: int = 1,
        talker: str = "SD",
        switch_settle_s: float = 0.0,
        settle_noise_sd_m: float = 0.3,
        silent=(),
    ):
        self.name = name
        self.transducers = list(transducers)
        if len(self.transducers) > 1 and not select:
            raise ValueError(f"{name}: {len(self.transducers)} transducers need a select input")
        self.select_name = select
        self.period_us = int(period_us)
        self.baud = int(baud)
        self.bits_per_byte = int(bits_per_byte)
        self.bytes_per_change = int(bytes_per_change)
        self.talker = talker
        self.switch_settle_us = int(switch_settle_s * 1e6)
        self.settle_noise_sd_m = float(settle_noise_sd_m)
        self.silent = fault_windows([(t0, t1, "silent") for t0, t1 in silent], ("silent",))
        self.silenced = 0
        self.inputs = {select: "level"} if select else {}
        self.outputs = {name: "bytes"}
        self.selected = 0
        self.switched_us = -(1 << 62)
        self.sample_us = int(phase_us)
        self.queue: list[tuple[int, bytes]] = []  # (time due, bytes) still on the wire
        self.next_us = self.sample_us
        self.sentences = 0
        self.last_sentence = b""
        self.true_m = [math.inf] * len(self.transducers)
        self.reading_m: float | None = None

    def initial_outputs(self) -> dict:
        return {self.name: b""}

    def set_input(self, name: str, value, t_us: int, plant) -> bool:
        chosen = 1 if int(value) else 0
        if chosen >= len(self.transducers):
            raise ValueError(f"{name}={value}: only {len(self.transducers)} transducer(s)")
        if chosen != self.selected:
            self.selected = chosen
            self.switched_us = t_us
        return False

    def fire(self, t_us: int, plant, out: list) -> None:
        while self.queue and self.queue[0][0] <= t_us:
            _, chunk = self.queue.pop(0)
            out.append(Change(t_us, self.name, chunk))
        if self.sample_us <= t_us:
            self._sample(t_us, plant)
        self.next_us = min(self.sample_us, self.queue[0][0] if self.queue else NEVER_US)

    def _sample(self, t_us: int, plant) -> None:
        if active_fault(self.silent, t_us):
            self.silenced += 1
            self.sample_us = t_us + self.period_us
            return
        pose = plant.pose_at(t_us)
        extra = self.settle_noise_sd_m if t_us - self.switched_us < self.switch_settle_us else 0.0
        for i, tr in enumerate(self.transducers):
            if i != self.selected:
                self.true_m[i] = tr.geometry(pose, plant.world)[0]
        self.true_m[self.selected], self.reading_m = self.transducers[self.selected].measure(
            t_us, pose, plant.world, plant.rng, extra
        )
        sentence = dpt_sentence(self.reading_m, talker=self.talker)
        self.last_sentence = sentence
        self.sentences += 1
        group = self.bytes_per_change if self.bytes_per_change > 0 else len(sentence)
        for start in range(0, len(sentence), group):
            end = min(start + group, len(sentence))
            wire_us = -(-end * self.bits_per_byte * 1_000_000 // self.baud)  # end of the stop bit, rounded up
            self.queue.append((t_us + wire_us, sentence[start:end]))
        self.sample_us = t_us + self.period_us

    def truth(self, t_us: int, plant) -> dict:
        names = _truth_names(self.name, len(self.transducers))
        truth = dict(zip(names[0], self.true_m))
        truth[names[1]] = self.selected
        truth[names[2]] = self.reading_m
        truth[names[3]] = self.last_sentence
        return truth


_TRUTH_NAMES: dict = {}


def _truth_names(name: str, transducers: int) -> tuple:
    """A sounder's truth columns (made once: ground truth asks every 50 ms): sonar.uart's
    sonar_l_range_m, sonar_r_range_m (two transducers; else sonar_0_range_m, ...), then
    sonar_selected, sonar_reading_m, sonar_sentence."""
    names = _TRUTH_NAMES.get((name, transducers))
    if names is None:
        key = name.split(".")[0]
        sides = ("l", "r") if transducers == 2 else tuple(str(i) for i in range(transducers))
        ranges = tuple(f"{key}_{s}_range_m" for s in sides)
        names = _TRUTH_NAMES[(name, transducers)] = (ranges, f"{key}_selected", f"{key}_reading_m", f"{key}_sentence")
    return names

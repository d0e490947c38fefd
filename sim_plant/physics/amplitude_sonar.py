"""Seed 002's amplitude sonars: a continuously driven 40 kHz transmitter, a receiver whose
echo amplitude is peak-detected into a DC level and read by an 8-bit ADC. Not time of
flight: the closer the wall, the bigger the reading (App. C.2, §3.3.4).

==========================  ==========  ===================================================
attribute                   default     source / meaning
==========================  ==========  ===================================================
``full_scale_v``            5.0         peak-detector output at the closest range (5 V
                                        logic, App. C)
``min_range_m``             0.030       "The minimum range of the sonars was 30mm ± 2mm"
                                        (App. C.4.1): nearer walls read full scale
``max_range_m``             1.0         no return beyond (the seed gives none; short)
``exponent``                1.0         "the ADC results were inversely proportional to the
                                        range": v = full_scale * (min_range / r) ** exponent
``peak_incidence_deg``      (5, 8)      "between 5° and 8° the signal was at its maximum"
``normal_gain``             0.9         relative return square on (below the 5-8° peak)
``absent_incidence_deg``    35          "At about 35° the return signal can be considered
                                        as absent" (App. C.4.2); a raised-cosine fall-off
                                        from 8° to 35°
``discharge_tau_ms``        150         peak detector RC: "the finite discharging time
                                        created the slope seen" at an opening (App. C.4.3);
                                        the value is not in the seed
``noise_v``                 0.01        electronic noise, half an 8-bit step ("noise was
                                        larger than 4.8 mV", App. C.4.1)
``corner_spike_p``          0.01        chance per update that a corner in the beam echoes
                                        back as a strong near return ("reflection caused by
                                        the corner as the robot turned", §5.6)
``update_us``               25_000      the analog level is re-evaluated this often
``adc``                     8-bit, 5 V  "the 8 bit ADC was implemented" (App. C.4.1)
==========================  ==========  ===================================================

Each channel has a ``gain`` (``small differences in components``: every channel was
calibrated). The output is a continuous voltage, not a sampled one: a Change is reported
only when the ADC count changes, and the board reads the latest value whenever it likes.
"""

import math

from sim_plant.engine import Part
from sim_plant.plant import Change
from sim_plant.sonars import Adc

RANDOM_BLOCK = 16
"""Updates' worth of random numbers drawn from the generator at a time."""


class AmplitudeChannel:
    """One transmitter/receiver pair: output name, mount ``(x_m, y_m, angle_rad)`` in the
    body frame, and its gain."""

    def __init__(self, name: str, mount, gain: float = 1.0):
        self.name = name
        self.mount = tuple(float(v) for v in mount)
        self.cos_mount, self.sin_mount = math.cos(self.mount[2]), math.sin(self.mount[2])
        self.gain = float(gain)
        self.held_v = 0.0
        self.target_v = 0.0
        self.value = 0
        self.range_m = math.inf


class AmplitudeSonarArray(Part):
    """All the amplitude sonars of a robot, updated together (see the module table)."""

    def __init__(
        self,
        channels,
        *,
        full_scale_v: float = 5.0,
        min_range_m: float = 0.030,
        max_range_m: float = 1.0,
        exponent: float = 1.0,
        peak_incidence_deg=(5.0, 8.0),
        normal_gain: float = 0.9,
        absent_incidence_deg: float = 35.0,
        discharge_tau_ms: float = 150.0,
        noise_v: float = 0.01,
        corner_spike_p: float = 0.01,
        update_us: int = 25_000,
        adc: Adc | None = None,
    ):
        self.channels = list(channels)
        self.full_scale_v = float(full_scale_v)
        self.min_range_m = float(min_range_m)
        self.max_range_m = float(max_range_m)
        self.exponent = float(exponent)
        self.peak_lo_rad, self.peak_hi_rad = (math.radians(a) for a in peak_incidence_deg)
        self.normal_gain = float(normal_gain)
        self.absent_rad = math.radians(absent_incidence_deg)
        self.decay = math.exp(-update_us / (discharge_tau_ms * 1000.0)) if discharge_tau_ms > 0 else 0.0
        self.noise_v = float(noise_v)
        self.corner_spike_p = float(corner_spike_p)
        self.update_us = int(update_us)
        self.adc = adc or Adc(8, 5.0)
        self._u16_table = tuple(self.adc.to_u16(c) for c in range(self.adc.max_counts + 1))
        self.outputs = {ch.name: "u16" for ch in self.channels}
        self.next_us = self.update_us
        self.spikes = 0
        self.draws: list[tuple[float, float]] = []

    def initial_outputs(self) -> dict:
        return {ch.name: ch.value for ch in self.channels}

    def incidence_gain(self, incidence_rad: float) -> float:
        """Relative echo amplitude against the angle between the axis and the wall normal."""
        a = abs(incidence_rad)
        if a >= self.absent_rad:
            return 0.0
        if a <= self.peak_lo_rad:
            return self.normal_gain + (1.0 - self.normal_gain) * a / self.peak_lo_rad
        if a <= self.peak_hi_rad:
            return 1.0
        return 0.5 * (1.0 + math.cos(math.pi * (a - self.peak_hi_rad) / (self.absent_rad - self.peak_hi_rad)))

    def range_volts(self, range_m: float) -> float:
        if range_m > self.max_range_m:
            return 0.0
        return self.full_scale_v * (self.min_range_m / max(range_m, self.min_range_m)) ** self.exponent

    def fire(self, t_us: int, plant, out: list) -> None:
        x, y, th = plant.pose_at(t_us)
        walls = plant.world.near(x, y, self.max_range_m + 0.3).walls
        if not self.draws:  # random numbers in blocks: (spike uniform, noise normal) per channel
            n = len(self.channels) * RANDOM_BLOCK
            self.draws = list(zip(plant.rng.random(n).tolist(), plant.rng.standard_normal(n).tolist()))
        co, si = math.cos(th), math.sin(th)
        cos_max, max_range = math.cos(self.absent_rad), self.max_range_m
        u16_table, volts_per_count, top = self._u16_table, self.adc.vref_v / self.adc.max_counts, self.adc.max_counts
        for ch in self.channels:
            spike_u, z = self.draws.pop()
            mx, my, ma = ch.mount
            sx, sy = x + co * mx - si * my, y + si * mx + co * my
            cx, cy = co * ch.cos_mount - si * ch.sin_mount, si * ch.cos_mount + co * ch.sin_mount
            # the walls that echo straight back (World.specular, inlined: it runs 120 times a second)
            target, nearest = 0.0, math.inf
            for ax, ay, ux, uy, length, _bx, _by, nx, ny, c in walls:
                sd = nx * sx + ny * sy - c
                cos_inc = -(nx * cx + ny * cy) if sd > 0.0 else nx * cx + ny * cy
                if cos_inc < cos_max:
                    continue
                d = sd if sd > 0.0 else -sd
                if d > max_range or d <= 1e-12:
                    continue
                s_on = ((sx - ax) * ux + (sy - ay) * uy) / (length * length)
                if s_on < 0.0 or s_on > 1.0:
                    continue
                v = self.range_volts(d) * self.incidence_gain(math.acos(min(cos_inc, 1.0)))
                if v > target:
                    target = v
                if d < nearest:
                    nearest = d
            if spike_u < self.corner_spike_p:
                corners = plant.world.near(x, y, max_range + 0.3).vertices_in_cone(
                    sx, sy, th + ma, self.absent_rad, max_range
                )
                if corners:
                    self.spikes += 1
                    target = max(target, self.range_volts(min(corners)))
            target *= ch.gain
            ch.target_v = target
            ch.range_m = nearest
            held = ch.held_v * self.decay
            if target > held:
                held = target
            ch.held_v = held
            counts = round((held + self.noise_v * z) / volts_per_count)
            value = u16_table[0 if counts < 0 else (top if counts > top else counts)]
            if value != ch.value:
                ch.value = value
                out.append(Change(t_us, ch.name, value))
        self.next_us = t_us + self.update_us

    def truth(self, t_us: int, plant) -> dict:
        return {f"{ch.name.split('.')[0]}_range_m": ch.range_m for ch in self.channels}

"""Reflectance sensors looking at the floor, over a tape line: the engine part behind the
catalogue's ``line_sensor``."""

import math

from sim_plant.engine import Part
from sim_plant.plant import NEVER_US, Change


class FloorSensors(Part):
    """Reflectance sensors looking at the floor (TCRT5000 or QTR style, on an ADC): each
    reads ``tape_u16`` over the tape (dark: little light comes back, the output is high)
    and ``floor_u16`` elsewhere. The floor is checked every ``period_us``; a reading is a
    change only when it flips (a continuous voltage, not a sampled one)."""

    FIXED_STATE = ("offsets", "tape", "inputs", "outputs", "names")

    def __init__(self, offsets, tape, *, width_m, tape_u16, floor_u16, period_us):
        if period_us <= 0:
            raise ValueError(f"floor_period_us: expected > 0, got {period_us}")
        if len(tape) == 1 or any(len(p) != 2 for p in tape):
            raise ValueError("tape: expected a path of [x, y] points (two or more)")
        self.offsets = [tuple(float(v) for v in o) for o in offsets]
        self.tape = [tuple(float(v) for v in p) for p in tape]
        self.half_width_m = float(width_m) / 2
        self.levels = (int(floor_u16), int(tape_u16))
        self.period_us = int(period_us)
        self.names = [f"floor_{i}.adc" for i in range(len(self.offsets))]
        self.outputs = dict.fromkeys(self.names, "u16")
        self.values = [self.levels[0]] * len(self.offsets)
        self.next_us = NEVER_US

    def start(self, t_us: int, plant) -> None:
        self.values = self._read(plant.pose_at(t_us))
        self.next_us = t_us + self.period_us

    def initial_outputs(self) -> dict:
        return dict(zip(self.names, self.values))

    def fire(self, t_us: int, plant, out: list) -> None:
        for name, old, new in zip(self.names, self.values, self._read(plant.pose_at(t_us))):
            if new != old:
                out.append(Change(t_us, name, new))
        self.values = self._read(plant.pose_at(t_us))
        self.next_us = t_us + self.period_us

    def _read(self, pose) -> list[int]:
        x, y, th = pose
        c, s = math.cos(th), math.sin(th)
        return [self.levels[self._on_tape(x + dx * c - dy * s, y + dx * s + dy * c)] for dx, dy in self.offsets]

    def _on_tape(self, px: float, py: float) -> bool:
        for (ax, ay), (bx, by) in zip(self.tape, self.tape[1:]):
            ux, uy = bx - ax, by - ay
            k = max(0.0, min(1.0, ((px - ax) * ux + (py - ay) * uy) / (ux * ux + uy * uy or 1.0)))
            if math.hypot(px - ax - k * ux, py - ay - k * uy) <= self.half_width_m:
                return True
        return False

"""The pieces of a signals-over-time figure, as plain data: a panel is a titled axis of
lines, with reference levels and notes that explain what a reader would otherwise take
for a fault (a flat input, a discarded range)."""

from dataclasses import dataclass, field

import numpy as np

US_PER_S = 1e6


@dataclass
class Line:
    label: str
    t_s: np.ndarray
    values: np.ndarray
    style: str = "line"  # "line", "step" (held until the next value), "points", "dashed" (a step)
    # or "colours" (values are 0xRRGGBB colours: a bar of each colour until the next, a row a line)


@dataclass
class Panel:
    title: str
    ylabel: str
    lines: list[Line] = field(default_factory=list)
    levels: list[tuple[float, str]] = field(default_factory=list)  # (value, label): a horizontal reference
    notes: list[str] = field(default_factory=list)  # written in the panel, under the lines

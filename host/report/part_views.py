"""The signals plot of a robot built from a body and parts: every part's declared views
(``VIEWS`` in :mod:`sim_plant.catalogue`), from the trace header's ``parts`` (the body,
each part's kind, name, mount and options) and the recorded signals and truth.

One panel per kind of view, each part's lines in it: ``range`` (the range the firmware
read, through the part's own law, against the true range), ``command`` (a motor's signed
duty, as its bridge's pins make it), ``count`` (an encoder's edges, decoded from the
recorded channels, against the disk's true count), ``contacts``, ``level``, ``voltage``,
``angle``, ``rate`` (a gyro's), ``heading`` (a compass's) and ``strip`` (a LED strip's
colours, a row a LED); then the body's speed, true and as the encoders' edges say it. A
part draws what it declares: nothing here names a robot.
"""

import numpy as np

from host.report.panels import US_PER_S, Line, Panel
from sim_plant import catalogue
from sim_plant.catalogue.base import PartsError

PLOTS = {
    "range": ("Rangers: the range the firmware read against the true range", "range (m)"),
    "command": ("Motors: the signed command the bridge's pins make", "duty (-1 .. 1)"),
    "angle": ("Servos: the angle the pulse asks for against the true angle", "degrees"),
    "rate": ("Gyros: the turn rate the chip reads against the body's true rate", "degrees/s"),
    "heading": ("Compasses: the heading the chip's field gives against the body's", "degrees"),
    "count": ("Encoders: edges on the recorded channels against the disk's true count", "edges"),
    "contacts": ("Bumpers: the switch's level against its true state", "level"),
    "voltage": ("Batteries: the voltage the ADC reading says against the battery's", "volts"),
    "level": ("Levels: buttons, probes, line sensors (a row each, low to high)", "row + level"),
    "strip": ("LED strips: each LED's colour over time (a row each, LED 0 at the bottom)", "LED"),
}
SPEED_WINDOW_US = 100_000
LEVEL_ROW = 1.0  # a level panel's signals, one above the other


class Recorded:
    """The trace's events by signal, grouped once: (t_us, values) arrays of each."""

    def __init__(self, trace):
        grouped: dict[str, list] = {}
        for t, name, value in trace.events:
            if isinstance(value, (int, float)):
                grouped.setdefault(name, []).append((t, value))
        self.series = {
            n: (np.asarray([p[0] for p in v], np.int64), np.asarray([p[1] for p in v], float))
            for n, v in grouped.items()
        }
        self.initial = trace.header.get("initial", {})
        wired = trace.header.get("wired")
        self.wired = None if wired is None else frozenset(wired)
        """A board of a set: the signals its pins are wired to (the others are other boards')."""

    def own(self, part) -> dict:
        """``part.signals()`` that this trace's board is wired to (all of them for one board)."""
        present = part.signals()
        return present if self.wired is None else {n: v for n, v in present.items() if n in self.wired}

    def get(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        return self.series.get(name, (np.zeros(0, np.int64), np.zeros(0)))


def part_panels(trace) -> list[Panel] | None:
    """The panels of a parts plant's trace; None for a trace of another plant."""
    described = trace.header.get("parts")
    if not described:
        return None
    recorded = Recorded(trace)
    panels: dict[str, Panel] = {}
    parts = []
    for entry in described.get("parts", []):
        cls = _part_class(entry["kind"], described.get("catalogue", ()))
        if cls is None:
            continue  # a part this checkout's catalogue no longer has: nothing to draw it with
        part = cls(entry["name"], entry.get("mount", {}), entry["options"])
        parts.append(part)
        for view in cls.VIEWS:
            panel = panels.setdefault(view.plot, Panel(*PLOTS.get(view.plot, (view.plot, ""))))
            DRAW.get(view.plot, draw_level)(panel, part, view, trace, recorded)
    ordered = [panels[k] for k in PLOTS if k in panels] + [p for k, p in panels.items() if k not in PLOTS]
    speed = speed_panel(trace, recorded, parts, described.get("body_options", {}))
    return ordered + ([speed] if speed.lines else [])


def _part_class(kind: str, sources) -> type | None:
    """The class of a part a trace header names: ours, or a user's (its rig file's catalogue
    sources, as the header keeps them: absolute folders, module names); None when gone."""
    try:
        for source in sources:
            catalogue.add(source)
        return catalogue.resolve("parts", kind)
    except PartsError:  # (a user's folder moved since the run: its parts are not drawn)
        return None


def _signals(part, view, recorded: Recorded) -> list[tuple[str, str, str]]:
    """(full name, suffix, kind) of the view's signals present on this part (and this board)."""
    present = recorded.own(part)
    wanted = [f"{part.name}.{s}" for s in view.signals if s != "<i>"]
    if "<i>" in view.signals:
        wanted += [n for n in present if n not in wanted]
    return [(n, n.split(".", 1)[1], present[n][1]) for n in wanted if n in present]


def _truth_lines(panel: Panel, part, view, trace, style: str = "line") -> None:
    tr = trace.truth
    for key in view.truth:
        column = key.format(name=part.name)
        if column in tr and len(tr["t_us"]):
            values = np.asarray(tr[column], dtype=float)
            panel.lines.append(Line(f"{column} (truth)", tr["t_us"] / US_PER_S, values, style))


def _reading(part, suffix: str, values: np.ndarray) -> np.ndarray:
    law = getattr(part, "reading", None)
    return law(suffix, values) if law else values


def high_pulses(t_us: np.ndarray, level: np.ndarray, initial=0) -> tuple[np.ndarray, np.ndarray]:
    """(end time, width in us) of every high pulse of a level series."""
    ends, widths, rose, last = [], [], None, initial
    for t, v in zip(t_us, level):
        if v and not last:
            rose = t
        elif last and not v and rose is not None:
            ends.append(t)
            widths.append(t - rose)
        last = v
    return np.asarray(ends, np.int64), np.asarray(widths, float)


def draw_range(panel: Panel, part, view, trace, recorded: Recorded) -> None:
    for name, suffix, kind in _signals(part, view, recorded):
        t, v = recorded.get(name)
        if kind == "level":
            t, v = high_pulses(t, v, recorded.initial.get(name, 0))
        metres = _reading(part, suffix, v)
        panel.lines.append(Line(f"{part.name}: read by the firmware", t / US_PER_S, metres, "points"))
        lost = int(np.isnan(metres).sum())
        if lost:
            panel.notes.append(f"{part.name}: {lost} of {len(metres)} readings found nothing in range (not drawn)")
    _truth_lines(panel, part, view, trace)


def signed_command(recorded: Recorded, part) -> tuple[np.ndarray, np.ndarray]:
    """A motor's signed duty as its bridge's pins make it, a value at each pin change:
    IN1/IN2 levels with a PWM (TB6612, L298N), two PWMs (DRV8833: IN1 - IN2), or DIR with
    a PWM (DIR high: forwards)."""
    kinds = {n.split(".", 1)[1]: k for n, (_d, k) in recorded.own(part).items()}
    level = dict.fromkeys(kinds, 0)
    changes = sorted((t, suffix, v) for suffix in kinds for t, v in zip(*recorded.get(f"{part.name}.{suffix}")))
    t_out, v_out = [], []
    for t, suffix, value in changes:
        level[suffix] = value
        if "pwm" not in kinds:  # two PWMs
            duty = (level["in1"] - level["in2"]) / 65535
        elif "dir" in kinds:
            duty = (1 if level["dir"] else -1) * level["pwm"] / 65535
        else:
            duty = (int(level["in1"] != 0) - int(level["in2"] != 0)) * level["pwm"] / 65535
        t_out.append(t / US_PER_S)
        v_out.append(duty)
    return np.asarray(t_out), np.asarray(v_out)


def draw_command(panel: Panel, part, view, trace, recorded: Recorded) -> None:
    if not recorded.own(part):
        return  # (another board's motor)
    t_s, duty = signed_command(recorded, part)
    panel.lines.append(Line(f"{part.name} ({part.options.get('bridge', '')})", t_s, duty, "step"))


def decoded_count(recorded: Recorded, part) -> tuple[np.ndarray, np.ndarray]:
    """An encoder's count from its recorded channels: A/B decoded x4 (A leading B counts
    up), or every edge of a single channel (no direction)."""
    names = list(recorded.own(part))
    if len(names) == 1:
        t, _v = recorded.get(names[0])
        return t, np.arange(1, len(t) + 1, dtype=float)
    a, b = names
    levels = {a: recorded.initial.get(a, 0), b: recorded.initial.get(b, 0)}
    changes = sorted((t, n, v) for n in names for t, v in zip(*recorded.get(n)))
    t_out, counts, n = [], [], 0
    for t, name, value in changes:
        if value == levels[name]:
            continue
        levels[name] = value
        same = levels[a] == levels[b]
        n += (-1 if same else 1) if name == a else (1 if same else -1)
        t_out.append(t)
        counts.append(n)
    return np.asarray(t_out, np.int64), np.asarray(counts, float)


def draw_count(panel: Panel, part, view, trace, recorded: Recorded) -> None:
    if recorded.own(part):  # (another board's encoder: its truth alone)
        t, n = decoded_count(recorded, part)
        what = "x4 from A/B" if len(recorded.own(part)) == 2 else "edges, no direction"
        panel.lines.append(Line(f"{part.name}: decoded ({what})", t / US_PER_S, n, "step"))
    _truth_lines(panel, part, view, trace, "dashed")


def draw_level(panel: Panel, part, view, trace, recorded: Recorded) -> None:
    """Each signal on a row of its own (as a logic analyser draws them), 0 to 0.8 of it."""
    for name, _suffix, kind in _signals(part, view, recorded):
        t, v = recorded.get(name)
        t = np.concatenate([[0], t, [trace.header.get("t_end_us", t[-1] if len(t) else 0)]])
        v = np.concatenate([[recorded.initial.get(name, 0)], v, v[-1:] if len(v) else [recorded.initial.get(name, 0)]])
        if kind == "pwm":  # (a tone or a waveform: its duty's scale is the driver's, 1023 of 65535 for
            values = (np.asarray(v, float) > 0).astype(float)  # picozero's Speaker: on while it is driven)
        else:
            values = v / 65535 if kind in ("duty", "u16") else np.asarray(v, float)
        row = len(panel.lines) * LEVEL_ROW
        scale = {"duty": " /65535", "u16": " /65535", "pwm": " on while its duty > 0"}.get(kind, "")
        label = f"{name}{scale} (row {row:g})"
        panel.lines.append(Line(label, t / US_PER_S, row + 0.8 * values, "step"))
        if (0.8, "") not in panel.levels:
            panel.levels.append((0.8, ""))  # a row's high: the axis spans it even when all stay low
    if view.plot == "contacts":
        _truth_lines(panel, part, view, trace, "dashed")


def draw_points(panel: Panel, part, view, trace, recorded: Recorded) -> None:
    """A reading through the part's law (a battery's volts, a servo's angle) and its truth."""
    for name, suffix, _kind in _signals(part, view, recorded):
        t, v = recorded.get(name)
        style = "step" if view.plot == "angle" else "points"
        what = "asked by the firmware's pulse" if view.plot == "angle" else "read by the firmware"
        panel.lines.append(Line(f"{part.name}: {what}", t / US_PER_S, _reading(part, suffix, v), style))
    _truth_lines(panel, part, view, trace)


def draw_strip(panel: Panel, part, view, trace, recorded: Recorded) -> None:
    """Each LED's colour (``0xRRGGBB`` outputs) as a bar of that colour on a row of its own."""
    for name, (direction, _kind) in recorded.own(part).items():
        if direction != "out" or not name.rpartition(".")[2].startswith("led"):
            continue  # (an apa102_strip's level<i>: a brightness, not a colour)
        t, v = recorded.get(name)
        t = np.concatenate([[0], t])
        v = np.concatenate([[recorded.initial.get(name, 0)], v])
        panel.lines.append(Line(name, t / US_PER_S, v, "colours"))
    faults = trace.truth.get(f"{part.name}_timing_faults")
    if faults is not None and len(faults) and np.nanmax(faults) > 0:
        panel.notes.append(
            f"{part.name}: {int(np.nanmax(faults))} streams out of the WS2812's timing (decoded as a chip would)"
        )


DRAW = {
    "range": draw_range,
    "command": draw_command,
    "count": draw_count,
    "contacts": draw_level,
    "level": draw_level,
    "voltage": draw_points,
    "angle": draw_points,
    "rate": draw_points,
    "heading": draw_points,
    "strip": draw_strip,
}


def speed_panel(trace, recorded: Recorded, parts: list, body: dict) -> Panel:
    """The body's true speed, and the speed each encoder's edges say over 100 ms windows
    (its metres per edge from its options and the body's wheel)."""
    panel = Panel("Speed: the encoders' edges against the truth", "speed (m/s)")
    tr = trace.truth
    for part in parts:
        per_edge = getattr(part, "metres_per_edge", None)
        m = per_edge(body) if per_edge else None
        if not m or not recorded.own(part):
            continue
        t, n = decoded_count(recorded, part)
        if len(t) < 2:
            continue
        edges = np.arange(0, int(t[-1]) + SPEED_WINDOW_US, SPEED_WINDOW_US)
        counts = np.concatenate([[0.0], n])[np.searchsorted(t, edges, side="right")]
        speed = np.diff(counts) * m / (SPEED_WINDOW_US / US_PER_S)
        panel.lines.append(
            Line(f"{part.name}: edges x {m * 1000:.3g} mm per 100 ms", edges[1:] / US_PER_S, speed, "step")
        )
    if panel.lines and "v_m_s" in tr:
        panel.lines.append(Line("v_m_s (truth)", tr["t_us"] / US_PER_S, tr["v_m_s"]))
    return panel

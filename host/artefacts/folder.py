"""The trace folder a recorded run leaves behind, and how to read it back.

==================  ==================================================================
file                content
==================  ==================================================================
``header.json``     app, board, world, plant and its options, fault schedule, seed, mode, commit,
                    MicroPython version, end time, the signals with their role and kind
``trace.jsonl``     the link messages, decoded (written by :mod:`host.artefacts.linklog`)
``signals.csv``     ``t_us,signal,value``: every firmware output and plant output change
``truth.csv``       ``t_us,x_m,y_m,theta_rad,...``: ground truth every 50 ms
``budgets.json``    each timing budget: limit, statistics and a histogram of its values
``trace.vcd``       the signals, the ground truth, the console's lines and the budgets'
                    misses, for a wave viewer
``trace.gtkw``      GTKWave's save file for it: ``gtkwave trace.gtkw`` shows it all
``console.log``     what the firmware printed (written by the rig)
==================  ==================================================================

Everything but ``budgets.json`` (which holds the wall-clock ``control.compute``) and
``console.log`` is in virtual time only: the same run gives the same bytes.
``docs/traces.md`` describes the formats.
"""

import csv
import heapq
import json
import math
import re
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from host.artefacts.console import stamped_lines
from host.artefacts.recorder import ROLE_SENSOR
from host.artefacts.vcd import write_gtkw, write_vcd
from host.core import provenance
from host.core.errors import ConfigError

FORMAT = "mpy-fil-trace/1"
HEADER = "header.json"
SIGNALS = "signals.csv"
TRUTH = "truth.csv"
BUDGETS = "budgets.json"
VCD = "trace.vcd"
GTKW = "trace.gtkw"
LINK = "trace.jsonl"
CONSOLE = "console.log"
DEFAULT_FOOTPRINT_HALF_WIDTH_M = 0.15
DEFAULT_COVERAGE_CELL_M = 0.05


# -- writing ------------------------------------------------------------------------


def write_trace_folder(folder: Path, run: dict, recorder, plant, budgets: dict) -> Path:
    """Write a stopped run's recording into ``folder``. ``run`` holds what identifies the
    run (app, board, plant_options, seed, mode, micropython, t_end_us); ``budgets`` maps
    names to budgets, each of which gives its own ``record()``."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    header = make_header(run, recorder, plant, link_trace=(folder / LINK).is_file())
    _write_json(folder / HEADER, header)
    events = _Records(recorder.events_in_time_order)  # (read from disk each time: never all in memory)
    truth = _Records(lambda: (row for chunk in recorder.iter_truth() for row in chunk))
    with open(folder / SIGNALS, "w", newline="", encoding="utf-8") as f:
        out = csv.writer(f, lineterminator="\n")
        out.writerow(["t_us", "signal", "value"])
        out.writerows(events)
    _write_truth(folder / TRUTH, truth)
    _write_json(folder / BUDGETS, [b.record() for b in budgets.values()])
    paths = write_vcd(
        folder / VCD,
        top=run["app"],
        comment=f"app {run['app']} board {run['board']} seed {run['seed']} commit {header['commit']}",
        signals=recorder.signals,
        initial=recorder.initial,
        events=events,
        truth=truth,
        notes=trace_notes(folder, budgets),
    )
    write_gtkw(folder / GTKW, VCD, paths)
    return folder


def trace_notes(folder: Path, budgets: dict) -> "_Records":
    """(t_us, channel, text) for the VCD's events, in time order: each console line
    (``console``, read from the file as it goes: a chatty firmware's console is never
    held whole) and each kept budget miss (``budget_miss``: the budget's name and value)."""
    misses = sorted(
        (
            (t, "budget_miss", f"{b.name} {value} us")
            for b in budgets.values()
            for t, value in b.first_misses
            if t is not None
        ),
        key=_time,
    )
    console = folder / CONSOLE

    def lines():
        return ((t, "console", line) for t, line in stamped_lines(console)) if console.is_file() else ()

    return _Records(lambda: heapq.merge(lines(), misses, key=_time))


def _time(record: tuple) -> int:
    return record[0]


class _Records:
    """A recording's records, made afresh each time they are iterated."""

    def __init__(self, make):
        self.make = make

    def __iter__(self):
        return iter(self.make())


def make_header(run: dict, recorder, plant, link_trace: bool) -> dict:
    return {
        "format": FORMAT,
        "app": run["app"],
        "rig_file": run.get("rig_file"),
        "board": run["board"],
        "world": describe_world(plant),
        "plant": type(getattr(plant, "inner", plant)).__name__,
        "faults": [{"kind": f.kind, **f.fields} for f in getattr(plant, "schedule", ())],
        "plant_options": run["plant_options"],
        "parts": described_parts(plant),
        "report": run.get("report"),
        "seed": run["seed"],
        "mode": run["mode"],
        "commit": provenance.commit(),
        "micropython": run["micropython"],
        "t_end_us": run["t_end_us"],
        "truth_period_us": recorder.truth_period_us,
        "footprint_half_width_m": footprint_half_width_m(plant),
        "coverage_cell_m": float(getattr(coverage_grid(plant), "cell_m", DEFAULT_COVERAGE_CELL_M)),
        "signals": recorder.signals,
        "initial": recorder.initial,
        "contacts": [list(c) for c in _truth_contacts(plant)],
        "link_trace": link_trace,
    }


def described_parts(plant) -> dict | None:
    """A plant built from a body and parts, as data (``PartsPlant.describe``): what the
    report draws each part's views from. None for a plant of another kind."""
    describe = getattr(getattr(plant, "inner", plant), "describe", None)
    return describe() if callable(describe) else None


def describe_world(plant) -> dict | None:
    """The plant's walls (its ``world``, a sim_plant.world.World), as ``{"name",
    "segments": [[ax, ay, bx, by], ...]}``; the name says the world's size."""
    world = getattr(plant, "world", None)
    if world is None or not hasattr(world, "segments"):
        return None
    segments = [[float(v) for v in s] for s in world.segments()]
    name = str(getattr(world, "name", "world"))
    if not re.search(r"\d x \d", name):
        xs = [v for s in segments for v in (s[0], s[2])]
        ys = [v for s in segments for v in (s[1], s[3])]
        name += f" {max(xs) - min(xs):g} x {max(ys) - min(ys):g} m"
    return {"name": name, "segments": segments}


def coverage_grid(plant):
    """The plant's own floor coverage grid (a sim_plant.coverage.CoverageGrid), if any."""
    for part in [plant, *getattr(plant, "parts", ())]:
        for value in (getattr(part, "grid", None), getattr(part, "coverage", None)):
            if hasattr(value, "half_width_m") and hasattr(value, "cell_m"):
                return value
    return None


def footprint_half_width_m(plant) -> float:
    """Half the width of the floor the robot sweeps (its coverage grid's, or its body's)."""
    grid = coverage_grid(plant)
    for value in (getattr(grid, "half_width_m", None), getattr(plant, "body_radius_m", None)):
        if isinstance(value, (int, float)):
            return float(value)
    return DEFAULT_FOOTPRINT_HALF_WIDTH_M


def _truth_contacts(plant) -> list:
    contacts = plant.truth().get("contacts", [])
    return [[int(c[0]), float(c[1]), float(c[2])] for c in contacts if isinstance(c, (list, tuple)) and len(c) >= 3]


def _write_truth(path: Path, truth: list) -> None:
    columns: list[str] = []
    for _t, row in truth:
        for key in row:
            if key != "t_us" and key not in columns:
                columns.append(key)
    with open(path, "w", newline="", encoding="utf-8") as f:
        out = csv.writer(f, lineterminator="\n")
        out.writerow(["t_us", *columns])
        for t, row in truth:
            out.writerow([t, *(_fmt(row.get(c)) for c in columns)])


def _fmt(value) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return repr(value)
    return str(value)


def _write_json(path: Path, data) -> None:
    path.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n", encoding="utf-8")


# -- reading ------------------------------------------------------------------------


@dataclass
class TraceData:
    """A trace folder in memory: ``truth`` maps each column (and ``t_us``) to an array."""

    folder: Path
    header: dict
    events: list = field(default_factory=list)
    truth: dict = field(default_factory=dict)
    budgets: list = field(default_factory=list)

    def series(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        """(t_us, value) of every recorded change of one numeric signal."""
        pairs = [(t, v) for t, n, v in self.events if n == name]
        if not pairs:
            return np.zeros(0, dtype=np.int64), np.zeros(0)
        t, v = zip(*pairs)
        return np.asarray(t, dtype=np.int64), np.asarray(v, dtype=float)

    def signals(self, role: str | None = None) -> dict[str, dict]:
        sigs = self.header.get("signals", {})
        return {n: i for n, i in sigs.items() if role is None or i["role"] == role}

    def firmware_outputs(self) -> list[tuple[int, str, object]]:
        sensors = set(self.signals(ROLE_SENSOR))
        return [e for e in self.events if e[1] not in sensors]


def load_trace(folder) -> TraceData:
    """Read a trace folder; a missing or malformed one raises ConfigError naming it."""
    folder = Path(folder)
    header_path = folder / HEADER
    if not header_path.is_file():
        raise ConfigError(f"trace folder {folder}: no {HEADER} (expected a folder written by a recorded run)")
    try:
        header = json.loads(header_path.read_text(encoding="utf-8"))
    except ValueError as e:
        raise ConfigError(f"trace folder {folder}: {HEADER} is not JSON ({e})") from e
    if header.get("format") != FORMAT:
        raise ConfigError(f"trace folder {folder}: format {header.get('format')!r}, expected {FORMAT!r}")
    data = TraceData(folder, header)
    with _reading(folder, HEADER):
        kinds = {n: i["kind"] for n, i in header.get("signals", {}).items()}
    if (folder / SIGNALS).is_file():
        with _reading(folder, SIGNALS), open(folder / SIGNALS, newline="", encoding="utf-8") as f:
            rows = csv.reader(f)
            next(rows, None)
            data.events = [(int(t), name, _parse(kinds.get(name), value)) for t, name, value in rows]
    if (folder / TRUTH).is_file():
        with _reading(folder, TRUTH):
            data.truth = _read_truth(folder / TRUTH)
    if (folder / BUDGETS).is_file():
        with _reading(folder, BUDGETS):
            data.budgets = json.loads((folder / BUDGETS).read_text(encoding="utf-8"))
    return data


@contextmanager
def _reading(folder: Path, name: str):
    """A file of the folder that does not parse raises ConfigError naming it."""
    try:
        yield
    except (ValueError, KeyError, TypeError, AttributeError) as e:  # (UnicodeDecodeError is a ValueError)
        raise ConfigError(
            f"trace folder {folder}: {name} is malformed ({type(e).__name__}: {e}); "
            "expected the file a recorded run writes (docs/traces.md)"
        ) from e


def _parse(kind: str | None, text: str):
    if kind == "bytes":
        return text
    try:
        return int(text)
    except ValueError:
        try:
            return float(text)
        except ValueError:
            return text


def _read_truth(path: Path) -> dict:
    with open(path, newline="", encoding="utf-8") as f:
        rows = list(csv.reader(f))
    if not rows:
        return {}
    columns, body = rows[0], rows[1:]
    out = {}
    for i, name in enumerate(columns):
        values = [float(r[i]) if i < len(r) and r[i] != "" else math.nan for r in body]
        out[name] = np.asarray(values, dtype=np.int64 if name == "t_us" else float)
    return out

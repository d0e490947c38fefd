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
``<display>.png``   a display part's last picture, ``<display>.gif`` all of them in turn
                    (:mod:`host.artefacts.pictures`: an ``ssd1306``'s)
``console.log``     what the firmware printed (written by the rig)
==================  ==================================================================

Everything but ``budgets.json`` (which holds the wall-clock ``control.compute``) and
``console.log`` is in virtual time only: the same run gives the same bytes.
A recorded run's folder starts with a header marked partial (:func:`begin_trace_folder`);
at the end each file is written whole or not at all, and the header last, sealing every
file of the folder (each one's digest, ``board_fs/`` included) and saying what is
incomplete. :func:`load_trace`, which every command that reads a folder goes through,
refuses a damaged folder by name (:func:`host.artefacts.checks.check_seal`).
``docs/traces.md`` describes the formats.
"""

import contextlib
import csv
import heapq
import io
import itertools
import json
import math
import re
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from host.artefacts import checks, integrity, pictures
from host.artefacts.console import stamped_lines
from host.artefacts.csvlines import SignalLines, TruthLines
from host.artefacts.recorder import ROLE_SENSOR
from host.artefacts.streaming import Streamed
from host.artefacts.vcd import write_gtkw, write_vcd
from host.core import provenance, safefs
from host.core.errors import ConfigError, OutputRefused

FORMAT = "mpy-fil-trace/1"
HEADER = "header.json"
MANIFEST = "manifest.json"  # what made the run (host/rig/loop/manifest.py), sealed with the rest
SIGNALS = "signals.csv"
TRUTH = "truth.csv"
BUDGETS = "budgets.json"
VCD = "trace.vcd"
GTKW = "trace.gtkw"
LINK = "trace.jsonl"
CONSOLE = "console.log"
CPU_LOAD = "cpu_load.csv"  # with MCU time: the firmware's busy share of each 100 ms (docs/mcu-time.md)
NOT_ENDED = "the run did not end (killed, or its machine stopped); console.log and trace.jsonl hold what streamed"
DEFAULT_FOOTPRINT_HALF_WIDTH_M = 0.15
DEFAULT_COVERAGE_CELL_M = 0.05


# -- writing ------------------------------------------------------------------------


def write_trace_folder(folder: Path, run: dict, recorder, plant, budgets: dict) -> Path:
    """Write a stopped run's recording into ``folder``. ``run`` holds what identifies the
    run (app, board, plant_options, seed, mode, micropython, t_end_us) and how it ended
    (``stop``: None, or why it was cut; ``incomplete``: streamed files cut short;
    ``console``: the console's counts); ``budgets`` maps names to budgets, each of which
    gives its own ``record()``.

    Each file is written whole or not at all (:func:`~host.artefacts.integrity.atomic`),
    and ``header.json`` last, with each file's SHA-256 and the list of what is missing or
    incomplete. A write that fails raises TraceWriteError naming its file, after the
    header has said so (when even the header cannot be written, the one written when the
    run began stays, marked partial)."""
    folder = Path(folder)
    safefs.make_folder(folder)  # (the folder itself a link: refused)
    incomplete = dict(run.get("incomplete") or {})
    error = None
    for name, write in (*_writers(folder, run, recorder, budgets), *pictures.writers(plant)):
        if error is not None:
            incomplete[name] = f"not written: {error.error.strerror or error.error} writing {error.path.name}"
            continue
        try:
            with integrity.atomic(folder / name) as part:
                write(part)
        except integrity.TraceWriteError as e:
            error = e
            incomplete[name] = f"not written: {e.error.strerror or e.error}"
    files = integrity.folder_digests(folder, HEADER)  # (every file, streamed ones cut short too: sealed as they are)
    header = make_header({**run, "incomplete": incomplete}, recorder, plant, link_trace=(folder / LINK).is_file())
    text = _json(integrity.seal({**header, "files": files}))
    try:
        integrity.write_text(folder / HEADER, text)
    except integrity.TraceWriteError as e:
        error = error or e
        with contextlib.suppress(OSError, OutputRefused):  # (in place: the start's header gives back its space)
            with safefs.open_write(folder / HEADER, "w", encoding="utf-8") as f:
                f.write(text)
    if error is not None:
        raise error
    return folder


def reseal(folder: Path) -> None:
    """After a deliberate edit of a trace folder (a test that changes a recording): the
    header's seal made anew over the files that are there."""
    folder = Path(folder)
    header = json.loads((folder / HEADER).read_text(encoding="utf-8"))
    header["files"] = integrity.folder_digests(folder, HEADER)
    integrity.write_text(folder / HEADER, _json(integrity.seal(header)))


def reseal_file(folder: Path, name: str) -> None:
    """The harness changed one file of a sealed folder on purpose after the run (the budgets'
    verdicts, stamped once the test has judged them): that file's digest in the seal made
    anew, and the header's; nothing when the header does not seal it."""
    folder = Path(folder)
    try:
        header = json.loads((folder / HEADER).read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return
    files = header.get("files") if isinstance(header, dict) else None
    if not isinstance(files, dict) or name not in files or not (folder / name).is_file():
        return
    files[name] = integrity.file_digest(folder / name)
    integrity.write_text(folder / HEADER, _json(integrity.seal(header)))


def set_boards(folder) -> list[str]:
    """The boards of a set of boards' run folder (docs/multi-board.md: a trace folder a
    board, named as the board), in name order; [] for anything else (a trace folder too)."""
    folder = Path(folder)
    if (folder / HEADER).is_file():
        return []
    try:
        return sorted(p.name for p in folder.iterdir() if (p / HEADER).is_file())
    except OSError:
        return []


def begin_trace_folder(folder: Path, run: dict, recorder, plant) -> None:
    """As a recorded run starts: an earlier run's files go, and a header marked partial
    ("the run did not end") stands until the run's own replaces it, so a run killed
    outright leaves a folder that says so."""
    folder = Path(folder)
    shown = [name for name, _write in pictures.writers(plant)]  # (a display's pictures)
    integrity.remove_stale(folder, (HEADER, SIGNALS, TRUTH, BUDGETS, VCD, GTKW, *shown))
    if recorder.streamed is None:  # (the big files made as the run goes: host/artefacts/streaming.py)
        recorder.streamed = Streamed(recorder)
    stop = {"reason": NOT_ENDED, "signal": None}
    header = make_header({**run, "stop": stop}, recorder, plant, link_trace=(folder / LINK).is_file())
    integrity.write_text(folder / HEADER, _json(integrity.seal(header)))


def drop_begun_folder(folder: Path) -> None:
    """The recording was dropped (a passed test that keeps none): the header written as it
    began goes too, as that run never wrote a folder."""
    path = Path(folder) / HEADER
    with contextlib.suppress(OSError, ValueError, AttributeError):
        if (json.loads(path.read_text(encoding="utf-8")).get("stop") or {}).get("reason") == NOT_ENDED:
            path.unlink()


def _writers(folder: Path, run: dict, recorder, budgets: dict):
    """(file name, write(path)) for each file made at the end, most needed first."""
    events = _Records(recorder.events_in_time_order)  # (read from disk each time: never all in memory)
    truth = _Records(lambda: (row for chunk in recorder.iter_truth() for row in chunk))
    vcd_paths: dict = {}
    streamed = recorder.streamed  # (the lines made as the run went, where they fit)
    if streamed is not None:
        streamed.finish()

    def signals(path):
        if streamed is not None and streamed.usable:
            with open(path, "wb") as f:
                f.write(b"t_us,signal,value\n")
                streamed.copy(streamed.signals_file, f)
        else:
            _write_signals(path, events)

    def truth_csv(path):
        columns = recorder.truth_columns()
        if streamed is not None and streamed.truth_fits(columns):
            with open(path, "wb") as f:
                f.write(streamed.truth_lines.header().encode())
                streamed.copy(streamed.truth_file, f)
        else:
            _write_truth(path, truth, columns)

    def vcd(path):
        comment = f"app {run['app']} board {run['board']} seed {run['seed']} commit {provenance.commit()}"
        notes = trace_notes(folder, budgets)
        signals = recorder.signals
        vcd_paths.update(
            write_vcd(
                path,
                top=run["app"],
                comment=comment,
                signals=signals,
                initial=recorder.initial,
                events=events,
                truth=truth,
                notes=notes,
                columns=recorder.truth_columns(),
                streamed=None if streamed is None else streamed.changes(),
            )
        )

    def cpu_load(path):
        with open(path, "w", newline="", encoding="utf-8") as f:
            out = csv.writer(f, lineterminator="\n")
            out.writerow(["t_us", "busy_share", "callbacks_share"])
            out.writerows(cpu_load_rows(run["mcu_time"]))

    return (
        (SIGNALS, signals),
        (TRUTH, truth_csv),
        (BUDGETS, lambda path: path.write_text(_json([b.record() for b in budgets.values()]), encoding="utf-8")),
        (VCD, vcd),
        (GTKW, lambda path: write_gtkw(path, VCD, vcd_paths)),
        *(((CPU_LOAD, cpu_load),) if run.get("mcu_time") else ()),
    )


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
        "plant": type(plant.unwrapped).__name__,
        "faults": [{"kind": f.kind, **f.fields} for f in plant.fault_schedule],
        "plant_options": run["plant_options"],
        "parts": plant.describe(),
        **({"wired": wired} if (wired := plant.wired_signals()) is not None else {}),  # a board of a set's own
        **({"displays": shown} if (shown := pictures.describe_displays(plant)) else {}),  # their film strips
        "report": run.get("report"),
        **({"spec": run["spec"]} if run.get("spec") else {}),  # what built the rig (host/rig/loop/spec.py)
        "seed": run["seed"],
        "mode": run["mode"],
        "commit": provenance.commit(),
        "micropython": run["micropython"],
        "t_end_us": run["t_end_us"],
        "truth_period_us": recorder.truth_period_us,
        "footprint_half_width_m": footprint_half_width_m(plant),
        "coverage_cell_m": coverage_cell_m(plant),
        "signals": recorder.signals,
        "initial": recorder.initial,
        "contacts": [list(c) for c in _truth_contacts(plant)],
        "link_trace": link_trace,
        "partial": bool(run.get("stop") or run.get("incomplete")),
        "stop": run.get("stop"),
        "incomplete": run.get("incomplete") or {},
        "console": run.get("console"),
        **({"board_fs": run["board_fs"]} if run.get("board_fs") else {}),  # what the firmware wrote on its flash
        **({"mcu_time": run["mcu_time"]} if run.get("mcu_time") else {}),  # the CPU load (docs/mcu-time.md)
    }


def describe_world(plant) -> dict | None:
    """The plant's walls (its ``world``, a sim_plant.world.World), as ``{"name",
    "segments": [[ax, ay, bx, by], ...]}``; the name says the world's size. A floor drawn
    as a picture adds ``"floor"`` (:func:`host.artefacts.pictures.describe_floor`)."""
    world = plant.world
    if world is None:
        return None
    segments = [[float(v) for v in s] for s in world.segments()]
    name = str(getattr(world, "name", "world"))
    if not re.search(r"\d x \d", name):
        xs = [v for s in segments for v in (s[0], s[2])]
        ys = [v for s in segments for v in (s[1], s[3])]
        name += f" {max(xs) - min(xs):g} x {max(ys) - min(ys):g} m"
    floor = pictures.describe_floor(plant)
    return {"name": name, "segments": segments, **({"floor": floor} if floor else {})}


def footprint_half_width_m(plant) -> float:
    """Half the width of the floor the robot sweeps (its coverage grid's), else a default."""
    grid = plant.coverage_grid()
    width = None if grid is None else grid.half_width_m
    return float(width) if isinstance(width, (int, float)) else DEFAULT_FOOTPRINT_HALF_WIDTH_M


def coverage_cell_m(plant) -> float:
    """The plant's coverage grid's cell, else a default."""
    grid = plant.coverage_grid()
    return DEFAULT_COVERAGE_CELL_M if grid is None else float(grid.cell_m)


def _truth_contacts(plant) -> list:
    contacts = plant.truth().get("contacts", [])
    return [[int(c[0]), float(c[1]), float(c[2])] for c in contacts if isinstance(c, (list, tuple)) and len(c) >= 3]


def _write_signals(path: Path, events) -> None:
    """``signals.csv``: what ``csv.writer`` writes (:class:`~host.artefacts.csvlines.SignalLines`)."""
    with open(path, "w", newline="", encoding="utf-8") as f:
        f.write("t_us,signal,value\n")
        lines = SignalLines()
        events = iter(events)
        while chunk := list(itertools.islice(events, _LINES_A_WRITE)):
            f.write(lines(chunk))


def _write_truth(path: Path, truth, columns: list[str]) -> None:
    """``truth.csv``: what ``csv.writer`` writes (:class:`~host.artefacts.csvlines.TruthLines`)."""
    with open(path, "w", newline="", encoding="utf-8") as f:
        lines = TruthLines(columns)
        f.write(lines.header())
        truth = iter(truth)
        while chunk := list(itertools.islice(truth, _LINES_A_WRITE)):
            f.write(lines(chunk))


_LINES_A_WRITE = 4096


def _json(data) -> str:
    return json.dumps(data, indent=1, sort_keys=True) + "\n"


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
    """Read a trace folder; a missing, malformed or damaged one raises ConfigError naming
    the file and what is wrong (:mod:`host.artefacts.checks`); a partial one that lacks a
    file says it is partial."""
    folder = Path(folder)
    header_path = folder / HEADER
    if not header_path.is_file():
        raise ConfigError(f"trace folder {folder}: no {HEADER} (expected a folder written by a recorded run)")
    try:
        header = json.loads(header_path.read_text(encoding="utf-8"))
    except (ValueError, RecursionError) as e:
        raise ConfigError(f"trace folder {folder}: {HEADER} is not JSON ({type(e).__name__}: {e})") from None
    if not isinstance(header, dict) or header.get("format") != FORMAT:
        got = header.get("format") if isinstance(header, dict) else header
        raise ConfigError(f"trace folder {folder}: format {got!r:.80}, expected {FORMAT!r}")
    checks.check_header(folder, header)
    checks.check_seal(folder, header)  # (every file: the ones read below and the others)
    data = TraceData(folder, header)
    kinds = {n: i["kind"] for n, i in header["signals"].items()}
    if checks.check_file(folder, header, SIGNALS, needed=True):
        with _reading(folder, SIGNALS):
            data.events = _read_signals(folder, kinds)
    if checks.check_file(folder, header, TRUTH, needed=True):
        with _reading(folder, TRUTH):
            data.truth = _read_truth(folder)
    if checks.check_file(folder, header, BUDGETS, needed=False):
        with _reading(folder, BUDGETS):
            data.budgets = json.loads((folder / BUDGETS).read_text(encoding="utf-8"))
            if not isinstance(data.budgets, list) or not all(isinstance(b, dict) for b in data.budgets):
                raise ValueError("expected a list of objects")
    checks.check_file(folder, header, CONSOLE, needed=False)  # (the report reads its telemetry)
    return data


def _read_signals(folder: Path, kinds: dict) -> list:
    text = (folder / SIGNALS).read_text(encoding="utf-8")
    checks.whole_lines(folder, SIGNALS, text)
    rows = csv.reader(io.StringIO(text))
    if next(rows, None) != ["t_us", "signal", "value"]:
        raise ValueError("expected the columns t_us,signal,value")
    events = [(int(t), name, _parse(kinds.get(name), value)) for t, name, value in rows]
    unknown = {e[1] for e in events} - set(kinds)
    if unknown:
        raise ValueError(f"signals not in header.json's signals: {sorted(unknown)[:5]}")
    if events and not 0 <= min(e[0] for e in events) <= max(e[0] for e in events) <= checks.MAX_T_END_US:
        raise ValueError("a time outside 0 .. ten simulated days")
    return events


@contextmanager
def _reading(folder: Path, name: str):
    """A file of the folder that does not parse raises ConfigError naming it."""
    try:
        yield
    except (
        ValueError,
        KeyError,
        TypeError,
        AttributeError,
        RecursionError,
        csv.Error,
    ) as e:  # (UnicodeDecodeError is a ValueError)
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


def _read_truth(folder: Path) -> dict:
    text = (folder / TRUTH).read_text(encoding="utf-8")
    checks.whole_lines(folder, TRUTH, text)
    rows = list(csv.reader(io.StringIO(text)))
    if not rows:
        return {}
    columns, body = rows[0], rows[1:]
    if not columns or columns[0] != "t_us":
        raise ValueError("expected t_us as the first column")
    for n, row in enumerate(body, start=2):
        if len(row) != len(columns):
            raise ValueError(f"line {n} has {len(row)} fields, expected {len(columns)}")
    out = {}
    for i, name in enumerate(columns):
        values = [float(r[i]) if r[i] != "" else math.nan for r in body]
        out[name] = np.asarray(values, dtype=float)
    t = out["t_us"]
    if len(t) and not (np.all(np.isfinite(t)) and t.min() >= 0 and t.max() <= checks.MAX_T_END_US):
        raise ValueError("a t_us outside 0 .. ten simulated days")
    out["t_us"] = t.astype(np.int64)
    return out


def cpu_load_rows(record: dict) -> list[tuple]:
    """``cpu_load.csv``'s rows from the header's ``mcu_time`` (host/rig/targets/mcutime.py): (t_us at
    the window's start, the main program's busy share, the callbacks')."""
    irq = record.get("callbacks_share") or [0.0] * len(record["busy_share"])
    return [(i * record["window_us"], share, irq[i]) for i, share in enumerate(record["busy_share"])]

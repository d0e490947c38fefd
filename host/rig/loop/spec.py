"""What a rig is, in one frozen value, and the one place that builds its plant.

A :class:`RigSpec` names everything that decides what a rig does: the app (one of ours by
name, a rig file by its path, or an :class:`App` in memory), the board, the world, the
seed, plant options over the world's (``--param``), faults over the rig file's (a
campaign's fault set), the start pose's placement error, the clock mode, the watchdog,
the firmware's folder, and how this process serves its link (``busy_poll``, decided by
the front end: the CLI, the pytest plugin, a campaign's runner). :class:`Recording` is
what a run keeps and shows (trace, recording, artefacts folder, progress).

Every front end (``mpy-fil run``/``check``, the pytest plugin's ``make_rig``, a
campaign's worker and checks, ``replay``, the virtual board) makes a spec and hands it to
:class:`host.rig.Rig`, which builds the plant with :func:`build_plant`; the trace
folder's header records the spec (:meth:`RigSpec.header`) so a replay rebuilds the same
one (:meth:`RigSpec.from_header`). ``docs/architecture.md`` draws it.
"""

import dataclasses
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from host.core.errors import ConfigError
from host.rig.config import arguments
from host.rig.config.app import App
from host.rig.loop.pacing import PACINGS
from host.rig.targets.target import FaultyLinkTarget, Target, UnixPortTarget
from sim_plant.faults import parse_faults, with_faults
from sim_plant.names import unknown
from sim_plant.plant import POSE, Plant, check_contract

PLACEMENT_KEYS = ("x_m", "y_m", "theta_deg")
LINK_FAULTS = ("link_corrupt", "link_stall")


def _frozen(mapping) -> tuple:
    """A mapping as a tuple of (name, value) pairs, in its order."""
    return tuple(dict(mapping).items())


@dataclass(frozen=True)
class RigSpec:
    """A rig's specification. Mappings (``options``, each of ``faults``, ``placement``)
    are given as dicts and kept as tuples of pairs; :attr:`plant_options`,
    :attr:`fault_entries` and :attr:`placement_ranges` give them back as dicts.
    A bad field is a ConfigError naming it; ``seed`` None draws one, kept here."""

    app: str | App = "rover"
    board: str | None = None  # default: the app's own
    world: str | None = None  # a named world of the app (None: the app's own options only)
    seed: int | None = 0
    options: tuple = ()  # plant options over the world's
    faults: tuple = ()  # fault entries ({"kind": ..., ...}) after the rig file's
    placement: tuple = ()  # start-pose error ranges: x_m, y_m, theta_deg = (low, high)
    mode: str = "lockstep"
    watchdog_s: float = 5.0
    main_dir: Path | None = None  # the firmware's main folder instead of the app's
    firmware_dir: Path | None = None  # a flashed board folder
    require_main: bool = True  # a flashed folder needs a main.py
    allow_exit: bool = False  # the firmware may end (else an end is FirmwareExited)
    busy_poll: bool = True  # this process may spin on its link (a core to spare: the front end's choice)

    def __post_init__(self):
        if self.mode not in PACINGS:
            raise ConfigError(f"mode: expected one of {sorted(PACINGS)}, got {self.mode!r}")
        arguments.seconds("watchdog_s", self.watchdog_s, positive=True)
        object.__setattr__(self, "seed", arguments.seed(self.seed))
        object.__setattr__(self, "options", _frozen(self.options))
        object.__setattr__(self, "faults", tuple(_frozen(f) for f in self.faults))
        object.__setattr__(self, "placement", _frozen(self.placement))

    @property
    def plant_options(self) -> dict:
        return dict(self.options)

    @property
    def fault_entries(self) -> list[dict]:
        return [dict(f) for f in self.faults]

    @property
    def placement_ranges(self) -> dict:
        return dict(self.placement)

    def replace(self, **changes) -> "RigSpec":
        return dataclasses.replace(self, **changes)

    def resolve(self) -> App:
        """The app, with a fault set's smaller heap (the interpreter's ``-X heapsize``)."""
        from host.rig.config.apps import get_app

        app = get_app(self.app) if isinstance(self.app, str) else self.app
        heap = [f.size for f in parse_faults(self.fault_entries) if f.kind == "heap"]
        return (
            dataclasses.replace(app, interpreter=dataclasses.replace(app.interpreter, heap_size=heap[-1]))
            if heap
            else app
        )

    def header(self, app: App) -> dict:
        """The spec as plain data for a trace folder's header (what :meth:`from_header` reads)."""
        return {
            "app": self.app if isinstance(self.app, str) else app_reference(app),
            "board": self.board or app.default_board,
            "world": self.world,
            "seed": self.seed,
            "options": self.plant_options,
            "faults": self.fault_entries,
            "placement": self.placement_ranges,
            "mode": self.mode,
        }

    @classmethod
    def from_header(cls, header: dict, **changes) -> "RigSpec":
        """The spec a trace folder's header recorded (a folder written before headers held
        one: its app, board, seed, mode and plant options)."""
        recorded = header.get("spec")
        if recorded is None:
            recorded = {
                "app": header.get("rig_file") or header["app"],
                "board": header.get("board"),
                "seed": header.get("seed", 0),
                "options": header.get("plant_options", {}),
                "mode": header.get("mode", "lockstep"),
            }
        known = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(recorded) - known)
        if unknown:
            raise ConfigError(f"spec: unknown fields {', '.join(unknown)}")
        return cls(**{**recorded, **changes})


@dataclass(frozen=True)
class Recording:
    """What a run keeps and shows: ``trace`` the link messages (``artefacts/trace.jsonl``),
    ``record`` every signal and ground truth (the trace folder, written at stop), in
    ``artefacts``; ``progress(t_us, t_end_us)`` called while it runs; ``time_round_trips``
    the wall time of each link round trip (the benchmarks); ``coverage`` the firmware's
    coverage, written to that coverage.py data file (docs/coverage.md)."""

    trace: bool = False
    record: bool = False
    artefacts: Path | None = None
    progress: Callable | None = None
    time_round_trips: bool = False
    coverage: Path | None = None


NO_RECORDING = Recording()


def app_reference(app: App) -> str:
    """How a trace's header names an app: its rig file (with ``::<board>`` for a board of a
    rig file with several: host.rig.config.apps.board_of_set), or its name."""
    board = app.board.in_set
    ref = str(app.rig_file or app.name)
    return f"{ref}::{board}" if board and app.rig_file else ref


def fault_schedule(spec: RigSpec, app: App) -> list:
    """The rig file's faults, then the spec's, as one schedule: what the harness applies
    (a smaller heap, link faults, brown-outs; the plant's own wrap it: :func:`build_plant`)."""
    own = [{"kind": f.kind, **f.fields} for f in app.run.faults]
    return parse_faults(own + spec.fault_entries)


def build_plant(spec: RigSpec, app: App) -> tuple[Plant, dict]:
    """The spec's plant and the options it was built with (over the app's own): the
    world's, the spec's options over them, the placement's start pose. The app builds it
    (``App.make_plant``: a rig file's plant comes with its own faults around it); the
    spec's faults wrap it once more, as a schedule of their own (each fault's random
    stream keyed by its place in the spec's faults, as a campaign's fault set). A plant
    that refuses its options raises ConfigError naming them."""
    options = plant_options(spec, app)
    if spec.placement:
        start = start_pose(_made(app, options))
        options["start_pose"] = placed(start, spec.placement_ranges, spec.seed)
    plant = check_contract(_made(app, options))
    if spec.faults:
        plant = with_faults(plant, parse_faults(spec.fault_entries))
    return plant, options


def plant_options(spec: RigSpec, app: App) -> dict:
    """The options over the app's own: the world's, the spec's over them (before placement)."""
    options = dict(app.worlds[_world(spec, app)]) if spec.world else {}
    options.update(spec.plant_options)
    return options


def default_target(spec: RigSpec, app: App, pacing) -> Target:
    """The unix port here, busy-polling its link if the spec lets it and a core is
    spare; with the schedule's link faults under its channel."""
    busy_poll_s = pacing.busy_poll_s(spec.busy_poll)
    link = [f for f in fault_schedule(spec, app) if f.kind in LINK_FAULTS]
    return FaultyLinkTarget(busy_poll_s, link, spec.seed) if link else UnixPortTarget(busy_poll_s)


def _world(spec: RigSpec, app: App) -> str:
    if spec.world not in app.worlds:
        known = unknown(spec.world, app.worlds, what="known")
        raise ConfigError(f"world: unknown world {spec.world!r} for app {app.name} {known}")
    return spec.world


class PlantOptionsError(ConfigError):
    """The app's plant refuses the options a spec builds it with."""


def _made(app: App, options: dict) -> Plant:
    try:
        return app.make_plant(**options)
    except (TypeError, ValueError, ArithmeticError) as e:
        raise PlantOptionsError(f"{app.name}'s plant rejects {options}: {e}") from None


def start_pose(plant: Plant):
    """Where the plant's robot starts: its pose at time 0 (its body's, for a body and parts)."""
    if POSE not in plant.capabilities:
        raise ConfigError(f"placement: the {type(plant).__name__} plant has no start pose to place")
    return plant.pose_at(0)


def placed(pose, placement: dict, seed: int) -> list[float]:
    """The start pose with the seed's placement error: uniform in each given range (x_m,
    y_m, theta_deg), from a stream of its own."""
    rng = np.random.default_rng([seed & 0xFFFFFFFF, 0x91ACE])
    draw = {k: float(rng.uniform(*placement[k])) if k in placement else 0.0 for k in PLACEMENT_KEYS}
    x, y, theta = pose
    return [x + draw["x_m"], y + draw["y_m"], theta + math.radians(draw["theta_deg"])]

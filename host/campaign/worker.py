"""One run of a campaign, in whatever process runs it (a local pool's, a Dask worker's):
the rig with the run's faults, driven to its end, judged; every way it can fail becomes
a failed result with its message, never an exception out of here (``docs/campaigns.md``).

A run ends at ``seconds`` of simulated time, or once the console shows ``until``. Its
wall time is bounded by ``timeout_s`` (checked while it runs, through the rig's progress
call) and a silent firmware by the rig's watchdog. A brown-out stops the board's process
at its time and boots it again on the same link; the plant carries on. Link faults sit
under the channel (:mod:`host.link.faults`), a smaller heap is the interpreter's
``-X heapsize``; the plant's faults wrap the plant (:mod:`sim_plant.faults`).
"""

import resource
import time
import traceback
from pathlib import Path

import numpy as np

from host.campaign.judges import judges
from host.campaign.scenario import task_key
from host.core import provenance, safefs
from host.core.errors import ConfigError, HarnessError
from host.rig import Rig
from host.rig.loop.spec import Recording, RigSpec, fault_schedule
from host.rig.targets.target import FaultyLinkTarget

MESSAGE_CHARS = 3000
COVERAGE_FILE = "coverage.npz"


class RunTimeout(HarnessError):
    """A run took longer than its wall-clock limit."""


def brownout(rig) -> None:
    """The board loses power where it is, then boots again (a reset the firmware did not
    ask for; the lines it drove go low meanwhile: ``Rig.power_cycle``); the plant carries on."""
    if getattr(rig.target, "proc", None) is None:
        raise ConfigError("brownout: needs the unix port target (a process the harness can cut the power of)")
    rig.power_cycle()


def run_one(task: dict, artefacts: str | None = None, record: bool = False) -> dict:
    """Run one task (``Campaign.tasks``); the result, as plain data."""
    started = time.monotonic()
    cpu0 = _cpu_s()
    result = {
        "key": task_key(task),
        "faultset": task["faultset"],
        "world": task["world"],
        "seed": task["seed"],
        "passed": False,
        "error": None,
        "message": "",
        "figures": {},
        "budgets": {},
        "t_end_s": 0.0,
        "resets": 0,
        "artefacts": artefacts,
        "commit": provenance.commit(),
    }
    rig = None
    try:
        if _is_set(task):  # several boards (docs/multi-board.md)
            rig = _make_set(task, artefacts, record, started)
            cuts = rig.brownouts
        else:
            rig, cuts = _make_rig(task, artefacts, record, started)
        rig.start()
        reached = _drive(rig, task, cuts)
        passed, figures, message = judges()[task["judge"]](rig, reached, task)
        result["figures"] = {k: float(v) for k, v in figures.items()}
        result["budgets"] = {name: _budget(b) for name, b in rig.budgets.items()}  # (a set's: <board>:<name>)
        save_coverage(rig, artefacts)
        missed = [f"{n} ({result['budgets'][n]['misses']} misses)" for n in task["budgets"] if rig.budgets[n].misses]
        if passed and missed:
            passed, message = False, f"expected the budgets kept, missed: {', '.join(missed)}"
        result.update(passed=passed, message=message)
    except HarnessError as e:
        result.update(error=type(e).__name__, message=f"{type(e).__name__}: {e}"[:MESSAGE_CHARS])
    except Exception as e:  # a crash of the harness itself is a failed run too, with its traceback
        tail = "".join(traceback.format_exception(e)[-6:])
        result.update(error="crash", message=f"harness crashed: {type(e).__name__}: {e}\n{tail}"[:MESSAGE_CHARS])
    finally:
        if rig is not None:
            rig.stop()
            result["t_end_s"] = rig.t_us / 1e6
            result["resets"] = rig.resets
            if isinstance(rig.target, FaultyLinkTarget) and rig.target.transport is not None:
                result["figures"].update({f"link_{k}": float(v) for k, v in rig.target.transport.counts.items()})
    result["wall_s"] = time.monotonic() - started
    result["cpu_s"] = _cpu_s() - cpu0  # this process and the firmware's (reaped at stop)
    return result


def save_coverage(rig, artefacts: str | None) -> Path | None:
    """The floor's coverage grid at the run's end, ``<artefacts>/coverage.npz`` (``covered``
    and ``free`` cells, the grid's ``extent`` in metres, the ``start`` and ``end`` poses):
    what the report's map of a worst run draws. None for a plant without a grid."""
    plant = rig.plant
    grid = plant.coverage_grid()
    if grid is None or not artefacts:
        return None
    grid.flush()
    path = safefs.make_folder(Path(artefacts)) / COVERAGE_FILE
    extent = (grid.x0_m, grid.x0_m + grid.nx * grid.cell_m, grid.y0_m, grid.y0_m + grid.ny * grid.cell_m)
    truth = rig.truth()
    start = plant.start_pose or (0, 0, 0)
    with safefs.open_write(path, "wb") as f:  # (a link at the name: refused)
        np.savez_compressed(
            f,
            covered=grid.covered & grid.free,
            free=grid.free,
            extent=np.array(extent, dtype=float),
            start=np.array(start[:3], dtype=float),
            end=np.array([truth.get("x_m", np.nan), truth.get("y_m", np.nan), truth.get("theta_rad", np.nan)]),
        )
    return path


def _cpu_s() -> float:
    me, children = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return me.ru_utime + me.ru_stime + children.ru_utime + children.ru_stime


def task_spec(task: dict) -> RigSpec:
    """The rig a task runs: its rig, world, seed, fault set and placement."""
    return RigSpec(
        task["rig"],
        world=task["world"],
        seed=task["seed"],
        faults=task["faults"],
        placement=task.get("placement") or {},
        busy_poll=task.get("busy_poll", True),
    )


def _watch(task: dict, started: float):
    """The run's progress callback: a RunTimeout once the run has taken its timeout_s of wall time."""
    deadline = started + task["timeout_s"]

    def watch_the_clock(t_us: int, t_end_us: int) -> None:
        if time.monotonic() > deadline:
            raise RunTimeout(
                f"the run took more than {task['timeout_s']:g} s of wall time (at virtual t={t_us / 1e6:.1f} s of "
                f"{task['seconds']:g} s); expected it within its timeout_s"
            )

    return watch_the_clock


def _make_rig(task: dict, artefacts: str | None, record: bool, started: float) -> tuple[Rig, list[int]]:
    """The rig with the run's faults, and the virtual times of its brown-outs."""
    spec = task_spec(task)
    recording = Recording(
        trace=record, record=record, artefacts=Path(artefacts) if artefacts else None, progress=_watch(task, started)
    )
    rig = Rig(spec, recording)
    schedule = fault_schedule(spec, rig.app)
    return rig, sorted(round(f.at_s * 1e6) for f in schedule if f.kind == "brownout")


def _drive(rig: Rig, task: dict, cuts: list[int]) -> bool:
    """Run to ``seconds`` in steps of ``step_s``, cutting the power at each brown-out;
    True once ``until`` is on the console (or, without one, at the end)."""
    end_us = round(task["seconds"] * 1e6)
    step_us = round(task["step_s"] * 1e6)
    until = task.get("until")
    while rig.t_us < end_us:
        stop = min(rig.t_us + step_us, end_us, *[_at(c) for c in cuts if _at(c) > rig.t_us] or [end_us])
        rig.run_until(stop)
        while cuts and rig.t_us >= _at(cuts[0]):
            cut = cuts.pop(0)
            if isinstance(cut, tuple):  # (a set's: the board it names)
                rig.power_cycle(cut[1])
            else:
                brownout(rig)
        if until and until in rig.console:
            return True
    return not until


def _at(cut) -> int:
    """A brown-out's instant: a one-board rig's (an instant), a set's ((instant, board))."""
    return cut[0] if isinstance(cut, tuple) else cut


def _is_set(task: dict) -> bool:
    from host.rig.config.boardfile import names_boards

    return str(task["rig"]).endswith(".toml") and names_boards(task["rig"])


class SetRun:
    """A set of boards as a campaign's run sees a rig: the set's clock and plant, every
    board's console (each line after its board's name), the budgets across boards and each
    board's as ``<board>:<name>``, the brown-outs of every board."""

    def __init__(self, boards, progress):
        self.boards = boards
        self.progress = progress
        self.plant = boards.plant
        self.brownouts = list(boards.brownouts)
        self.app = next(r.app for r in boards.rigs.values() if hasattr(r, "app"))
        self.target = None

    @property
    def budgets(self) -> dict:
        """(Read anew: a board that browns out has budgets anew.)"""
        found = dict(self.boards.budgets)
        for name, rig in self.boards.rigs.items():
            found.update({f"{name}:{b}": budget for b, budget in getattr(rig, "budgets", {}).items()})
        return found

    @property
    def t_us(self) -> int:
        return self.boards.t_us

    @property
    def console(self) -> str:
        return "".join(
            f"{name}: {line}\n" for name, rig in self.boards.rigs.items() for line in rig.console.splitlines()
        )

    @property
    def resets(self) -> int:
        return sum(getattr(rig, "resets", 0) for rig in self.boards.rigs.values())

    def truth(self) -> dict:
        return self.boards.truth()

    def start(self) -> None:
        self.boards.start()

    def stop(self) -> None:
        self.boards.stop()

    def run_until(self, t_us: int) -> None:
        self.progress(self.t_us, t_us)
        self.boards.run_until(t_us)

    def power_cycle(self, board: str) -> None:
        self.boards.power_cycle(board)


def _make_set(task: dict, artefacts: str | None, record: bool, started: float) -> SetRun:
    """A set of boards with the run's faults (each harness fault on its board, the others on
    the one plant), its brown-outs as (instant, board)."""
    from host.rig.config.boardfile import load_boards
    from host.rig.loop.boardset import BoardSet

    boards = BoardSet(
        load_boards(task["rig"]),
        seed=task["seed"],
        world=task["world"],
        faults=task["faults"],
        artefacts=Path(artefacts) if artefacts else None,
        trace=record,
        record=record,
    )
    return SetRun(boards, _watch(task, started))


def _budget(budget) -> dict:
    stats = budget.stats()
    return {k: stats.get(k) for k in ("count", "p50", "p99", "max", "misses")}

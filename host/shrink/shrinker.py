"""Shrinks a failing campaign task to a minimal one that fails the same way
(``docs/testing-tools.md``): three phases, each keeping only candidates whose run has the
original's failure signature (:mod:`.signature`).

1. **Faults**: ddmin over the fault list (:mod:`.ddmin`). A fault taken out leaves an
   empty slot behind (a brown-out at 10^9 s, which never comes), so every fault left keeps
   its place in the schedule and with it its random stream; at the end the slots are
   taken out too when the run still fails the same way without them.
2. **Windows**: each fault left that has a window (``start_s``, ``end_s``) is cut, in
   rounds, to its later half, its earlier half or its middle half (tried in that order,
   together: shorter, and later where it can), then trimmed by a quarter at either end,
   until no cut fails the same way or the window is ``resolution_s`` long.
3. **Duration**: the shortest duration (to ``resolution_s``) that still fails the same
   way, three durations tried at once per round (the quartiles of what is left: the
   same answer for any number of workers); windows end with it. Skipped for a failure a
   shorter run has whatever the firmware does (:attr:`.signature.Signature.needs_duration`:
   a deadline, a console text or a coverage the judge wants): a fixed firmware would fail
   the cut run the same way.

A run is refused (ConfigError, nothing shrunk) when it passes when run again, when its
failure is the harness's own (a crash, a setting refused:
:attr:`.signature.Signature.harness_own`), when its judge is not one the shrink knows, or
when the failure needs its whole duration and there is no fault to shrink.
"""

import time
from dataclasses import dataclass, field

from host.campaign.judges import judges
from host.core.errors import ConfigError
from host.shrink.ddmin import ddmin
from host.shrink.runs import Runs
from host.shrink.signature import Signature, signature
from sim_plant.faults import FOREVER_S, KINDS

EMPTY_SLOT = {"kind": "brownout", "at_s": FOREVER_S}
"""What a removed fault leaves in its place: a brown-out that never comes (runs are
at most ten simulated days)."""
MIN_RESOLUTION_S = 0.01
STEPS = 64  # the default resolution: the duration over this
PROBES = 3  # durations tried per round (the same for any number of workers: the same answer)


@dataclass
class Shrunk:
    """What a shrink found: the minimal task, what it removed, what it cost."""

    original: dict
    minimal: dict
    signature: Signature
    kept: list[int]  # the original faults' places that are left
    windows: dict[int, tuple[float, float]]
    runs: int = 0
    tried: int = 0
    wall_s: float = 0.0
    notes: list[str] = field(default_factory=list)

    def removed_rows(self) -> list[dict]:
        """A row per fault and one for the duration: what it was, what is left."""
        rows = []
        for i, fault in enumerate(self.original["faults"]):
            what = f"faults[{i}] {_label(fault)}"
            if i not in self.kept:
                rows.append({"what": what, "before": _window_text(fault, self.original), "after": "removed"})
            else:
                start, end = self.windows.get(i, (None, None))
                after = f"{start:g}-{min(end, self.minimal['seconds']):g} s" if start is not None else "kept"
                rows.append({"what": what, "before": _window_text(fault, self.original), "after": after})
        rows.append(
            {"what": "duration", "before": f"{self.original['seconds']:g} s", "after": f"{self.minimal['seconds']:g} s"}
        )
        return rows


class Shrinker:
    """Shrinks ``task`` (which must fail) with ``runs``; ``say(text)`` hears the progress."""

    def __init__(self, task: dict, runs: Runs, say=lambda text: None, resolution_s: float | None = None):
        self.task = task
        self.runs = runs
        self.say = say
        self.faults = list(task["faults"])
        self.resolution_s = resolution_s or max(task["seconds"] / STEPS, MIN_RESOLUTION_S)
        self.kept = list(range(len(self.faults)))
        self.windows: dict[int, tuple[float, float]] = {}
        self.seconds = float(task["seconds"])
        self.signature: Signature | None = None
        self.notes: list[str] = []
        self.slots = True  # removed faults leave empty slots (False once they need not)

    # -- the candidates ------------------------------------------------------------
    def build(self, kept=None, windows=None, seconds=None, slots=None) -> dict:
        """The task with these faults (the others as empty slots, or gone), windows and
        duration; a window ends with the run."""
        kept = self.kept if kept is None else kept
        windows = self.windows if windows is None else windows
        seconds = self.seconds if seconds is None else seconds
        slots = self.slots if slots is None else slots
        faults = []
        for i, fault in enumerate(self.faults):
            if i in kept:
                fault = dict(fault)
                if i in windows:
                    fault["start_s"], fault["end_s"] = windows[i][0], min(windows[i][1], seconds)
                faults.append(fault)
            elif slots:
                faults.append(dict(EMPTY_SLOT))
        while slots and faults and faults[-1] == EMPTY_SLOT:
            faults.pop()  # (a slot after the last fault keeps no place)
        return {**self.task, "faults": faults, "seconds": round(seconds, 6)}

    def same(self, tasks: list[dict]) -> list[bool]:
        """Whether each task fails as the original did."""
        results = self.runs.run(tasks)
        return [signature(r, t["judge"]) == self.signature for r, t in zip(results, tasks)]

    def _progress(self, phase: str) -> None:
        windows = ", ".join(f"[{i}] {a:g}-{b:g} s" for i, (a, b) in sorted(self.windows.items()))
        self.say(
            f"shrink {phase}: {self.runs.runs} runs so far; {len(self.kept)} of {len(self.faults)} faults"
            f"{' (' + windows + ')' if windows else ''}, {self.seconds:g} s"
        )

    # -- the phases ----------------------------------------------------------------
    def shrink(self) -> Shrunk:
        started = time.monotonic()
        known = judges()
        if self.task["judge"] not in known:
            raise ConfigError(
                f"judge {self.task['judge']!r}: a shrink knows only the judges {', '.join(sorted(known))} "
                "(what each failure means, so that a candidate fails the same way)"
            )
        first = self.runs.run([self.build()])[0]
        self.signature = signature(first, self.task["judge"])
        if self.signature is None:
            raise ConfigError("the run passed when run again: nothing to shrink (expected a failing run)")
        if self.signature.harness_own:
            raise ConfigError(
                f"the run fails with the harness's own error, not the firmware's ({_first_line(first)}); "
                "expected a failure of the firmware or its judge: nothing to shrink"
            )
        if self.signature.needs_duration and not self.faults:
            raise ConfigError(
                f"the run fails as {self.signature}: a shorter run fails so whatever the firmware does, and the run "
                "has no faults to take out: nothing can be shrunk soundly"
            )
        self.say(f"shrink: the run fails as {self.signature}")
        self.shrink_faults()
        self.shrink_windows()
        self.shrink_duration()
        self.drop_slots()
        minimal = self.build()
        return Shrunk(
            self.task, minimal, self.signature, list(self.kept), dict(self.windows),
            self.runs.runs, self.runs.tried, time.monotonic() - started, self.notes,
        )  # fmt: skip

    def shrink_faults(self) -> None:
        def fails(candidates: list[list]) -> list[bool]:
            answer = self.same([self.build(kept=c) for c in candidates])
            self.say(f"shrink faults: tried {len(candidates)} sets of {', '.join(str(len(c)) for c in candidates)}")
            return answer

        self.kept = ddmin(self.kept, fails)
        self._progress("faults")

    def shrink_windows(self) -> None:
        for i in list(self.kept):
            fault = self.faults[i]
            if "start_s" not in KINDS[fault["kind"]]:
                continue
            start = float(fault.get("start_s", 0.0))
            end = min(float(fault.get("end_s", FOREVER_S)), self.seconds)
            if end <= start:  # (a window after the run's end: the fault never acts, nothing to cut)
                continue
            self.windows[i] = (start, end)
            while True:
                cut = self._cut(i, *self.windows[i])
                if cut is None:
                    break
                self.windows[i] = cut
            self._progress(f"window of faults[{i}]")

    def _cut(self, i: int, start: float, end: float) -> tuple[float, float] | None:
        """A shorter window of fault ``i`` that still fails the same way, or None."""
        width = end - start
        if width <= self.resolution_s:
            return None
        half, quarter = width / 2, width / 4
        rounds = [
            [(start + half, end), (start, start + half), (start + quarter, end - quarter)],
            [(start + quarter, end), (start, end - quarter)],
        ]
        for cuts in rounds:
            cuts = [(round(a, 6), round(b, 6)) for a, b in cuts]
            tasks = [self.build(windows={**self.windows, i: c}) for c in cuts]
            for cut, ok in zip(cuts, self.same(tasks)):
                if ok:
                    return cut
        return None

    def shrink_duration(self) -> None:
        if self.signature.needs_duration:
            what = "the judge's deadline" if self.signature.deadline else "something the judge wants did not happen"
            self.notes.append(f"duration kept: the failure is {what} (a shorter run fails so whatever happens)")
            return
        low = max([a for a, _ in self.windows.values()] + [0.0])  # (no shorter: a window would start after the end)
        high = self.seconds
        while high - low > self.resolution_s:
            probes = sorted({round(low + (high - low) * j / (PROBES + 1), 3) for j in range(1, PROBES + 1)})
            answers = self.same([self.build(seconds=p) for p in probes])
            failing = [p for p, ok in zip(probes, answers) if ok]
            high = min(failing + [high])
            low = max([p for p, ok in zip(probes, answers) if not ok and p < high] + [low])
        self.seconds = high
        self._progress("duration")

    def drop_slots(self) -> None:
        """Take out the empty slots of removed faults when the run fails the same way
        without them (the faults after them take other random streams)."""
        with_slots, without = self.build(), self.build(slots=False)
        if with_slots["faults"] == without["faults"]:
            return
        if self.same([without])[0]:
            self.slots = False
            return
        self.notes.append(
            "empty slots kept: without them the faults after them draw other random numbers and the run "
            "does not fail the same way"
        )


def _label(fault: dict) -> str:
    what = fault.get("signal") or fault.get("wheel") or fault.get("direction") or fault.get("at_s") or fault.get("size")
    return f"{fault['kind']} {what}" if what is not None else fault["kind"]


def _window_text(fault: dict, task: dict) -> str:
    if "start_s" not in KINDS[fault["kind"]]:
        return "-"
    start = float(fault.get("start_s", 0.0))
    end = min(float(fault.get("end_s", FOREVER_S)), task["seconds"])
    return f"{start:g}-{end:g} s"


def _first_line(result: dict) -> str:
    lines = (result.get("message") or "").strip().splitlines()
    return lines[0][:300] if lines else str(result.get("error"))

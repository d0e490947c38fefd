"""What a live rig was given, in order: every stop of its clock and every poke at one
(``docs/live.md``, "Snapshots"). The interpreter cannot save itself, so a snapshot is a
place in this journal, and restoring it starts the rig again and replays the journal to
there: the same calls at the same virtual instants give the same run (its link trace
digest says so), firmware state included.

An entry is a tuple: ``("to", t_us)`` the rig served to that instant; ``("set", part,
control, value)`` a part's control set; ``("stdin", bytes)`` bytes on the console's input;
``("eval", line, source)`` an expression read or a REPL line run in the paused firmware;
``("fault", entry)`` a fault injected (it lives in the replayed rig's spec: nothing to do
when replaying)."""

from dataclasses import dataclass

from host.rig.loop.introspect import FirmwareEvalError, firmware_eval
from host.scenario.runner import write_console


@dataclass(frozen=True)
class Snapshot:
    """A place in a live rig's journal: its instant, how many entries led there, and the
    link trace's digest then (None unless the rig traces)."""

    t_us: int
    entries: int
    trace_digest: str | None


def apply(rig, entry: tuple):
    """Give ``rig`` one journal entry; what it gives back (an eval's status and text)."""
    kind = entry[0]
    if kind == "to":
        return rig.run_until(entry[1])
    if kind == "set":
        return rig.plant.set_control(*entry[1:])
    if kind == "stdin":
        return write_console(rig, entry[1])
    if kind == "eval":
        return firmware_eval(rig, entry[2], line=entry[1])
    return None  # ("fault": in the spec)


def replay(rig, entries: list) -> None:
    """The journal's entries again, on a rig started afresh (an eval that raised raises
    again: it is the firmware's, the run goes on as it did)."""
    for entry in entries:
        try:
            apply(rig, entry)
        except FirmwareEvalError:
            pass


def faults(entries: list) -> list[dict]:
    """The fault entries injected along ``entries``, in order."""
    return [entry[1] for entry in entries if entry[0] == "fault"]

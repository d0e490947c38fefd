"""``mpy-fil shrink RUN`` and ``mpy-fil campaign --shrink``: shrink a failing run (or each
distinct failure of a campaign), write the minimal run as a one-run campaign, and say
how to run it again (``docs/testing-tools.md``). The command line hands in ``say``, the
only way out to the terminal."""

import json
from pathlib import Path

from host.campaign.scenario import Campaign, task_key
from host.campaign.store import CAMPAIGN
from host.core import safefs
from host.core.errors import ConfigError
from host.report.table import format_table
from host.shrink.runs import Runs
from host.shrink.shrinker import Shrinker, Shrunk
from host.shrink.signature import signature
from host.shrink.source import find_run

MINIMAL = "minimal"
REPORT = "shrink.json"
COLUMNS = ("what", "before", "after")


def write_minimal(shrunk: Shrunk, out: Path) -> str:
    """``out/campaign.json`` (the minimal run, a campaign of one run) and ``out/shrink.json``
    (what was removed, the signature, the cost); the command that runs it again."""
    task = shrunk.minimal
    campaign = Campaign(
        rig=task["rig"], name=MINIMAL, seconds=task["seconds"], until=task.get("until"), step_s=task["step_s"],
        judge=task["judge"], worlds=[task["world"]], seeds=1, first_seed=task["seed"], timeout_s=task["timeout_s"],
        budgets=list(task.get("budgets") or []), figures=list(task.get("figures") or []),
        placement=dict(task.get("placement") or {}), faultsets={MINIMAL: task["faults"]},
    )  # fmt: skip
    out = safefs.make_folder(out)  # (made by the caller; a link put there since is refused)
    safefs.write_text(out / CAMPAIGN, json.dumps(campaign.to_dict(), indent=1, default=str) + "\n")
    key = task_key({**task, "faultset": MINIMAL})
    command = f"mpy-fil campaign --replay {key} --out {out}"
    report = {
        "signature": shrunk.signature.to_dict(),
        "command": command,
        "original": shrunk.original,
        "minimal": task,
        "removed": shrunk.removed_rows(),
        "runs": shrunk.runs,
        "tried": shrunk.tried,
        "wall_s": round(shrunk.wall_s, 3),
        "notes": shrunk.notes,
    }
    safefs.write_text(out / REPORT, json.dumps(report, indent=1, default=str) + "\n")
    return command


def shrink_task(task: dict, out: Path, *, workers: int, say, resolution_s: float | None = None) -> tuple[Shrunk, str]:
    """Shrink one task; the result and the command that runs the minimal run again."""
    with Runs(workers) as runs:
        shrunk = Shrinker(task, runs, say, resolution_s).shrink()
    command = write_minimal(shrunk, out)
    say(f"shrunk in {shrunk.runs} runs ({shrunk.tried} asked for, the rest known), {shrunk.wall_s:.1f} s of wall time")
    say(f"fails as: {shrunk.signature}")
    say(format_table(shrunk.removed_rows(), COLUMNS))
    for note in shrunk.notes:
        say(f"note: {note}")
    say(f"minimal run: {out / CAMPAIGN}")
    say(f"run it again (traced): {command}")
    return shrunk, command


def shrink_command(args, say) -> int:
    """``mpy-fil shrink RUN``: 0 when shrunk (the minimal run still fails the same way)."""
    source = find_run(args.run, app=args.app, trust_folder=args.trust_folder)
    default = _default_out(source.label)
    out = safefs.output_folder(
        Path(args.out) if args.out else default,
        what="--out",
        inputs={"the run RUN": args.run},
        base=None if args.out else default.parent.parent.parent,  # (the folder build/shrink/ is in)
    )
    say(f"shrink {source.label}: {len(source.task['faults'])} faults, {source.task['seconds']:g} s; out {out}")
    if source.result is not None and source.result.get("passed"):
        say("note: the campaign recorded this run as passed")
    shrink_task(source.task, out, workers=args.workers, say=say, resolution_s=args.resolution)
    return 0


def _default_out(label: str) -> Path:
    from host.core.paths import output_root

    name = "-".join(p for p in Path(label).parts[-3:] if p not in ("/",))
    return output_root(None) / "shrink" / name


def shrink_campaign(campaign: Campaign, results: list[dict], out: Path, *, workers: int, say) -> list[dict]:
    """``campaign --shrink``: each distinct failure signature of the campaign's results,
    the first run (by seed) that has it, shrunk into ``out/shrink/<n>``. A row per
    signature: how many runs failed so, which was shrunk, into what, with what command."""
    tasks = {task_key(t): t for t in campaign.tasks()}
    groups: dict = {}
    for result in sorted(results, key=lambda r: (r["faultset"], r["world"], r["seed"])):
        sig = signature(result, campaign.judge)
        if sig is not None and result["key"] in tasks:
            groups.setdefault(sig, []).append(result["key"])
    rows = []
    for n, (sig, keys) in enumerate(groups.items(), start=1):
        say(f"shrink {n} of {len(groups)}: {keys[0]} ({len(keys)} run(s) failed as {sig})")
        folder = safefs.make_folder(Path(out) / "shrink" / str(n), base=out)
        try:
            shrunk, command = shrink_task(tasks[keys[0]], folder, workers=workers, say=say)
        except ConfigError as e:  # (refused: the harness's own failure, a judge it cannot shrink soundly)
            say(f"shrink {n} of {len(groups)}: refused: {e}")
            rows.append({"signature": str(sig), "runs_failed": len(keys), "shrunk": keys[0], "refused": str(e)})
            continue
        rows.append(
            {
                "signature": str(sig), "runs_failed": len(keys), "shrunk": keys[0],
                "faults": f"{len(shrunk.original['faults'])} -> {len(shrunk.kept)}",
                "seconds": f"{shrunk.original['seconds']:g} -> {shrunk.minimal['seconds']:g}",
                "shrink_runs": shrunk.runs, "command": command,
            }
        )  # fmt: skip
    if not groups:
        say("campaign --shrink: no run failed, nothing to shrink")
    return rows

"""The run to shrink, as a campaign task: from a campaign's run (its folder under the
campaign's ``runs/`` or ``replay/``, or ``CAMPAIGN/faultset/world/seed``), or from any
recorded run's trace folder (its header's spec: rig, world, seed, faults, placement; its
duration; judged as a campaign of that rig would be)."""

import json
from dataclasses import dataclass
from pathlib import Path

from host.artefacts.folder import HEADER, load_trace, set_boards
from host.campaign.scenario import Campaign, load_campaign, task_key
from host.campaign.store import CAMPAIGN, ResultStore
from host.core.errors import ConfigError
from host.core.paths import REPO
from sim_plant.faults import FaultError, parse_faults

SUBFOLDERS = ("runs", "replay")
TRACE_FAULTSET = "trace"


@dataclass
class Source:
    task: dict
    label: str  # what the user named, for messages
    result: dict | None = None  # the campaign's own result of the run, when there is one


def find_run(text: str, *, app: str | None = None, trust_folder: bool = False) -> Source:
    """The task of the run ``text`` names; a ConfigError (one line) when it names none."""
    path = Path(text)
    found = _in_campaign(path)
    if found is not None:
        return found
    if (path / HEADER).is_file():
        return _from_trace(path, app, trust_folder)
    if set_boards(path):
        return _from_set(path, app, trust_folder)
    raise ConfigError(
        f"RUN {text}: expected a trace folder (with {HEADER}), a set of boards' run folder (a trace folder a "
        "board), a campaign's run folder (CAMPAIGN/runs/faultset/world/seed) or CAMPAIGN/faultset/world/seed"
    )


def _in_campaign(path: Path) -> Source | None:
    """``path`` under a folder holding ``campaign.json``: that campaign's task for the key
    the rest of the path spells."""
    path = path.absolute()
    for folder in path.parents:
        if (folder / CAMPAIGN).is_file():
            rest = path.relative_to(folder).parts
            rest = rest[1:] if rest and rest[0] in SUBFOLDERS else rest
            return campaign_run(folder, "/".join(rest))
    return None


def campaign_run(folder: Path, key: str) -> Source:
    """Run ``key`` of the campaign in ``folder``, with its stored result."""
    try:
        campaign = Campaign(**json.loads((folder / CAMPAIGN).read_text(encoding="utf-8")))
    except (OSError, ValueError, TypeError, RecursionError) as e:
        raise ConfigError(f"RUN: {folder / CAMPAIGN} cannot be read ({type(e).__name__}: {e})") from None
    tasks = {task_key(t): t for t in campaign.tasks()}
    if key not in tasks:
        some = ", ".join(list(tasks)[:3])
        raise ConfigError(f"RUN: no run {key!r} in the campaign {folder} (runs are faultset/world/seed, e.g. {some})")
    stored = {r["key"]: r for r in ResultStore(folder).read()}
    return Source(tasks[key], f"{folder}/{key}", stored.get(key))


def _from_trace(folder: Path, app: str | None, trust_folder: bool) -> Source:
    from host.rig.config.apps import apps

    header = load_trace(folder).header
    spec = header.get("spec") or {}
    _check_spec(folder, spec)
    if spec.get("mode", "lockstep") != "lockstep":
        raise ConfigError(f"RUN {folder}: a {spec.get('mode')} run; expected a lockstep run (its runs repeat)")
    if spec.get("options"):
        raise ConfigError(f"RUN {folder}: the run had plant options {spec['options']} (--param); a shrink sets none")
    rig = app or spec.get("app") or header.get("app")
    if not isinstance(rig, str) or not rig:
        raise ConfigError(f"RUN {folder}: {HEADER} names no rig (spec.app)")
    if app is None and rig not in apps() and not trust_folder:
        raise ConfigError(
            f"RUN {folder}: the trace's header names a rig file to run ({rig}); a shrink runs only a firmware "
            "you name: --app RIG, or --trust-folder to run the one the header names"
        )
    if rig not in apps() and not Path(rig).is_absolute() and not Path(rig).exists() and (REPO / rig).exists():
        rig = str(REPO / rig)
    seconds = header["t_end_us"] / 1e6
    campaign = load_campaign(
        rig, seeds=1, first_seed=int(spec.get("seed", header.get("seed", 0))), seconds=seconds, step_s=min(1.0, seconds)
    )
    if spec.get("world"):
        campaign.worlds = [spec["world"]]
    campaign.faultsets = {TRACE_FAULTSET: list(spec.get("faults") or [])}
    campaign.placement = dict(spec.get("placement") or {})
    return Source(campaign.tasks()[0], str(folder))


def _from_set(folder: Path, app: str | None, trust_folder: bool) -> Source:
    """A set of boards' run folder (docs/multi-board.md): its rig file, seed and world as its
    boards' headers name them (each ``<rig file>::<board>``), its duration the longest of
    theirs, each board's harness faults naming it; judged as a campaign of that rig file."""
    specs, ends = {}, []
    for board in set_boards(folder):
        header = load_trace(folder / board).header
        specs[board] = header.get("spec") or {}
        _check_spec(folder / board, specs[board])
        ends.append(header["t_end_us"])
    rigs = {str(spec.get("app", "")).rpartition("::")[0] for spec in specs.values()}
    seeds = {spec.get("seed") for spec in specs.values()}
    worlds = {spec.get("world") for spec in specs.values()}
    if len(rigs) != 1 or "" in rigs or len(seeds) != 1 or len(worlds) != 1:
        raise ConfigError(f"RUN {folder}: its boards' headers name different rig files, seeds or worlds ({rigs})")
    rig = app or rigs.pop()
    if app is None and not trust_folder:
        raise ConfigError(
            f"RUN {folder}: the boards' headers name a rig file to run ({rig}); a shrink runs only a firmware "
            "you name: --app RIG, or --trust-folder to run the one the headers name"
        )
    if not Path(rig).is_absolute() and not Path(rig).exists() and (REPO / rig).exists():
        rig = str(REPO / rig)
    seconds = max(ends) / 1e6
    campaign = load_campaign(rig, seeds=1, first_seed=int(seeds.pop() or 0), seconds=seconds, step_s=min(1.0, seconds))
    world = worlds.pop()
    if world:
        campaign.worlds = [world]
    faults = [{**f, "board": board} for board, spec in specs.items() for f in spec.get("faults") or ()]
    campaign.faultsets = {TRACE_FAULTSET: faults}
    return Source(campaign.tasks()[0], str(folder))


def _check_spec(folder: Path, spec: dict) -> None:
    """The header's spec as a shrink reads it: faults the harness can apply, a world's name,
    a placement table; else a ConfigError naming the field (never a run of the harness
    failing on it, shrunk as if it were the firmware's failure)."""
    where = f"RUN {folder}: {HEADER} spec"
    try:
        parse_faults([] if spec.get("faults") is None else spec["faults"])
    except FaultError as e:
        raise ConfigError(f"{where}.{e}; expected the faults a recorded run lists (docs/campaigns.md)") from None
    for name, kinds in (("world", (str, type(None))), ("placement", (dict, type(None))), ("seed", (int, type(None)))):
        if not isinstance(spec.get(name), kinds) or isinstance(spec.get(name), bool):
            raise ConfigError(f"{where}.{name}: expected {kinds[0].__name__}, got {spec.get(name)!r:.80}")

"""A campaign as data: which rig, how each run goes and is judged, and the seeds, fault
sets and worlds it crosses (``docs/campaigns.md``).

A campaign is a rig (an app's name or a rig file) or a scenario file: TOML with a
``[campaign]`` table and fault sets::

    [campaign]
    rig = "duct"              # an app, or a rig file's path (relative to this file)
    seconds = 90              # simulated seconds at most per run
    until = "explored:"       # the run ends early once the console shows this
    step_s = 2.0              # how often it looks
    judge = "duct_branch"     # how a run is judged (host/campaign/judges.py, or the catalogue's)
    worlds = ["one-right-branch"]
    seeds = 20
    timeout_s = 300           # wall seconds a run may take before it counts as hung
    budgets = ["control.period"]   # budgets a run must keep to pass
    worst_by = "home_off_m"   # the figure that ranks the worst runs (default: the judge's own)
    expected = { snags = 0.9 }     # a showcase's known pass rate per fault set ...
    explained = "docs/campaigns.md, The duct robot and its tether"   # ... and where it is explained

    [[faultsets]]             # none, or one named set of [[faultsets.faults]] each
    name = "snags"
    [[faultsets.faults]]
    kind = "tether_snag"
    rate = 0.3

A file of ``[[faults]]`` alone (``--faults``) is one fault set named after the file.
Every mistake is a ConfigError naming the file and the field.
"""

from dataclasses import dataclass, field
from pathlib import Path

from host.core.errors import ConfigError
from host.rig.config import arguments
from host.rig.config.app import Judge
from host.rig.config.apps import get_app
from host.rig.config.tomlfile import read_toml
from host.rig.loop.spec import RigSpec, build_plant
from sim_plant.faults import FaultError, parse_faults, with_faults
from sim_plant.plant import check_contract

CAMPAIGN_KEYS = {
    "rig": str,
    "seconds": (int, float),
    "until": str,
    "step_s": (int, float),
    "judge": str,
    "worlds": list,
    "seeds": int,
    "first_seed": int,
    "timeout_s": (int, float),
    "budgets": list,
    "worst_by": str,
    "worst_low": bool,
    "expected": dict,
    "explained": str,
    "figures": list,
    "placement": dict,
}
PLACEMENT_KEYS = ("x_m", "y_m", "theta_deg")
MAX_SEEDS = 100_000


@dataclass
class Campaign:
    rig: str  # an app's name or a rig file's path
    name: str
    seconds: float = 60.0
    until: str | None = None
    step_s: float = 1.0
    judge: str = ""  # default: "declared" for a rig file with [report.judge], else "generic"
    worlds: list[str] = field(default_factory=list)  # default: the rig's first world
    seeds: int = 10
    first_seed: int = 1
    timeout_s: float = 600.0
    budgets: list[str] = field(default_factory=list)
    worst_by: str | None = None
    worst_low: bool | None = None  # the worst runs have the lowest worst_by; default: the figure's direction
    expected: dict = field(default_factory=dict)  # fault set -> the pass rate a showcase is known to give
    explained: str | None = None  # where that rate is explained (docs/campaigns.md, a section)
    figures: list[str] = field(default_factory=list)  # truth fields recorded as figures
    placement: dict = field(default_factory=dict)  # x_m, y_m, theta_deg: [low, high] added to the start pose
    faultsets: dict[str, list] = field(default_factory=lambda: {"none": []})  # name -> raw [[faults]] tables
    source: str | None = None  # the scenario file

    def seed_list(self) -> list[int]:
        return list(range(self.first_seed, self.first_seed + self.seeds))

    def tasks(self) -> list[dict]:
        """One task per (fault set, world, seed): what a worker needs, as plain data."""
        common = {
            "rig": self.rig,
            "seconds": self.seconds,
            "until": self.until,
            "step_s": self.step_s,
            "judge": self.judge,
            "timeout_s": self.timeout_s,
            "budgets": self.budgets,
            "figures": self.figures,
            "placement": self.placement,
        }
        return [
            {**common, "faultset": name, "faults": faults, "world": world, "seed": seed}
            for name, faults in self.faultsets.items()
            for world in self.worlds
            for seed in self.seed_list()
        ]

    def to_dict(self) -> dict:
        return {k: getattr(self, k) for k in self.__dataclass_fields__}


def task_key(task: dict) -> str:
    """``faultset/world/seed``: a run's name in the results, and what --replay takes."""
    return f"{task['faultset']}/{task['world']}/{task['seed']}"


def load_campaign(target: str, *, faults_file: str | None = None, **overrides) -> Campaign:
    """A campaign from a scenario file, or from a rig (app or rig file) and defaults;
    ``overrides`` (seeds, worlds, seconds, ...) come from the command line."""
    path = Path(target)
    data: dict = {}
    if path.suffix == ".toml" and path.is_file():
        data = read_toml(path)
    if "campaign" in data:
        table = _table(path, data["campaign"])
        rig = table.pop("rig", None)
        if rig is None:
            raise ConfigError(f"{path}: [campaign] rig: missing (an app's name or a rig file's path)")
        if rig.endswith(".toml") and not Path(rig).is_absolute():
            rig = str((path.parent / rig).resolve())
        campaign = Campaign(rig=rig, name=path.stem, source=str(path), **table)
        campaign.faultsets = _faultsets(path, data) or campaign.faultsets
    else:
        campaign = Campaign(rig=target, name=path.stem if path.suffix == ".toml" else target)
    if faults_file:
        fpath = Path(faults_file)
        campaign.faultsets = _faultsets(fpath, read_toml(fpath)) or {"none": []}
    for key, value in overrides.items():
        if value is not None:
            setattr(campaign, key, value)
    _check(campaign)
    return campaign


def _table(path: Path, table) -> dict:
    if not isinstance(table, dict):
        raise ConfigError(f"{path}: [campaign]: expected a table")
    for key, value in table.items():
        if key not in CAMPAIGN_KEYS:
            raise ConfigError(f"{path}: [campaign] {key}: unknown key (known: {', '.join(CAMPAIGN_KEYS)})")
        types = CAMPAIGN_KEYS[key]
        if isinstance(value, bool) and types is not bool or not isinstance(value, types):
            raise ConfigError(f"{path}: [campaign] {key}: expected {types}, got {value!r}")
    return dict(table)


def _faultsets(path: Path, data: dict) -> dict[str, list]:
    """``[[faultsets]]`` (each a name and its [[faultsets.faults]]) or a plain ``[[faults]]``."""
    sets: dict[str, list] = {}
    if not isinstance(data.get("faultsets", []), list):
        raise ConfigError(f"{path}: faultsets: expected an array of tables, [[faultsets]]")
    for i, entry in enumerate(data.get("faultsets", [])):
        name = entry.get("name") if isinstance(entry, dict) else None
        if not isinstance(name, str) or not name or "/" in name:
            raise ConfigError(f"{path}: faultsets[{i}] name: expected a name without '/', got {name!r}")
        if name in sets:
            raise ConfigError(f"{path}: faultsets[{i}] name: {name!r} twice")
        sets[name] = _checked(path, f"faultsets[{i}] ({name}) ", entry.get("faults", []))
    if "faults" in data:
        sets[path.stem] = _checked(path, "", data["faults"])
    return sets


def _checked(path: Path, where: str, faults) -> list:
    """The tables checked as a schedule; a ``board`` (the board a harness fault of a set of
    boards acts on) is checked with the campaign's rig (:func:`_check`)."""
    try:
        parse_faults([{k: v for k, v in f.items() if k != "board"} if isinstance(f, dict) else f for f in faults])
    except FaultError as e:
        raise ConfigError(f"{path}: {where}{e}") from None
    return faults


def _check(campaign: Campaign) -> None:
    from host.rig.config.boardfile import names_boards

    if str(campaign.rig).endswith(".toml") and names_boards(campaign.rig):
        _check_boards(campaign)
        _check_common(campaign)
        return
    app = get_app(campaign.rig)  # (a ConfigError names the rig file and the field)
    judge = app.run.report.judge if app.run.report is not None else None
    campaign.judge = campaign.judge or ("declared" if judge is not None and judge != Judge() else "generic")
    campaign.worlds = campaign.worlds or [next(iter(app.worlds))]
    for world in campaign.worlds:
        if world not in app.worlds:
            raise ConfigError(f"campaign worlds: {app.name} has no world {world!r} (worlds: {', '.join(app.worlds)})")
    for name, faults in campaign.faultsets.items():  # each set fits the rig's plant
        try:
            for world in campaign.worlds:
                build_plant(RigSpec(app, world=world, faults=faults), app)
        except FaultError as e:
            raise ConfigError(f"{campaign.source or campaign.rig}: fault set {name!r}: {e}") from None
    _check_placement(campaign)
    _check_expected(campaign)
    known = [b.name for b in app.make_budgets(build_plant(RigSpec(app, world=campaign.worlds[0]), app)[0])]
    for name in campaign.budgets:
        if name not in known:
            raise ConfigError(f"campaign budgets: {app.name} has no budget {name!r} (budgets: {', '.join(known)})")
    _check_common(campaign)


def _check_boards(campaign: Campaign) -> None:
    """A campaign of a rig file with several boards (docs/multi-board.md): its worlds are the
    file's, its fault sets' harness faults each name a board (``board = "motor"``), its
    budgets are those across boards by name and each board's as ``<board>:<name>``; judged
    ``generic`` or ``no_contact`` (over every board's console and the one plant's truth)."""
    from host.rig.config.boardfile import load_boards
    from host.rig.loop.boardset import split_faults

    boards = load_boards(campaign.rig)
    first = next(iter(boards.firmware().values()))
    campaign.judge = campaign.judge or "generic"
    if campaign.judge not in ("generic", "no_contact"):
        raise ConfigError(f"campaign judge: a set of boards is judged generic or no_contact, got {campaign.judge!r}")
    if campaign.placement:
        raise ConfigError("campaign placement: not for a set of boards (its plant's start pose is the world's)")
    campaign.worlds = campaign.worlds or [next(iter(first.worlds))]
    for world in campaign.worlds:
        if world not in first.worlds:
            known = ", ".join(first.worlds)
            raise ConfigError(f"campaign worlds: {boards.name} has no world {world!r} (worlds: {known})")
    for name, faults in campaign.faultsets.items():  # each set fits the boards and the plant
        try:
            plant_faults, _own = split_faults(boards, faults)
            for world in campaign.worlds:
                with_faults(check_contract(boards.make_plant(**first.worlds[world])), parse_faults(plant_faults))
        except (ConfigError, FaultError) as e:
            raise ConfigError(f"{campaign.source or campaign.rig}: fault set {name!r}: {e}") from None
    _check_expected(campaign)
    known = list(boards.budgets)
    for board, app in boards.firmware().items():
        plant = check_contract(boards.make_plant(**first.worlds[campaign.worlds[0]]))
        known += [f"{board}:{b.name}" for b in app.make_budgets(plant)]
    for name in campaign.budgets:
        if name not in known:
            raise ConfigError(f"campaign budgets: {boards.name} has no budget {name!r} (budgets: {', '.join(known)})")


def _check_common(campaign: Campaign) -> None:
    from host.campaign.judges import judges

    known = judges()  # (the generic ones, ours and the rig's own: its [plant] catalogue is read)
    if campaign.judge not in known:
        raise ConfigError(f"campaign judge: expected one of {', '.join(known)}, got {campaign.judge!r}")
    if not 1 <= campaign.seeds <= MAX_SEEDS:
        raise ConfigError(f"campaign seeds: expected 1 to {MAX_SEEDS}, got {campaign.seeds}")
    arguments.seed(campaign.first_seed)
    arguments.seed(campaign.first_seed + campaign.seeds - 1)
    arguments.seconds("campaign seconds", campaign.seconds, positive=True, limit_s=arguments.MAX_RUN_S)
    arguments.seconds("campaign step_s", campaign.step_s, positive=True)
    arguments.seconds("campaign timeout_s", campaign.timeout_s, positive=True)


def _check_placement(campaign: Campaign) -> None:
    """``placement = {x_m = [-0.3, 0], y_m = [0, 0.3], theta_deg = [-5, 5]}``: ranges of the
    uniform error added to the plant's start pose, drawn per seed."""
    for key, span in campaign.placement.items():
        ok = isinstance(span, list) and len(span) == 2 and all(isinstance(v, (int, float)) for v in span)
        if key not in PLACEMENT_KEYS or not ok or span[0] > span[1]:
            raise ConfigError(
                f"campaign placement {key}: expected one of {', '.join(PLACEMENT_KEYS)} = [low, high], got {span!r}"
            )


def _check_expected(campaign: Campaign) -> None:
    """``expected = { <fault set> = rate }``: each a fault set's name and a rate in [0, 1]."""
    for name, rate in campaign.expected.items():
        if name not in campaign.faultsets:
            known = ", ".join(campaign.faultsets)
            raise ConfigError(f"campaign expected {name}: no such fault set (fault sets: {known})")
        if isinstance(rate, bool) or not isinstance(rate, (int, float)) or not 0 <= rate <= 1:
            raise ConfigError(f"campaign expected {name}: expected a pass rate from 0 to 1, got {rate!r}")

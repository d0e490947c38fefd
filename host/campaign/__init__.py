"""Campaigns: a rig over seeds x fault sets x worlds, in parallel on this machine or a
Dask cluster, with a report of success rates, distributions and the worst runs
(``docs/campaigns.md``).

- :mod:`.scenario`: the campaign as data (a scenario file, or a rig and defaults);
- :mod:`.worker`: one run with its faults, judged; every failure a result;
- :mod:`.judges`: how a run passes, and its figures;
- :mod:`.runner`: the local pool or the Dask cluster, skipping what is done;
- :mod:`.store`: ``results.jsonl``, appended as runs finish;
- :mod:`.report`: Wilson intervals, plots, HTML, CSV and JSON.
"""

from pathlib import Path

from host.campaign.scenario import Campaign, load_campaign, task_key
from host.campaign.store import CAMPAIGN
from host.core import safefs
from host.core.errors import ConfigError
from host.core.nesting import read_json


def replay(out, key: str) -> dict:
    """Run ``key`` (``faultset/world/seed``) of the campaign in ``out`` again, with its
    trace folder (``out/replay/<key>``): the result, as the campaign had it."""
    from host.campaign.worker import run_one

    path = Path(out) / CAMPAIGN
    if not path.is_file():
        raise ConfigError(f"--out {out}: no {CAMPAIGN} (not a campaign's folder)")
    campaign = Campaign(**read_json(path, "campaign file"))
    tasks = {task_key(t): t for t in campaign.tasks()}
    if key not in tasks:
        some = ", ".join(list(tasks)[:3])
        raise ConfigError(f"--replay: no run {key!r} in {out} (runs are faultset/world/seed, e.g. {some})")
    folder = safefs.make_folder(Path(out) / "replay" / key, base=out)  # (replay/ or a part of it a link: refused)
    return run_one(tasks[key], str(folder), record=True)


__all__ = ["Campaign", "load_campaign", "replay", "task_key"]

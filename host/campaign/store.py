"""A campaign's results on disk: ``results.jsonl``, one line per finished run, appended
and flushed as each run ends, so an interrupted campaign keeps what finished and a rerun
skips it (``docs/campaigns.md``). A line cut short by a crash is ignored when read."""

import json
import os
from pathlib import Path

from host.core import safefs
from host.core.errors import ConfigError

RESULTS = "results.jsonl"
CAMPAIGN = "campaign.json"
SAME = ("rig", "seconds", "until", "step_s", "judge", "budgets", "faultsets", "placement", "figures")
"""What a run's result depends on: a folder's results are reused only for the same."""


class ResultStore:
    def __init__(self, folder: Path):
        self.folder = Path(folder)
        self.path = self.folder / RESULTS

    def open(self, campaign: dict) -> None:
        """Start, or go on with, the results of ``campaign`` in this folder; a folder that
        holds another campaign's results is refused (ConfigError)."""
        self.folder = safefs.make_folder(self.folder)  # (made by the command line; a link since: refused)
        self.path = self.folder / RESULTS
        safefs.refuse_link(self.path)  # (appended to, kept across runs: never a file elsewhere)
        self._same(campaign)
        if self.path.is_file() and self.path.stat().st_size:
            with self.path.open("rb+") as f:  # a line the crash cut short stays alone on its line
                f.seek(-1, os.SEEK_END)
                if f.read(1) != b"\n":
                    f.write(b"\n")
        safefs.write_text(self.folder / CAMPAIGN, json.dumps(campaign, indent=1, default=str) + "\n")

    def _same(self, campaign: dict) -> None:
        old_path = self.folder / CAMPAIGN
        if not (old_path.is_file() and self.path.is_file()):
            return
        try:
            old = json.loads(old_path.read_text(encoding="utf-8"))
        except (json.JSONDecodeError, RecursionError):
            return
        new = json.loads(json.dumps(campaign, default=str))
        differ = [k for k in SAME if k != "faultsets" and k in old and old.get(k) != new.get(k)]
        old_sets, new_sets = old.get("faultsets", {}), new.get("faultsets", {})
        if any(old_sets[name] != new_sets[name] for name in set(old_sets) & set(new_sets)):
            differ.append("faultsets")  # (a fault set added is a campaign grown; one changed is another)
        if differ:
            raise ConfigError(
                f"--out {self.folder}: holds the results of another campaign (it differs in {', '.join(differ)}); "
                "expected the same campaign to go on with: give another --out, or delete the folder"
            )

    def read(self) -> list[dict]:
        """Every whole line's result, the last one of each run (a run rerun replaces it)."""
        if not self.path.is_file():
            return []
        by_key: dict[str, dict] = {}
        for line in self.path.read_text(encoding="utf-8").splitlines():
            try:
                result = json.loads(line)
            except (json.JSONDecodeError, RecursionError):
                continue  # (a line the crash cut short)
            if isinstance(result, dict) and "key" in result:
                by_key[result["key"]] = result
        return list(by_key.values())

    def done(self) -> set[str]:
        return {r["key"] for r in self.read()}

    def append(self, result: dict) -> None:
        line = json.dumps(result, default=str) + "\n"
        with safefs.open_write(self.path, "a", encoding="utf-8") as f:
            f.write(line)
            f.flush()
            os.fsync(f.fileno())

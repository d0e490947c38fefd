"""A campaign's results on disk: ``results.jsonl``, one line per finished run, appended
and flushed as each run ends, so an interrupted campaign keeps what finished and a rerun
skips it (``docs/campaigns.md``). A line cut short by a crash is ignored when read."""

import json
import os
from pathlib import Path

RESULTS = "results.jsonl"
CAMPAIGN = "campaign.json"


class ResultStore:
    def __init__(self, folder: Path):
        self.folder = Path(folder)
        self.path = self.folder / RESULTS

    def open(self, campaign: dict) -> None:
        self.folder.mkdir(parents=True, exist_ok=True)
        if self.path.is_file() and self.path.stat().st_size:
            with self.path.open("rb+") as f:  # a line the crash cut short stays alone on its line
                f.seek(-1, os.SEEK_END)
                if f.read(1) != b"\n":
                    f.write(b"\n")
        (self.folder / CAMPAIGN).write_text(json.dumps(campaign, indent=1, default=str) + "\n", encoding="utf-8")

    def read(self) -> list[dict]:
        """Every whole line's result, the last one of each run (a run rerun replaces it)."""
        if not self.path.is_file():
            return []
        by_key: dict[str, dict] = {}
        for line in self.path.read_text(encoding="utf-8").splitlines():
            try:
                result = json.loads(line)
            except json.JSONDecodeError:
                continue  # (a line the crash cut short)
            if isinstance(result, dict) and "key" in result:
                by_key[result["key"]] = result
        return list(by_key.values())

    def done(self) -> set[str]:
        return {r["key"] for r in self.read()}

    def append(self, result: dict) -> None:
        line = json.dumps(result, default=str) + "\n"
        with self.path.open("a", encoding="utf-8") as f:
            f.write(line)
            f.flush()
            os.fsync(f.fileno())

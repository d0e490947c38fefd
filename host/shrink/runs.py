"""The runs a shrink tries: each a campaign task (``host.campaign.scenario``) run by
``host.campaign.worker.run_one``, in this process one after another, or a batch at once
on the campaign's local process pool (``host.campaign.runner.LocalPool``). A task tried
before is not run again (its result is kept by its content)."""

import concurrent.futures as cf
import json

from host.campaign.runner import GUARD_S, LocalPool, failed
from host.campaign.worker import run_one


def task_id(task: dict) -> str:
    """A task's content as text: the same run, the same id."""
    return json.dumps(task, sort_keys=True, default=str)


class Runs:
    """Runs batches of tasks, ``workers`` at once (1: in this process); ``runs`` counts
    those actually run, ``tried`` every task asked for."""

    def __init__(self, workers: int = 1):
        self.workers = max(1, workers)
        self.pool = LocalPool(self.workers, busy_poll=False) if self.workers > 1 else None
        self.cache: dict[str, dict] = {}
        self.runs = 0
        self.tried = 0

    def run(self, tasks: list[dict]) -> list[dict]:
        """Each task's result, in the order given."""
        self.tried += len(tasks)
        todo = {}
        for task in tasks:
            key = task_id(task)
            if key not in self.cache and key not in todo:
                todo[key] = task
        self.runs += len(todo)
        if self.pool is None or len(todo) == 1:
            for key, task in todo.items():
                self.cache[key] = run_one(task)
        else:
            self._on_pool(todo)
        return [self.cache[task_id(t)] for t in tasks]

    def _on_pool(self, todo: dict[str, dict]) -> None:
        futures = {self.pool.submit(task, None): key for key, task in todo.items()}
        limit_s = max(t["timeout_s"] for t in todo.values()) + GUARD_S
        done, late = cf.wait(futures, timeout=limit_s)
        for future in done:
            key = futures[future]
            try:
                self.cache[key] = future.result()
            except Exception as e:  # (the worker process died)
                self.cache[key] = failed(todo[key], "crash", f"the worker running it died: {type(e).__name__}: {e}")
        for future in late:
            key = futures[future]
            self.cache[key] = failed(todo[key], "hung", f"no result within {limit_s:g} s of wall time")
        if late:
            self.pool.restart()

    def close(self) -> None:
        if self.pool is not None:
            self.pool.close()
            self.pool = None

    def __enter__(self):
        return self

    def __exit__(self, *exc) -> None:
        self.close()

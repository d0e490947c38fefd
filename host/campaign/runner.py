"""Runs a campaign's tasks in parallel and stores each result as it comes
(``docs/campaigns.md``).

Two executors, one contract (``submit`` tasks, results as they finish): a local pool of
processes (:class:`concurrent.futures.ProcessPoolExecutor`, the default: no server to
start) and a Dask cluster (:class:`distributed.Client` on a scheduler's address; Dask's
``LocalCluster`` in the tests). Runs already in the results are skipped. A worker
process that dies takes its runs with it: they are run again once, then recorded as
failed; a pool that gives nothing back for ``timeout_s`` + ``GUARD_S`` is stopped and
its runs recorded as hung. The campaign itself never waits without a deadline.
"""

import concurrent.futures as cf
import multiprocessing
import os
import re
import socket
import urllib.parse

from host.campaign.scenario import Campaign, task_key
from host.campaign.store import ResultStore
from host.campaign.worker import run_one
from host.core import safefs
from host.core.children import die_with_parent
from host.core.errors import ConfigError
from host.rig.loop import manifest

GUARD_S = 120.0
MAX_BREAKS = 2
SCHEMES = ("tcp", "tls", "ws", "wss")
"""The schemes of a Dask scheduler's address the harness takes (``tcp`` when none)."""
CONNECT_S = 20.0
HOST_NAME = re.compile(r"(?!-)[A-Za-z0-9-]{1,63}(?<!-)(\.(?!-)[A-Za-z0-9-]{1,63}(?<!-))*\.?")


def scheduler_address(text: str) -> str:
    """``--scheduler``, checked before anything runs: ``[scheme://]host:port`` with a
    scheme of :data:`SCHEMES`, a host name or IP address this machine resolves, a port
    from 1 to 65535. The address, with its scheme; a ConfigError (one line) otherwise."""
    scheme, sep, rest = text.strip().partition("://")
    if not sep:
        scheme, rest = "tcp", text.strip()
    expected = "expected [tcp|tls|ws|wss]://HOST:PORT (a port from 1 to 65535), e.g. tcp://127.0.0.1:8786"
    if scheme not in SCHEMES:
        raise ConfigError(f"--scheduler {text!r}: unknown scheme {scheme!r}; {expected}")
    try:
        parts = urllib.parse.urlsplit("//" + rest)
        host, port = parts.hostname, parts.port
    except ValueError as e:  # (a port out of range or not a number, a bracket unclosed)
        raise ConfigError(f"--scheduler {text!r}: {e}; {expected}") from None
    if not host or port is None or rest != parts.netloc or parts.username is not None or not 0 < port < 65536:
        raise ConfigError(f"--scheduler {text!r}: {expected}")
    if not (HOST_NAME.fullmatch(host) or ":" in host) or len(host) > 253:
        raise ConfigError(f"--scheduler {text!r}: {host!r} is not a host name or IP address; {expected}")
    try:
        socket.getaddrinfo(host, port, type=socket.SOCK_STREAM)
    except (OSError, UnicodeError, ValueError) as e:
        raise ConfigError(f"--scheduler {text!r}: the host {host!r} does not resolve ({e})") from None
    return f"{scheme}://{rest}"


def failed(task: dict, error: str, message: str) -> dict:
    """The result of a run that gave none."""
    return {
        "key": task_key(task),
        "faultset": task["faultset"],
        "world": task["world"],
        "seed": task["seed"],
        "passed": False,
        "error": error,
        "message": message,
        "figures": {},
        "budgets": {},
        "t_end_s": 0.0,
        "resets": 0,
        "wall_s": 0.0,
    }


def _start_worker(counter=None) -> None:
    """Each pool worker's start: it dies with the campaign (a parent-death signal, so a
    SIGKILL of ``mpy-fil campaign`` leaves no worker running), and, beside others, it does
    not busy-poll (its tasks say so) and is kept to one core of its own, taken in turn (the interpreter it
    starts inherits it): a rig's host and firmware hand the link back and forth, cheaper
    on one core than across two."""
    die_with_parent()
    if counter is None:
        return
    with counter.get_lock():
        n = counter.value
        counter.value += 1
    cores = sorted(os.sched_getaffinity(0))
    os.sched_setaffinity(0, {cores[n % len(cores)]})


class LocalPool:
    """``workers`` processes of this machine."""

    def __init__(self, workers: int, busy_poll: bool):
        self.workers = workers
        self.busy_poll = busy_poll
        self.pool = self._new()

    def _new(self):
        context = multiprocessing.get_context("spawn")  # (no fork of a process with threads)
        args = () if self.busy_poll else (context.Value("i", 0),)
        return cf.ProcessPoolExecutor(
            max_workers=self.workers, mp_context=context, initializer=_start_worker, initargs=args
        )

    def submit(self, task: dict, artefacts: str):
        return self.pool.submit(run_one, {**task, "busy_poll": self.busy_poll}, artefacts)

    def wait(self, futures, timeout_s: float):
        return cf.wait(futures, timeout=timeout_s, return_when=cf.FIRST_COMPLETED)

    def restart(self, futures=()) -> None:
        """Stop every worker process (a hung or broken pool: they are all this
        campaign's) and start afresh."""
        for proc in list(getattr(self.pool, "_processes", {}).values()):
            proc.kill()
        self.pool.shutdown(wait=True, cancel_futures=True)
        self.pool = self._new()

    def close(self) -> None:
        for proc in list(getattr(self.pool, "_processes", {}).values()):
            if proc.is_alive():
                proc.kill()
        self.pool.shutdown(wait=True, cancel_futures=True)


class DaskPool:
    """The workers of a Dask cluster, at its scheduler's address (``tcp://host:8786``)."""

    def __init__(self, address: str, busy_poll: bool):
        from distributed import Client

        try:
            parts = urllib.parse.urlsplit("//" + address.partition("://")[2])
            socket.create_connection((parts.hostname, parts.port), timeout=CONNECT_S).close()  # (refused: at once)
            self.client = Client(address, timeout=f"{CONNECT_S:g}s")
        except (OSError, TimeoutError) as e:
            first = (str(e).strip().splitlines() or [type(e).__name__])[0][:200]
            raise ConfigError(
                f"--scheduler {address}: no Dask scheduler answered ({first}); "
                "expected one running there (docs/campaigns.md, Dask cluster)"
            ) from None
        self.busy_poll = busy_poll
        self.workers = sum(w.get("nthreads", 1) for w in self.client.scheduler_info()["workers"].values())

    def submit(self, task: dict, artefacts: str):
        return self.client.submit(run_one, {**task, "busy_poll": self.busy_poll}, artefacts, pure=False)

    def wait(self, futures, timeout_s: float):
        from distributed import wait

        try:
            done = wait(list(futures), timeout=timeout_s, return_when="FIRST_COMPLETED").done
        except TimeoutError:
            done = set()
        return done, set(futures) - set(done)

    def restart(self, futures=()) -> None:
        """A hung pool: cancel this campaign's own runs, and nothing else. The cluster's
        workers are not the campaign's to restart (``client.restart()`` would restart
        every worker of a shared cluster, and other people's work with them); a run
        still busy in a worker thread ends at its own ``timeout_s``."""
        if futures:
            self.client.cancel(list(futures), force=True)

    def close(self) -> None:
        self.client.close()


def run_campaign(
    campaign: Campaign, out, *, workers: int = 1, scheduler: str | None = None, on_result=None, busy_poll: bool = True
):
    """Run what is not done yet; every result in the store (``out``), as they finish;
    ``on_result(result, done, total)`` for progress; ``busy_poll`` False: not even a lone
    worker spins on its link. Returns every result in the store."""
    store = ResultStore(out)
    store.open(campaign.to_dict())
    manifest.write_campaign(out, campaign.rig, campaign.to_dict())  # (host/rig/loop/manifest.py)
    tasks = campaign.tasks()
    done_keys = store.done()
    todo = [t for t in tasks if task_key(t) not in done_keys]
    if not todo:
        return store.read()
    busy_poll = busy_poll and workers <= 1 and scheduler is None  # (a second rig takes the spare core)
    pool = DaskPool(scheduler, busy_poll) if scheduler else LocalPool(min(workers, len(todo)), busy_poll)
    count = [len(tasks) - len(todo)]

    def report(result: dict) -> None:
        count[0] += 1
        if on_result is not None:
            on_result(result, count[0], len(tasks))

    try:
        _run(pool, todo, store, campaign, report)
    finally:
        pool.close()
    return store.read()


def _run(pool, todo: list[dict], store: ResultStore, campaign: Campaign, report) -> None:
    breaks: dict[str, int] = {}
    pending = list(todo)
    runs = {task_key(t): safefs.make_folder(store.folder / "runs" / task_key(t), base=store.folder) for t in todo}
    while pending:
        futures = {pool.submit(t, str(runs[task_key(t)])): t for t in pending}
        pending = []
        while futures:
            done, _ = pool.wait(list(futures), campaign.timeout_s + GUARD_S)
            if not done:  # nothing for too long: the pool is stuck
                for task in futures.values():
                    _record(store, report, failed(task, "hung", _hung(campaign)))
                pool.restart(list(futures))
                break
            for future in done:
                task = futures.pop(future)
                try:
                    result = future.result()
                except Exception as e:  # the worker process died (or the cluster lost it)
                    key = task_key(task)
                    breaks[key] = breaks.get(key, 0) + 1
                    if breaks[key] < MAX_BREAKS:
                        pending.append(task)
                        continue
                    result = failed(task, "crash", f"the worker running it died twice: {type(e).__name__}: {e}")
                _record(store, report, result)
        if pending and isinstance(pool, LocalPool):
            pool.restart()


def _hung(campaign: Campaign) -> str:
    return (
        f"hung: no run of the pool finished within {campaign.timeout_s + GUARD_S:g} s of wall time "
        f"(timeout_s {campaign.timeout_s:g} + {GUARD_S:g}); the pool was stopped"
    )


def _record(store: ResultStore, report, result: dict) -> None:
    store.append(result)
    report(result)


__all__ = ["DaskPool", "LocalPool", "run_campaign"]

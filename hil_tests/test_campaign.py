"""Campaigns in the loop (docs/campaigns.md): a small campaign of short rover runs over
the harness's own faults (brown-out, a smaller heap, link corruption and stalls) on the
local pool and on a Dask LocalCluster, its results kept when interrupted and skipped when
rerun, its report, a replay of a run, and a run that hangs."""

import json
import multiprocessing
import os
from pathlib import Path

import numpy as np
import pytest

from host.campaign import load_campaign, replay
from host.campaign.report import wilson, write_report
from host.campaign.runner import run_campaign
from host.campaign.worker import run_one

pytestmark = [pytest.mark.hil, pytest.mark.xdist_group("test_campaign")]  # (make hil: its module fixtures run once)

SCENARIO = """
[campaign]
rig = "rover"
seconds = 4
step_s = 1.0
judge = "generic"
seeds = 2
timeout_s = 120

[[faultsets]]
name = "none"

[[faultsets]]
name = "brownout"
[[faultsets.faults]]
kind = "brownout"
at_s = 2.0

[[faultsets]]
name = "heap-16K"
[[faultsets.faults]]
kind = "heap"
size = "16K"  # (the rover needs 24K: 20K fails)

[[faultsets]]
name = "corrupt"
[[faultsets.faults]]
kind = "link_corrupt"
direction = "to_firmware"
rate = 0.05

[[faultsets]]
name = "stalls"
[[faultsets.faults]]
kind = "link_stall"
direction = "both"
rate = 0.02
stall_ms = 5
"""


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    """The small campaign, run once on two local workers: (campaign, folder, results, lines)."""
    folder = tmp_path_factory.mktemp("campaign")
    scenario = folder / "small.toml"
    scenario.write_text(SCENARIO)
    campaign = load_campaign(str(scenario))
    lines = []
    results = run_campaign(campaign, folder / "out", workers=2, on_result=lambda r, d, t: lines.append((d, t, r)))
    return campaign, folder / "out", results, lines


def by_key(results):
    return {r["key"]: r for r in results}


def where(results) -> str:
    return "results:\n" + "\n".join(f"  {r['key']}: {r['passed']} {r['error']} {r['message'][:200]}" for r in results)


def test_the_small_campaign_runs_every_run_and_says_so_as_each_finishes(small):
    campaign, out, results, lines = small
    assert len(results) == 10 == len(campaign.tasks()), f"expected 5 fault sets x 2 seeds; {where(results)}"
    assert [d for d, _t, _r in lines] == list(range(1, 11)) and all(t == 10 for _d, t, _r in lines)
    assert not multiprocessing.active_children(), "expected the pool's processes ended with the campaign"
    r = by_key(results)
    for seed in (1, 2):
        assert r[f"none/room/{seed}"]["passed"] and r[f"none/room/{seed}"]["resets"] == 0, where(results)


def test_a_brownout_boots_the_firmware_again_at_its_time_and_the_plant_runs_on(small):
    _c, out, results, _l = small
    run = by_key(results)["brownout/room/1"]
    console = (out / "runs" / "brownout" / "room" / "1" / "console.log").read_text()
    assert run["passed"] and run["resets"] == 1 and run["t_end_s"] == 4.0, where(results)
    assert console.count("control every 50 ms") == 2, f"expected two boots on the console, got:\n{console}"
    assert run["budgets"]["control.period"]["misses"] >= 1, "expected the lost power to show as a missed period"


def test_a_smaller_heap_is_the_interpreters_and_a_firmware_that_does_not_fit_fails_with_its_traceback(small):
    _c, _o, results, _l = small
    run = by_key(results)["heap-16K/room/1"]
    assert not run["passed"] and run["error"] == "FirmwareError", where(results)
    assert "MemoryError" in run["message"] and "main.py" in run["message"], run["message"]
    # (as its board prints it: at a line of main.py, or while main.py compiles, no frame; never the shim's)
    assert "_hilboot" not in run["message"], run["message"]


def test_link_corruption_ends_the_run_as_a_damaged_link_and_stalls_only_cost_wall_time(small):
    _c, _o, results, _l = small
    r = by_key(results)
    for seed in (1, 2):
        bad, slow = r[f"corrupt/room/{seed}"], r[f"stalls/room/{seed}"]
        assert not bad["passed"] and bad["error"] == "LinkDamaged", where(results)
        assert "damaged or lost" in bad["message"] and bad["figures"]["link_corrupted_to_firmware"] >= 1
        assert slow["passed"] and slow["figures"]["link_stalls"] >= 1, where(results)
        assert slow["budgets"]["control.period"] == r[f"none/room/{seed}"]["budgets"]["control.period"], (
            "expected a stalled link to change nothing in virtual time"
        )


def test_the_report_gives_wilson_intervals_distributions_worst_runs_csv_and_json(small):
    campaign, out, results, _l = small
    paths = write_report(out, campaign.to_dict(), results)
    summary = json.loads(paths["json"].read_text())
    groups = {g["faultset"]: g for g in summary["groups"]}
    assert set(groups) == {"none", "brownout", "heap-16K", "corrupt", "stalls"}
    for g in groups.values():
        assert (g["wilson_lo"], g["wilson_hi"]) == pytest.approx(wilson(g["passed"], g["runs"]))
    assert groups["none"]["passed"] == 2 and groups["corrupt"]["passed"] == 0
    worst = summary["worst"]
    assert {w["key"] for w in worst[:4]} == {"corrupt/room/1", "corrupt/room/2", "heap-16K/room/1", "heap-16K/room/2"}
    assert all(w["replay"].startswith(".venv/bin/mpy-fil campaign --replay ") for w in worst)
    page = paths["html"].read_text()
    assert "Worst runs" in page and 'src="plots/success_rate.png"' in page and "LinkDamaged" in page
    grid = np.load(out / "runs" / "none" / "room" / "1" / "coverage.npz")
    assert grid["covered"].shape == grid["free"].shape and 0 < grid["covered"].sum() < grid["free"].sum()
    assert 'src="maps/none_room_' in page, "expected a map of the floor for a worst run that has its grid"
    assert len(paths["runs_csv"].read_text().splitlines()) == 11
    assert (out / "plots" / "success_rate.png").stat().st_size > 1000


def test_a_rerun_skips_what_is_done_and_an_interrupted_campaign_runs_only_the_rest(small, tmp_path):
    campaign, out, results, _l = small
    again = []
    assert len(run_campaign(campaign, out, workers=2, on_result=lambda *a: again.append(a))) == 10
    assert again == [], "expected nothing run again"
    cut = tmp_path / "cut"
    cut.mkdir()
    lines = (out / "results.jsonl").read_text().splitlines()
    (cut / "results.jsonl").write_text("\n".join(lines[:3]) + "\n" + lines[3][: len(lines[3]) // 2])  # killed mid-line
    rest = []
    finished = run_campaign(campaign, cut, workers=2, on_result=lambda r, d, t: rest.append(r["key"]))
    kept = {json.loads(x)["key"] for x in lines[:3]}
    assert len(rest) == 7 and not kept & set(rest), f"expected the 7 runs not kept to run, ran {rest}"
    assert {r["key"] for r in finished} == {r["key"] for r in results}


def test_a_dask_local_cluster_runs_the_same_campaign_to_the_same_results(small, tmp_path):
    distributed = pytest.importorskip("distributed")
    campaign, _o, results, _l = small
    campaign.faultsets = {k: campaign.faultsets[k] for k in ("none", "brownout")}
    import dask

    with (
        dask.config.set({"temporary-directory": str(tmp_path / "scratch")}),  # (no scratch left in /tmp)
        distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster,
    ):
        got = run_campaign(campaign, tmp_path / "dask", scheduler=cluster.scheduler_address)
    local = by_key(results)
    assert len(got) == 4, where(got)
    for r in got:
        mine = local[r["key"]]
        same = ("passed", "resets", "t_end_s", "figures")
        assert {k: r[k] for k in same} == {k: mine[k] for k in same}, f"{r['key']}: dask {r}, local {mine}"
        assert r["budgets"]["control.period"] == mine["budgets"]["control.period"]


def test_replay_runs_a_campaigns_run_again_with_its_trace_folder(small):
    _c, out, results, _l = small
    again = replay(out, "brownout/room/2")
    first = by_key(results)["brownout/room/2"]
    assert (again["passed"], again["resets"], again["figures"]) == (first["passed"], first["resets"], first["figures"])
    header = json.loads((out / "replay" / "brownout" / "room" / "2" / "header.json").read_text())
    assert header["faults"] == [{"kind": "brownout", "at_s": 2.0}] and header["seed"] == 2


def test_a_run_that_takes_too_long_is_a_failed_run_that_says_so():
    task = {
        "rig": "rover",
        "seconds": 600,
        "until": None,
        "step_s": 600,
        "judge": "generic",
        "timeout_s": 0.5,
        "budgets": [],
        "figures": [],
        "faultset": "none",
        "world": "room",
        "seed": 1,
        "faults": [],
    }
    r = run_one(task)
    assert not r["passed"] and r["error"] == "RunTimeout", r
    assert "more than 0.5 s of wall time" in r["message"] and r["wall_s"] < 10, r["message"]
    assert 0 < r["t_end_s"] < 600


def test_no_busy_polling_in_a_campaigns_workers():
    """The runner's choice rides in each task (no environment variable): a worker's rig
    does not spin on its link when its task says so."""
    from host.campaign.worker import task_spec
    from host.link import spare_core
    from host.rig import Rig

    task = {"rig": "rover", "world": "room", "seed": 1, "faults": []}
    assert Rig(task_spec({**task, "busy_poll": False})).target.busy_poll_s == 0.0
    assert (Rig(task_spec({**task, "busy_poll": True})).target.busy_poll_s > 0.0) == spare_core()


def test_the_command_line_runs_a_campaign_prints_progress_and_replays_a_run(tmp_path):
    import subprocess
    import sys

    def cli(*args):
        return subprocess.run([sys.executable, "-m", "host.cli", "campaign", *args], capture_output=True, text=True)

    out = tmp_path / "out"
    run = cli("rover", "--seeds", "2", "--seconds", "2", "--workers", "2", "--out", str(out))
    assert run.returncode == 0, f"expected exit 0, got {run.returncode}:\n{run.stdout}\n{run.stderr}"
    lines = run.stdout.splitlines()
    assert lines[0].startswith("campaign rover: 2 runs (1 fault set(s) x 1 world(s) x 2 seeds) on 2 local worker(s)")
    assert any(ln.startswith("[1/2] pass none/room/") for ln in lines) and any(ln.startswith("[2/2] ") for ln in lines)
    assert "none / room: 2 of 2 passed" in run.stdout and f"campaign report: {out / 'campaign.html'}" in run.stdout
    again = cli("--replay", "none/room/2", "--out", str(out))
    assert again.returncode == 0 and "pass none/room/2" in again.stdout, again.stdout + again.stderr
    assert (out / "replay" / "none" / "room" / "2" / "header.json").is_file()
    bad = cli("rover", "--seeds", "0")
    assert bad.returncode == 2 and "argument --seeds: expected 1 or more, got 0" in bad.stderr, bad.stderr
    other = cli("rover", "--seeds", "2", "--seconds", "3", "--out", str(out))
    assert other.returncode == 2 and "holds the results of another campaign" in other.stderr, other.stderr


def rover_truth(faults):
    import time

    from host.campaign.worker import _drive, _make_rig

    task = {
        "rig": "rover",
        "seconds": 5,
        "until": None,
        "step_s": 1,
        "judge": "generic",
        "timeout_s": 60,
        "budgets": [],
        "figures": [],
        "faultset": "x",
        "world": "room",
        "seed": 1,
        "faults": faults,
    }
    rig, cuts = _make_rig(task, None, False, time.monotonic())
    try:
        rig.start()
        _drive(rig, task, cuts)
        return rig.truth()
    finally:
        rig.stop()


def test_plant_faults_reach_the_firmware_a_stuck_sonar_slows_the_rover_and_a_jammed_wheel_turns_it():
    plain = rover_truth([])
    near = rover_truth([{"kind": "stuck", "signal": "sonar.adc", "value": 1000}])
    jammed = rover_truth([{"kind": "stuck_wheel", "wheel": "left", "start_s": 1.0, "end_s": 4.0}])
    assert abs(plain["theta_rad"]) < 0.05 and plain["distance_m"] > 1.2, f"expected a straight run, got {plain}"
    assert near["distance_m"] < 0.6 * plain["distance_m"] and near["fault_events"]["stuck sonar.adc"] >= 5, (
        f"expected the rover to slow for an obstacle that is not there: {near['distance_m']:.2f} m vs "
        f"{plain['distance_m']:.2f} m"
    )
    assert abs(jammed["theta_rad"]) > 0.5 and jammed["distance_m"] < plain["distance_m"], (
        f"expected the rover to swing about its jammed wheel, got theta {jammed['theta_rad']:.2f} rad"
    )


def descendants(pid: int) -> dict[int, str]:
    """The living processes under ``pid`` (walking /proc's parent links): pid -> command."""
    parents, names = {}, {}
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue  # (ended while we looked)
        name, rest = stat[stat.index("(") + 1 : stat.rindex(")")], stat[stat.rindex(")") + 2 :].split()
        if rest[0] != "Z":
            parents[int(entry.name)], names[int(entry.name)] = int(rest[1]), name
    found, frontier = {}, [pid]
    while frontier:
        parent = frontier.pop()
        for child, ppid in parents.items():
            if ppid == parent and child not in found:
                found[child] = names[child]
                frontier.append(child)
    return found


def alive(pids) -> dict[int, str]:
    left = {}
    for pid in pids:
        try:
            stat = Path(f"/proc/{pid}/stat").read_text()
        except OSError:
            continue
        if stat[stat.rindex(")") + 2] != "Z":
            left[pid] = stat[stat.index("(") + 1 : stat.rindex(")")]
    return left


def test_a_campaign_killed_mid_run_leaves_no_worker_and_no_micropython_running(tmp_path):
    import subprocess
    import sys
    import time

    command = [sys.executable, "-m", "host.cli", "campaign", "rover", "--seeds", "4", "--seconds", "120"]
    proc = subprocess.Popen(
        [*command, "--workers", "2", "--out", str(tmp_path / "c")], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
    )
    tree = {}
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and sum("micropython" in n for n in tree.values()) < 2:
            time.sleep(0.2)
            tree = descendants(proc.pid) if proc.poll() is None else tree
        assert sum("micropython" in n for n in tree.values()) == 2, f"expected two runs under way, saw {tree}"
        proc.kill()  # SIGKILL: no handler runs, only the kernel's parent-death signals
        proc.wait(timeout=10)
        end = time.monotonic() + 5
        while alive(tree) and time.monotonic() < end:
            time.sleep(0.1)
        left = alive(tree)
        assert not left, f"expected nothing of the killed campaign's tree left after 5 s, left: {left}"
    finally:  # (the test leaves nothing either: what it saw of the tree, ended)
        if proc.poll() is None:
            tree.update(descendants(proc.pid))
            proc.kill()
            proc.wait()
        for pid in alive(tree):
            os.kill(pid, 9)

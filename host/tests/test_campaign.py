"""The campaign's parts without firmware (host/campaign, docs/campaigns.md): the
scenario file and its mistakes, the rig file's [[faults]], the Wilson interval, the worst
runs, the placement error, the results file; the report for every outcome and a report
that fails."""

import json
import math
import re
import tempfile
import threading
from pathlib import Path

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from host.campaign import load_campaign, task_key
from host.campaign import report as report_module
from host.campaign.report import ReportError, error_bars, summarize, wilson, worst, write_report
from host.campaign.runner import failed
from host.campaign.store import ResultStore
from host.core.errors import ConfigError
from host.rig.config.rigfile import load_rig
from host.rig.loop.spec import placed

RIG = """
name = "bench"
[firmware]
dir = "."
[board.pins]
A = 1
[plant]
body = "bench"
[[plant.parts]]
kind = "wire"
name = "w0"
[wiring]
"""


def scenario(tmp_path, text: str):
    path = tmp_path / "s.toml"
    path.write_text(text)
    return str(path)


def test_wilson_matches_the_textbook_interval():
    lo, hi = wilson(18, 20)  # 0.9 from 20 runs: [0.699, 0.972]
    assert (round(lo, 3), round(hi, 3)) == (0.699, 0.972)
    assert wilson(0, 10)[0] == 0.0 and round(wilson(0, 10)[1], 3) == 0.278
    assert wilson(10, 10)[1] == pytest.approx(1.0) and round(wilson(10, 10)[0], 3) == 0.722


def test_the_interval_holds_the_rate_within_0_and_1_for_every_count_up_to_200():
    for n in range(1, 201):
        for k in range(n + 1):
            lo, hi = wilson(k, n)
            assert 0.0 <= lo <= k / n <= hi <= 1.0, f"{k} of {n}: [{lo!r}, {hi!r}]"
        assert wilson(n, n)[1] == 1.0 and wilson(0, n)[0] == 0.0, f"n={n}: the exact interval reaches the rate"


@settings(max_examples=400, derandomize=True, database=None, deadline=None)
@given(n=st.integers(1, 200), data=st.data())
def test_the_plots_error_bars_are_never_negative(n, data):
    k = data.draw(st.integers(0, n))
    rows = summarize([result(f"a/w/{i}", i < k) for i in range(n)])
    assert rows[0]["wilson_lo"] <= rows[0]["rate"] <= rows[0]["wilson_hi"]
    assert min(min(side) for side in error_bars(rows)) >= 0.0


def task(key: str) -> dict:
    faultset, world, seed = key.split("/")
    return {"faultset": faultset, "world": world, "seed": int(seed)}


def outcomes(n: int, kind: str, seed: int) -> list[dict]:
    """``n`` results of one group (and, for mixed, a second group), each with a figure
    that is sometimes missing or NaN, as judges give them."""
    runs = []
    for i in range(n):
        passed = {"pass": True, "fail": False}.get(kind, (i * 7 + seed) % 3 != 0)
        figures = {"coverage": ((i * 37 + seed) % 100) / 100} if i % 5 else {"coverage": math.nan}
        group = "b" if kind == "mixed" and i % 4 == 3 else "a"
        key = f"{group}/room/{i + 1}"
        runs.append({**failed(task(key), None if passed else "FirmwareError", ""), **result(key, passed, **figures)})
        runs[-1].update(wall_s=1.0 + i % 3, t_end_s=2.0)
    return runs


@settings(max_examples=12, derandomize=True, database=None, deadline=None)
@given(n=st.integers(1, 200), kind=st.sampled_from(["pass", "fail", "mixed"]), seed=st.integers(0, 99))
@example(n=10, kind="pass", seed=0)  # the default campaign that passes: the report crashed
@example(n=4, kind="pass", seed=0)
@example(n=69, kind="fail", seed=0)  # an all-failing count whose lower bound rounded above 0
@example(n=1, kind="fail", seed=0)
@example(n=200, kind="mixed", seed=3)
def test_the_report_is_written_for_every_outcome_and_count(n, kind, seed):
    runs = outcomes(n, kind, seed)
    with tempfile.TemporaryDirectory() as tmp:
        paths = write_report(Path(tmp), {"name": "x", "rig": "rover", "worst_by": "coverage"}, runs)
        summary = json.loads(paths["json"].read_text())
        assert summary["runs"] == n and sum(g["runs"] for g in summary["groups"]) == n
        for g in summary["groups"]:
            assert 0.0 <= g["wilson_lo"] <= g["rate"] <= g["wilson_hi"] <= 1.0, g
        page = paths["html"].read_text()
        images = re.findall(r'<img alt="[^"]*" src="([^"]+)"', page)
        assert len(images) == 3, f"expected the rate, coverage and wall time plots, got {images}"
        assert all((Path(tmp) / src).is_file() for src in images) and "data:" not in page, images
        assert len(paths["runs_csv"].read_text().splitlines()) == n + 1


def test_a_report_that_fails_keeps_the_results_and_says_so_in_one_line(tmp_path, monkeypatch):
    store = ResultStore(tmp_path)
    store.open({"name": "x"})
    runs = outcomes(10, "pass", 0)
    for r in runs:
        store.append(r)

    def no_plots(*_a):
        raise RuntimeError("no space left on device\nsecond line")

    monkeypatch.setattr(report_module, "_plots", no_plots)
    with pytest.raises(ReportError) as e:
        write_report(tmp_path, {"name": "x"}, store.read())
    message = str(e.value)
    assert "\n" not in message and str(tmp_path / "results.jsonl") in message, message
    assert "RuntimeError: no space left on device" in message and "the 10 results are kept" in message
    assert len(store.read()) == 10 and (tmp_path / "summary.json").is_file(), "expected the results kept"


def test_the_command_line_says_in_one_line_where_the_results_are_when_the_report_fails(tmp_path, monkeypatch, capsys):
    import signal

    from host import cli
    from host.campaign import runner

    def fake_run(campaign, out, **_kw):
        store = ResultStore(out)
        store.open(campaign.to_dict())
        for r in outcomes(3, "pass", 0):
            store.append(r)
        return store.read()

    def no_plots(*_a):
        raise ValueError("'xerr' must not contain negative values")

    monkeypatch.setattr(runner, "run_campaign", fake_run)
    monkeypatch.setattr(report_module, "_plots", no_plots)
    before = signal.getsignal(signal.SIGTERM)
    try:
        code = cli.main(["campaign", "rover", "--seeds", "3", "--seconds", "1", "--out", str(tmp_path / "c")])
    finally:
        signal.signal(signal.SIGTERM, before)
    err = capsys.readouterr().err
    assert code == 1 and len(err.strip().splitlines()) == 1, err
    assert f"kept in {tmp_path / 'c' / 'results.jsonl'}" in err and "Traceback" not in err, err
    assert len((tmp_path / "c" / "results.jsonl").read_text().splitlines()) == 3


def test_a_scenario_crosses_fault_sets_worlds_and_seeds(tmp_path):
    text = """
[campaign]
rig = "rover"
seeds = 3
first_seed = 5
worlds = ["room", "long-room"]
[[faultsets]]
name = "none"
[[faultsets]]
name = "noisy"
[[faultsets.faults]]
kind = "noise"
signal = "sonar.adc"
sd = 100
"""
    campaign = load_campaign(scenario(tmp_path, text))
    keys = [task_key(t) for t in campaign.tasks()]
    assert len(keys) == 12 and len(set(keys)) == 12
    assert keys[0] == "none/room/5" and keys[-1] == "noisy/long-room/7"
    assert load_campaign(scenario(tmp_path, text), seeds=1, worlds=["room"]).tasks()[-1]["seed"] == 5


@pytest.mark.parametrize(
    "text, message",
    [
        ('[campaign]\nrig = "rover"\nseed = 3\n', "[campaign] seed: unknown key"),
        ("[campaign]\nseeds = 3\n", "[campaign] rig: missing"),
        ('[campaign]\nrig = "rover"\nworlds = ["moon"]\n', "rover has no world 'moon'"),
        ('[campaign]\nrig = "rover"\njudge = "vibes"\n', "judge: expected one of generic"),
        ('[campaign]\nrig = "rover"\nbudgets = ["speed"]\n', "rover has no budget 'speed'"),
        (
            '[campaign]\nrig = "rover"\n[[faultsets]]\nname = "x"\n[[faultsets.faults]]\nkind = "dropout"\n',
            "faultsets[0] (x) faults[0] (dropout): missing signal",
        ),
        (
            '[campaign]\nrig = "rover"\n[[faultsets]]\nname = "x"\n[[faultsets.faults]]\n'
            'kind = "dropout"\nsignal = "nope"\n',
            "fault set 'x': faults[0] (dropout) signal: the plant has no output 'nope'",
        ),
        ('[campaign]\nrig = "rover"\nplacement = { x_m = [1, 0] }\n', "placement x_m: expected one of x_m"),
    ],
)
def test_a_bad_scenario_is_refused_naming_the_file_and_the_field(tmp_path, text, message):
    with pytest.raises(ConfigError) as e:
        load_campaign(scenario(tmp_path, text))
    assert message in str(e.value), f"expected {message!r} in: {e.value}"


def test_a_rig_file_takes_faults_checked_against_its_plant(tmp_path):
    (tmp_path / "main.py").write_text("")
    rig = tmp_path / "rig.toml"
    rig.write_text(RIG + '[[faults]]\nkind = "heap"\nsize = "96K"\n')
    app = load_rig(rig)
    assert app.interpreter.heap_size == "96K" and [f.kind for f in app.run.faults] == ["heap"]
    rig.write_text(RIG + '[[faults]]\nkind = "stuck"\nsignal = "nothing"\nvalue = 1\n')
    with pytest.raises(ConfigError, match=r"rig.toml: \[\[faults\]\]: faults\[0\] \(stuck\) signal: the plant has no"):
        load_rig(rig)


def test_the_placement_error_is_drawn_per_seed_within_its_ranges():
    spans = {"x_m": [-0.3, 0.0], "y_m": [0.0, 0.3], "theta_deg": [-5.0, 5.0]}
    poses = [placed((10.0, 1.0, 0.0), spans, seed) for seed in range(200)]
    assert placed((10.0, 1.0, 0.0), spans, 7) == poses[7]
    assert all(9.7 <= x <= 10.0 and 1.0 <= y <= 1.3 and abs(th) <= 0.0873 for x, y, th in poses)
    assert max(x for x, _, _ in poses) - min(x for x, _, _ in poses) > 0.25, "expected the range used"


def result(key, passed, **figures):
    faultset, world, seed = key.split("/")
    return {"key": key, "faultset": faultset, "world": world, "seed": int(seed), "passed": passed, "figures": figures}


def test_the_worst_runs_are_the_failures_then_the_lowest_or_highest_figure():
    runs = [
        result("a/w/1", True, coverage=0.97),
        result("a/w/2", False, coverage=0.5),
        result("a/w/3", True, coverage=0.95),
    ]
    assert [r["key"] for r in worst(runs, "coverage", low=True)] == ["a/w/2", "a/w/3", "a/w/1"]
    assert [r["key"] for r in worst(runs, "coverage")] == ["a/w/2", "a/w/1", "a/w/3"]
    rows = summarize(runs)
    assert rows[0]["passed"] == 2 and rows[0]["figures"]["coverage"]["median"] == 0.95


def test_the_results_file_keeps_whole_lines_and_the_last_of_each_run(tmp_path):
    store = ResultStore(tmp_path)
    store.open({"name": "x"})
    store.append(result("a/w/1", False))
    store.append(result("a/w/1", True))
    with store.path.open("a") as f:
        f.write('{"key": "a/w/2", "pass')  # a crash mid-line
    store.open({"name": "x"})
    store.append(result("a/w/3", True))
    assert {r["key"]: r["passed"] for r in store.read()} == {"a/w/1": True, "a/w/3": True}
    assert json.loads((tmp_path / "campaign.json").read_text()) == {"name": "x"}


def test_a_folder_with_another_campaigns_results_is_refused(tmp_path):
    store = ResultStore(tmp_path)
    store.open({"rig": "rover", "seconds": 4, "seeds": 2})
    store.append(result("a/w/1", True))
    store.open({"rig": "rover", "seconds": 4, "seeds": 20})  # more seeds: the same campaign, going on
    with pytest.raises(ConfigError, match=r"holds the results of another campaign \(it differs in seconds\)"):
        store.open({"rig": "rover", "seconds": 8, "seeds": 2})


def test_a_fault_set_added_grows_the_campaign_and_one_changed_is_another(tmp_path):
    store = ResultStore(tmp_path)
    store.open({"rig": "duct", "faultsets": {"a": [{"kind": "tether_snag", "rate": 0.1}]}})
    store.append(result("a/w/1", True))
    store.open({"rig": "duct", "faultsets": {"a": [{"kind": "tether_snag", "rate": 0.1}], "b": []}})
    with pytest.raises(ConfigError, match=r"differs in faultsets"):
        store.open({"rig": "duct", "faultsets": {"a": [{"kind": "tether_snag", "rate": 0.5}]}})


class Accepted(Exception):
    """The arguments got as far as running the campaign (with this scheduler address)."""

    scheduler = None


def campaign_cli(argv: list[str], monkeypatch) -> tuple[object, str]:
    """``mpy-fil campaign`` in this process up to the run (which is not started): the
    exit code, or ``Accepted``; and stderr."""
    import contextlib
    import io
    import signal

    from host import cli
    from host.campaign import runner

    def no_run(*_a, scheduler=None, **_kw):
        Accepted.scheduler = scheduler
        raise Accepted

    monkeypatch.setattr(runner, "run_campaign", no_run)
    before = signal.getsignal(signal.SIGTERM)
    err = io.StringIO()
    try:
        with contextlib.redirect_stderr(err):
            code = cli.main(["campaign", *argv])
    except SystemExit as e:
        code = e.code
    except Accepted:
        code = Accepted
    finally:
        signal.signal(signal.SIGTERM, before)
    return code, err.getvalue()


def assert_accepted_or_refused_in_one_line(code, err: str, argv) -> None:
    assert code is Accepted or code == 2, f"{argv}: expected accepted or exit 2, got {code!r}: {err}"
    if code == 2:
        assert len(err.strip().splitlines()) == 1 and "Traceback" not in err, f"{argv}: expected one line:\n{err}"
        assert err.startswith("mpy-fil campaign: error: "), err


numbers = st.one_of(
    st.integers(-(2**70), 2**70).map(str),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.sampled_from(["", " ", "1e3", "0x10", "1_000", "nan", "-0", "١٢"]),
    st.text(max_size=12),
)
hosts = st.sampled_from(["127.0.0.1", "localhost", "[::1]", "::1", "no-such-host.invalid", "", "a b", "h\x00", "-x-"])
schedulers = st.one_of(
    st.text(max_size=40),
    st.builds(
        "{}{}:{}".format,
        st.sampled_from(["tcp://", "tls://", "ws://", "", "http://", "inproc://", "TCP://", "tcp:/"]),
        st.one_of(hosts, st.text(max_size=10)),
        st.one_of(st.integers(-10, 70000).map(str), st.text(max_size=6)),
    ),
)


@settings(max_examples=150, derandomize=True, database=None, deadline=None)
@given(
    seeds=st.one_of(st.none(), numbers),
    workers=st.one_of(st.none(), numbers),
    seconds=st.one_of(st.none(), numbers),
    scheduler=st.one_of(st.none(), schedulers),
)
@example(seeds="10", workers="2", seconds="2", scheduler=None)
@example(seeds=None, workers=None, seconds=None, scheduler="tcp://127.0.0.1:8786")
@example(seeds=None, workers=None, seconds=None, scheduler="tcp://127.0.0.1:65536")
@example(seeds=None, workers=None, seconds=None, scheduler="tcp://no-such-host.invalid:8786")
@example(seeds="100000", workers="1000", seconds="1e300", scheduler="ucx://x:1")
def test_campaign_arguments_are_accepted_or_refused_in_one_line(seeds, workers, seconds, scheduler):
    with tempfile.TemporaryDirectory() as tmp, pytest.MonkeyPatch.context() as monkeypatch:
        argv = ["rover", "--out", tmp]
        for flag, value in (("--seeds", seeds), ("--workers", workers), ("--seconds", seconds)):
            argv += [f"{flag}={value}"] if value is not None else []
        argv += [f"--scheduler={scheduler}"] if scheduler is not None else []
        code, err = campaign_cli(argv, monkeypatch)
    assert_accepted_or_refused_in_one_line(code, err, argv)
    if scheduler == "tcp://127.0.0.1:8786" and code == 2:
        assert "--scheduler" not in err, f"expected a good address accepted: {err}"
    if code is Accepted and scheduler is not None:  # what Dask is given is an address it reads
        from distributed.comm.addressing import parse_address, parse_host_port

        scheme, location = parse_address(Accepted.scheduler)
        host, port = parse_host_port(location)
        assert scheme in ("tcp", "tls", "ws", "wss") and host and 0 < port < 65536, Accepted.scheduler


@settings(max_examples=60, derandomize=True, database=None, deadline=None)
@given(content=st.one_of(st.binary(max_size=80), st.text(max_size=80).map(str.encode)))
@example(content=b"\xff\xfe[[faults]]\nkind = 'noise'\n")
@example(content=b"[[faults]\nkind =")
@example(content=b"faultsets = 3")
@example(content=b"faults = [" * 2000)
@example(content=b'[[faults]]\nkind = "noise"\nsignal = "sonar.adc"\nsd = 100\n')
def test_a_faults_file_is_accepted_or_refused_in_one_line_naming_it(content):
    with tempfile.TemporaryDirectory() as tmp, pytest.MonkeyPatch.context() as monkeypatch:
        path = Path(tmp) / "faults.toml"
        path.write_bytes(content)
        argv = ["rover", "--faults", str(path), "--out", str(Path(tmp) / "out")]
        code, err = campaign_cli(argv, monkeypatch)
    assert_accepted_or_refused_in_one_line(code, err, argv)
    if code == 2:
        assert str(path) in err, f"expected the file named: {err}"


def test_a_bad_scheduler_or_faults_file_is_refused_before_anything_runs(tmp_path, monkeypatch):
    bad = tmp_path / "faults.toml"
    bad.write_bytes(b"[[faults]]\nkind = '\xe9'\n")
    cases = [
        (["--scheduler", "tcp://10.0.0.5"], "argument --scheduler: expected [tcp|tls|ws|wss]://HOST:PORT"),
        (["--scheduler", "http://127.0.0.1:8786"], "unknown scheme 'http'"),
        (["--scheduler", "tcp://no-such-host.invalid:8786"], "the host 'no-such-host.invalid' does not resolve"),
        (["--scheduler", "tcp://127.0.0.1:65536"], "Port out of range"),
        (["--faults", str(bad)], f"{bad}: not UTF-8 text (byte 0xe9 at offset 19)"),
    ]
    for argv, message in cases:
        code, err = campaign_cli(["rover", "--out", str(tmp_path / "out"), *argv], monkeypatch)
        assert code == 2 and message in err and len(err.splitlines()) == 1, f"{argv}: {code} {err}"
    assert not (tmp_path / "out" / "results.jsonl").exists()


RELEASE = threading.Event()


def hang(*_a, **_kw):
    """A run that never ends by itself (until the test lets it go)."""
    RELEASE.wait(60)
    return {}


def someone_elses_work(x):
    RELEASE.wait(60)
    return x * 2


def test_a_hung_campaign_on_a_shared_dask_cluster_cancels_its_own_runs_and_leaves_the_rest(tmp_path, monkeypatch):
    distributed = pytest.importorskip("distributed")
    from host.campaign import runner

    monkeypatch.setattr(runner, "run_one", hang)
    monkeypatch.setattr(runner, "GUARD_S", 0.0)
    monkeypatch.setitem(dask_config(), "temporary-directory", str(tmp_path / "dask"))  # (no scratch left in /tmp)
    campaign = load_campaign("rover", seeds=2, seconds=1.0, timeout_s=1.0)
    RELEASE.clear()
    cluster = distributed.LocalCluster(
        n_workers=1,
        threads_per_worker=3,
        processes=False,
        protocol="tcp",
        host="127.0.0.1",
        dashboard_address=None,
    )
    try:
        with distributed.Client(cluster.scheduler_address) as other:
            workers = set(other.scheduler_info()["workers"])
            theirs = other.submit(someone_elses_work, 21, pure=False)
            results = runner.run_campaign(campaign, tmp_path, scheduler=cluster.scheduler_address)
            assert [r["error"] for r in results] == ["hung", "hung"], results
            assert set(other.scheduler_info()["workers"]) == workers, "expected the cluster's workers not restarted"
            assert theirs.status == "pending", f"expected another client's work left running, got {theirs.status}"
            RELEASE.set()
            assert theirs.result(timeout=10) == 42
    finally:
        RELEASE.set()
        cluster.close()


def dask_config() -> dict:
    """Dask's live configuration (a test points its scratch space at its own folder)."""
    import dask

    return dask.config.config


# -- the worst runs by the judged figure, the lines printed, the page (issue 27 point 9) --


def planted_pool(tmp_path=None) -> list[dict]:
    """A pool campaign of 50 seeds as the showcase gave it: 11 pass (>= 95 %), the 39
    others fail at 89-94.9 %; the five lowest, in order, are seeds 4, 19, 45, 21, 48."""
    lowest = {4: 0.887, 19: 0.889, 45: 0.891, 21: 0.893, 48: 0.895}
    passing = {5, 6, 9, 13, 17, 24, 30, 33, 37, 41, 50}
    runs = []
    for seed in range(1, 51):
        cover = lowest.get(seed, 0.951 + seed / 10_000 if seed in passing else 0.90 + seed / 1_000)
        message = "" if seed in passing else f"expected >= 95 % of the floor covered, got {cover:.1%}"
        run = result(f"sonar-faults/default/{seed}", seed in passing, coverage=cover, mission_min=55 + seed % 4)
        runs.append({**run, "message": message, "wall_s": 40.0, "t_end_s": 3400.0, "error": None})
    return runs


POOL = {"name": "pool_placement", "rig": "pool_cleaner", "judge": "pool_mission", "seeds": 50, "first_seed": 1}


def test_the_worst_runs_are_the_worst_by_the_judged_figure_failed_first():
    runs = planted_pool()
    by, low = report_module.judged_by(POOL)
    assert (by, low) == ("coverage", True), "a pool mission is judged by coverage, higher better"
    keys = [r["seed"] for r in worst(runs, by, low)]
    assert keys[:5] == [4, 19, 45, 21, 48], f"expected the lowest coverage first, got seeds {keys}"
    as_filed = [r["seed"] for r in worst(runs, "coverage", low=True)]  # the showcase's worst_low = true
    assert as_filed[:5] == [4, 19, 45, 21, 48], f"the failed runs are ranked by coverage too, got {as_filed}"


def test_each_figure_has_its_direction_and_an_error_run_is_worse_than_any_figure():
    assert report_module.judged_by({"judge": "duct_branch"}) == ("home_off_m", False)
    assert report_module.judged_by({"worst_by": "mission_min"}) == ("mission_min", False)
    assert report_module.judged_by({"worst_by": "coverage", "worst_low": False}) == ("coverage", False)
    runs = [
        result("a/w/1", True, mission_min=50.0),
        result("a/w/2", True, mission_min=58.0),
        result("a/w/3", False, mission_min=51.0),
        result("a/w/4", False),  # (a run that ended in an error has no figures)
        result("a/w/5", False, mission_min=57.0),
    ]
    assert [r["seed"] for r in worst(runs, "mission_min", low=False)] == [4, 5, 3, 2, 1]


def test_counts_get_whole_number_bins():
    edges = report_module.histogram_bins([0, 1, 1, 2, 4], integer=True)
    assert list(edges) == [-0.5, 0.5, 1.5, 2.5, 3.5, 4.5], edges
    wide = report_module.histogram_bins(list(range(0, 200, 7)), integer=True)
    steps = set(float(x) for x in (wide[1:] - wide[:-1]))
    assert len(steps) == 1 and steps.pop().is_integer() and all((e - 0.5).is_integer() for e in wide), wide


def test_the_command_prints_a_line_per_group_saying_a_showcase_rate_is_the_expected_one():
    runs = planted_pool()
    showcase = {**POOL, "expected": {"sonar-faults": 0.22}, "explained": "docs/campaigns.md, The pool cleaner"}
    lines = report_module.summary_lines(showcase, runs)
    assert lines[0] == (
        "  sonar-faults / default: 11 of 50 passed, 22% [95 % Wilson 13%-35%]: the expected showcase figure "
        "(about 22%; explained in docs/campaigns.md, The pool cleaner)"
    ), lines
    assert "    39 failed: expected >= 95 % of the floor covered" in lines, lines
    assert lines[-1].startswith("    worst by floor covered: seed 4 (88.7 %), seed 19 (88.9 %)"), lines
    off = report_module.summary_lines({**showcase, "expected": {"sonar-faults": 0.9}}, runs)
    assert "NOT the showcase's expected 90%" in off[0], off
    assert ": " not in report_module.summary_lines(POOL, runs)[0].split("]")[1], "no note without an expectation"
    line = report_module.progress_line(runs[3], 4, 50, "coverage", 2.5)
    assert line.startswith("[4/50] fail sonar-faults/default/4 floor covered 88.7 %, 40 s: expected >= 95 %"), line


def planted_grid(out: Path, key: str, missed_rows: int) -> None:
    """A 25 x 8 m floor of 5 cm cells, covered but for ``missed_rows`` rows along y = 0."""
    import numpy as np

    free = np.ones((160, 500), dtype=bool)
    covered = free.copy()
    covered[:missed_rows, :] = False
    folder = out / "runs" / key
    folder.mkdir(parents=True)
    np.savez_compressed(
        folder / "coverage.npz",
        covered=covered,
        free=free,
        extent=np.array([0.0, 25.0, 0.0, 8.0]),
        start=np.array([24.5, 0.3, 3.14]),
        end=np.array([0.5, 7.5, 0.0]),
    )


def test_the_page_maps_where_each_worst_run_missed_the_floor_with_files_beside_it(tmp_path):
    runs = planted_pool()
    planted_grid(tmp_path, "sonar-faults/default/4", missed_rows=7)
    paths = write_report(tmp_path, POOL, runs)
    page = paths["html"].read_text()
    src = "maps/sonar-faults_default_4.png"
    assert f'src="{src}"' in page and (tmp_path / src).stat().st_size > 5000, "expected the map of seed 4's floor"
    assert "8.40 m² along the side wall at y = 0.0 m" in page, "expected the missed strip measured along its wall"
    first = page.index('id="w0"')
    assert "sonar-faults/default/4" in page[first : first + 400], "expected seed 4 first of the worst runs"
    assert "floor covered" in page and "mission time (min)" in page, "expected readable figure names"
    text = re.sub(r"<[^>]+>", " ", page)
    assert "mission_min" not in text and "coverage_fraction" not in text, "a raw key shown as a name"
    assert '{"' not in page and "&quot;" not in text, "expected the set-up as a table, not JSON"
    assert "<th>judge</th><td>pool_mission</td>" in page and "seeds</th><td>50: 1 to 50" in page


def test_missed_floor_is_counted_by_the_wall_it_lies_along():
    import numpy as np

    from host.campaign.maps import missed_by_place

    free = np.ones((160, 500), dtype=bool)
    covered = free.copy()
    covered[150:, :] = False  # 10 rows, 0.5 m along y = 8 m
    covered[80, 100:140] = False  # 2 m of a lane's edge in the middle
    where = missed_by_place(covered, free, (0.0, 25.0, 0.0, 8.0))
    assert where["along the side wall at y = 8.0 m"] == pytest.approx(10 * 480 * 0.0025)  # (0.5 m of each end:
    assert where["in the corners"] == pytest.approx(10 * 20 * 0.0025)  # the corners)
    assert where["in the middle, between lanes"] == pytest.approx(40 * 0.0025)
    assert where["along the side wall at y = 0.0 m"] == 0.0


def test_a_declared_judges_campaign_is_ranked_by_the_figure_its_rig_file_judges():
    runs = [result("a/w/1", True, t_end_s=4.0, coverage=0.97), result("a/w/2", True, t_end_s=4.0, coverage=0.90)]
    assert report_module.judged_by({"judge": "declared"}, runs) == ("coverage", True)
    assert report_module.judged_by({"judge": "declared"}, [result("a/w/1", True, t_end_s=4.0)]) == ("t_end_s", False)

"""The campaign's parts without firmware (host/campaign, docs/campaigns.md): the
scenario file and its mistakes, the rig file's [[faults]], the Wilson interval, the worst
runs, the placement error, the results file."""

import json

import pytest

from host.campaign import load_campaign, task_key
from host.campaign.report import summarize, wilson, worst
from host.campaign.store import ResultStore
from host.campaign.worker import placed
from host.core.errors import ConfigError
from host.rig.rigfile import load_rig

RIG = """
name = "bench"
[firmware]
dir = "."
[board.pins]
A = 1
[plant]
kind = "wires"
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
    assert app.heap_size == "96K" and [f.kind for f in app.extra["faults"]] == ["heap"]
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

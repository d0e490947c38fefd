"""``host/bench/plant_share.py``: the calls a rig makes on its plant, recorded in a run and
replayed on a fresh plant, give the run's results again (so the replay's CPU time is the
plant's own work), and a replay that differs is refused, naming the call."""

import pytest

from host import bench
from host.rig import Recording, Rig, RigSpec
from host.rig.loop.spec import build_plant


def _tool():
    return bench.plant_share()


def _recorded(tool, sim_s: float):
    spec = RigSpec("rover", seed=1, busy_poll=False)
    plant, _ = build_plant(spec, spec.resolve())
    recorded = tool.RecordedPlant(plant)
    with Rig(spec, Recording(), plant=recorded) as rig:
        rig.run_for(sim_s)
        truth = rig.truth()
    return spec, recorded.calls, truth


def test_a_runs_plant_calls_replayed_on_a_fresh_plant_give_its_results_and_its_ground_truth():
    tool = _tool()
    spec, calls, truth = _recorded(tool, 3.0)
    names = {c[0] for c in calls}
    assert {"reset", "set_input", "snapshot", "advance_to", "next_change_us"} <= names, names
    fresh, _ = build_plant(spec, spec.resolve())
    tool.replay(fresh, calls, True, [])
    assert fresh.t_us == 3_000_000, f"expected the replay to end at the run's 3 s, got {fresh.t_us} us"
    assert fresh.truth() == truth, f"expected the run's ground truth\n{truth}\nafter the replay, got\n{fresh.truth()}"


def test_a_replay_that_differs_from_the_run_is_refused_naming_the_call():
    tool = _tool()
    spec, calls, _ = _recorded(tool, 1.0)
    i = next(i for i, c in enumerate(calls) if c[0] == "advance_to" and c[2])
    name, args, result = calls[i]
    calls[i] = (name, args, result[:-1])  # (as if the rig had changed the plant outside its calls)
    fresh, _ = build_plant(spec, spec.resolve())
    with pytest.raises(SystemExit) as e:
        tool.replay(fresh, calls, True, [])
    assert f"call {i} (advance_to" in str(e.value) and "changed the plant outside its calls" in str(e.value), e.value


def test_the_tool_prints_the_hosts_and_the_plants_time_an_exchange_beside_what_the_share_leaves(capsys):
    assert _tool().main(["rover", "1", "--repeat", "1"]) == 0
    out = capsys.readouterr().out
    assert "rover: 1 simulated s, 20 exchanges, " in out, out
    assert "the plant's own calls replayed: " in out and "at 65% of it an exchange may take " in out, out


def test_make_bench_prints_each_robots_plant_share_against_what_65_percent_leaves(capsys):
    m = {"robot": "rover", "sim_s": 60.0, "repeat": 3, "exchanges": 1200, "plant_calls": 6000, "raw_us": 20.0}
    m.update(host_us=100.0, system_us=10.0, plant_us=40.0, fw_us=45.0)
    bench.report_plant_shares([m])
    out = capsys.readouterr().out
    # (floor 65 us; at 65 % an exchange may take 100 us: 35 us for the host, the plant 114 % of it)
    assert out.startswith("  rover, 60 simulated s, busy polling off: host CPU an exchange"), out
    assert (
        "leaves the host 35.0 us beyond the floor: the plant alone takes 114% of that, the host's user time 286%" in out
    )

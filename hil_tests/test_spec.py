"""One spec builds every rig (host/rig/loop/spec.py): the CLI, the pytest plugin and a
campaign's worker given the same spec run the same link trace and record the same spec,
which a replay reads back; a campaign runs a rig file written as a body and parts.

Run from a flashed board (``make hil FIRMWARE=build/vboard/<board>/fs``), the plugin's rigs
run the flashed files while the CLI and a worker run the app's sources: the plugin's trace
must then be theirs but for its header's firmware (hil_tests/flashed.py), and a replay runs
the flashed files its recording ran."""

import hashlib
import json

import pytest
from flashed import as_from_sources, ran_from_flash

from host.campaign import load_campaign
from host.campaign.runner import run_campaign
from host.campaign.worker import run_one
from host.cli import main
from host.core.paths import REPO
from host.rig import Rig, RigSpec
from host.rig.loop.replay import FirmwareChoice, replay
from host.rig.loop.spec import build_plant, fault_schedule, placed
from host.rig.targets.target import FaultyLinkTarget
from sim_plant.faults import FaultyPlant

pytestmark = pytest.mark.hil

SECONDS = 2.0
TWO_SONAR = REPO / "examples" / "two_sonar_bot" / "rig.toml"


def _recorded(folder, rig=None) -> tuple[str, dict]:
    """(the sha256 of the folder's trace.jsonl, as from the sources when ``rig`` ran from a
    flash, the spec its header recorded)."""
    trace = (folder / "trace.jsonl").read_bytes()
    digest = hashlib.sha256(as_from_sources(trace, rig) if rig else trace).hexdigest()
    return digest, json.loads((folder / "header.json").read_text())["spec"]


def test_the_cli_the_plugin_and_a_campaign_worker_run_the_same_spec_to_the_same_link_trace(make_rig, tmp_path):
    cli = tmp_path / "cli"
    argv = ["run", "--world", "long-room", "--seed", "3", "--duration", str(SECONDS), "--out", str(cli), "--no-plots"]
    assert main(argv) == 0

    rig = make_rig("rover", world="long-room", seed=3, trace=True, record=True, artefacts=tmp_path / "plugin")
    rig.run_for(SECONDS)
    rig.stop()

    task = {"rig": "rover", "world": "long-room", "seed": 3, "faults": [], "faultset": "none", "budgets": []}
    task.update(seconds=SECONDS, step_s=SECONDS, judge="generic", timeout_s=120)
    result = run_one(task, str(tmp_path / "worker"), record=True)
    assert result["passed"], result["message"]

    runs = {name: _recorded(tmp_path / name, rig if name == "plugin" else None) for name in ("cli", "plugin", "worker")}
    specs = {name: spec for name, (_d, spec) in runs.items()}
    assert specs["cli"] == specs["plugin"] == specs["worker"], specs
    assert specs["cli"]["world"] == "long-room" and specs["cli"]["seed"] == 3
    digests = {name: digest for name, (digest, _s) in runs.items()}
    assert len(set(digests.values())) == 1, f"expected one link trace, got {digests}"
    assert rig.trace_digest == hashlib.sha256((tmp_path / "plugin" / "trace.jsonl").read_bytes()).hexdigest()
    assert RigSpec.from_header({"spec": specs["cli"]}) == RigSpec("rover", board=rig.board, world="long-room", seed=3)


def test_a_spec_builds_the_plant_of_its_world_with_its_options_over_the_worlds():
    spec = RigSpec("rover", world="long-room", seed=3, options={"room_h_m": 5.0})
    plant, options = build_plant(spec, spec.resolve())
    assert options == {"room_w_m": 8.0, "room_h_m": 5.0}
    assert (plant.body.options["room_w_m"], plant.body.options["room_h_m"]) == (8.0, 5.0)
    with pytest.raises(AttributeError):
        spec.seed = 4  # frozen


def test_a_campaign_runs_a_rig_file_of_a_body_and_parts(tmp_path):
    scenario = tmp_path / "two_sonar.toml"
    scenario.write_text(
        f"""
[campaign]
rig = "{TWO_SONAR}"
seconds = 3
step_s = 0.5
judge = "generic"
until = "two_sonar_bot: pressed"
seeds = 2
timeout_s = 120
placement = {{ x_m = [-0.05, 0.05], theta_deg = [-3, 3] }}

[[faultsets]]
name = "none"

[[faultsets]]
name = "rear-sonar-dropout"
[[faultsets.faults]]
kind = "dropout"
signal = "sonar_rear.echo"
"""
    )
    campaign = load_campaign(str(scenario))
    results = run_campaign(campaign, tmp_path / "out", workers=2)
    assert len(results) == 4
    failed = [f"{r['key']}: {r['message'][:300]}" for r in results if not r["passed"]]
    assert not failed, f"expected every run of the body+parts rig to pass: {failed}"
    keys = sorted(r["key"] for r in results)
    assert keys == [f"{f}/box-ahead/{s}" for f in ("none", "rear-sonar-dropout") for s in (1, 2)]
    assert all(r["t_end_s"] >= 1.0 for r in results), "expected each run to the button's press (1 s in)"


def test_a_replay_rebuilds_the_spec_its_folder_recorded(make_rig, tmp_path):
    spec = {"world": "small-room", "seed": 5, "plant_options": {"room_w_m": 3.5}}
    rig = make_rig("rover", trace=True, record=True, artefacts=tmp_path / "run", **spec)
    rig.run_for(1.5)
    rig.stop()
    # (from a flash: the flashed files, which the recording's manifest lists, not the app's sources)
    choice = FirmwareChoice(firmware=rig.spec.firmware_dir) if ran_from_flash(rig) else FirmwareChoice()
    result = replay(tmp_path / "run", tmp_path / "replay", choice=choice)
    assert result.same and result.recorded > 0, str(result.difference)
    recorded, replayed = (json.loads((tmp_path / f / "header.json").read_text()) for f in ("run", "replay"))
    assert replayed["spec"] == recorded["spec"]
    assert recorded["spec"]["world"] == "small-room" and recorded["spec"]["options"] == {"room_w_m": 3.5}
    assert replayed["plant_options"]["start_pose"] == [1.0, 1.5, 0.0], "expected the world's start pose"


def test_a_specs_link_faults_go_under_the_channel_wherever_it_runs():
    stall = {"kind": "link_stall", "direction": "both", "rate": 0.02, "stall_ms": 5}
    assert isinstance(Rig(RigSpec("rover", faults=[stall])).target, FaultyLinkTarget)
    assert not isinstance(Rig(RigSpec("rover")).target, FaultyLinkTarget)


def test_a_rig_files_faults_stay_inside_and_a_specs_wrap_them_once_as_a_schedule_of_their_own(tmp_path):
    rig_file = tmp_path / "rig.toml"
    (tmp_path / "main.py").write_bytes((TWO_SONAR.parent / "main.py").read_bytes())
    rig_file.write_text(TWO_SONAR.read_text() + '\n[[faults]]\nkind = "dropout"\nsignal = "sonar_front.echo"\n')
    spec = RigSpec(str(rig_file), faults=[{"kind": "dropout", "signal": "sonar_rear.echo"}])
    plant, _options = build_plant(spec, spec.resolve())
    assert isinstance(plant, FaultyPlant) and isinstance(plant.inner, FaultyPlant), "expected two wrappers"
    assert [(f.signal, f.index) for f in plant.schedule] == [("sonar_rear.echo", 0)], "the spec's, indexed alone"
    assert [(f.signal, f.index) for f in plant.inner.schedule] == [("sonar_front.echo", 0)], "the rig file's"
    assert [f.signal for f in fault_schedule(spec, spec.resolve())] == ["sonar_front.echo", "sonar_rear.echo"]


def test_a_placed_start_is_the_plants_pose_at_time_zero_moved_by_the_seeds_draw():
    spec = RigSpec(str(TWO_SONAR), seed=4, placement={"x_m": [-0.05, 0.05], "theta_deg": [-3, 3]})
    plant, options = build_plant(spec, spec.resolve())
    bare, _ = build_plant(RigSpec(str(TWO_SONAR), seed=4), spec.resolve())
    assert options["start_pose"] == placed(bare.pose_at(0), spec.placement_ranges, 4)
    assert options["start_pose"] != [1.0, 1.0, 0.0] and plant.pose_at(0) == pytest.approx(options["start_pose"])

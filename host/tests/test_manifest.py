"""A run's manifest.json (host/rig/loop/manifest.py, docs/traces.md) and replay's check of it."""

import hashlib
import json
import subprocess
import sys
from importlib import metadata

import pytest

from host.artefacts.folder import reseal
from host.core import interpreter
from host.core.paths import REPO, SHIM_DIR
from host.rig.loop import manifest
from host.rig.loop.replay import FirmwareChoice, ManifestMismatch, replay
from host.tests.test_coverage import covbot

pytestmark = pytest.mark.hil
TRUSTED = FirmwareChoice(trust_folder=True)  # (the recording's rig file is the test's own)


def sha256(path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def recorded(make_rig, tmp_path, presses="[[0.2, 0.4]]", **kw):
    rig_file = covbot(tmp_path / "bot", presses)
    rig = make_rig(str(rig_file), seed=7, record=True, trace=True, artefacts=tmp_path / "run", **kw)
    rig.run_for(1.0)
    rig.stop()
    return rig_file.parent, tmp_path / "run"


def edited_replay(run, tmp_path, changes: dict) -> list:
    """``run``'s manifest with ``changes`` (``"part.field": value``) written in: the replay
    command of that folder."""
    found = json.loads((run / "manifest.json").read_text())
    for where, value in changes.items():
        part, field = where.split(".")
        found[part][field] = value
    (run / "manifest.json").write_text(json.dumps(found))
    reseal(run)  # (an edit on purpose: else the seal refuses the folder)
    return [sys.executable, "-m", "host.cli", "replay", str(run), "--trust-folder", "--out", str(tmp_path / "o")]


def test_a_runs_manifest_names_every_file_the_build_the_shim_the_plant_and_the_tools(make_rig, tmp_path):
    firmware, run = recorded(make_rig, tmp_path)
    found = json.loads((run / "manifest.json").read_text())
    files = found["firmware"]["files"]
    assert files["main.py"]["sha256"] == sha256(firmware / "main.py")
    assert files["reaction.py"]["sha256"] == sha256(firmware / "reaction.py")
    header = json.loads((run / "header.json").read_text())
    link_header = json.loads((run / "trace.jsonl").read_text().splitlines()[0])["header"]
    assert found["firmware"]["sha256"] == link_header["firmware"]["sha256"], "the digest the trace names"
    assert header["files"]["manifest.json"] == sha256(run / "manifest.json"), "sealed with the folder's files"
    binary = interpreter.find()
    build = found["interpreter"]
    assert build["sha256"] == sha256(binary) and build["variant"] == "standard"
    assert build["version"].startswith("MicroPython v1.25.0")
    ours = list(interpreter.make_options("standard"))
    assert build["make_options"] in (ours, None)  # (None: a $MICROPYTHON of one's own)
    assert found["shim"]["files"]["_hilboot.py"] == sha256(SHIM_DIR / "_hilboot.py")
    assert set(found["shim"]["files"]) >= {"machine.py", "time.py", "_hil.py", "_hilcov.py"}
    parts = {p["name"]: p for p in found["plant"]["parts"]}
    assert parts["btn"]["kind"] == "button" and parts["btn"]["options"]["presses"] == [[0.2, 0.4]]
    assert found["run"]["seed"] == 7 and found["run"]["faults"] == [] and found["run"]["mode"] == "lockstep"
    assert found["tools"]["numpy"] == metadata.version("numpy") and found["tools"]["coverage"] == "7.17.3"
    assert found["harness"]["commit"] == header["commit"]


def test_the_manifest_hashes_an_entry_file_outside_the_firmware_folder(make_rig, tmp_path):
    firmware = covbot(tmp_path / "bot", "[]").parent
    (tmp_path / "elsewhere").mkdir()
    (tmp_path / "elsewhere" / "main.py").write_text((firmware / "main.py").read_text() + "# the one that runs\n")
    (tmp_path / "elsewhere" / "reaction.py").write_text((firmware / "reaction.py").read_text())
    rig = make_rig(str(firmware / "rig.toml"), main_dir=tmp_path / "elsewhere", trace=True, artefacts=tmp_path / "r")
    rig.run_for(0.2)
    rig.stop()
    found = json.loads((tmp_path / "r" / "manifest.json").read_text())
    entry = found["firmware"]["files"]["main.py"]
    assert entry["sha256"] == sha256(tmp_path / "elsewhere" / "main.py") != sha256(firmware / "main.py")
    assert entry["source"] == str((tmp_path / "elsewhere" / "main.py").resolve())


def test_a_run_with_coverage_names_the_settrace_build(make_rig, tmp_path, settrace):
    _, run = recorded(make_rig, tmp_path, coverage=tmp_path / ".coverage.run")
    build = json.loads((run / "manifest.json").read_text())["interpreter"]
    assert build["variant"] == "settrace" and build["sha256"] == sha256(interpreter.find_variant("settrace"))
    if build["make_options"] is not None:
        assert "CFLAGS_EXTRA=-DMICROPY_PY_SYS_SETTRACE=1" in build["make_options"]


def test_replay_names_a_changed_firmware_file_and_goes_on_only_when_told(make_rig, tmp_path):
    firmware, run = recorded(make_rig, tmp_path)
    same = replay(run, tmp_path / "again", choice=TRUSTED)
    assert same.same and same.manifest == [], same.manifest
    (firmware / "reaction.py").write_text((firmware / "reaction.py").read_text().replace("count += 1", "count += 2"))
    with pytest.raises(ManifestMismatch) as refused:
        replay(run, tmp_path / "refused", choice=TRUSTED)
    assert [line.split(":")[0] for line in refused.value.lines] == ["firmware file reaction.py"], refused.value.lines
    assert "--ignore-manifest" in str(refused.value) and not (tmp_path / "refused" / "trace.jsonl").exists()
    anyway = replay(run, tmp_path / "anyway", choice=TRUSTED, ignore_manifest=True)
    assert anyway.manifest and anyway.manifest[0].startswith("firmware file reaction.py: was ")
    named = replay(run, tmp_path / "named", choice=FirmwareChoice(app=str(firmware / "rig.toml")))
    assert named.manifest == anyway.manifest, "a firmware the user names may differ: listed, not refused"


def test_replay_of_a_folder_without_a_manifest_says_it_was_not_checked(make_rig, tmp_path):
    _, run = recorded(make_rig, tmp_path)
    (run / "manifest.json").unlink()
    reseal(run)  # (a folder written before manifests: nothing else is missing)
    result = replay(run, tmp_path / "again", choice=TRUSTED)
    assert result.same and result.manifest is None


def test_mpy_fil_replay_prints_each_difference_and_exits_1_unless_told(make_rig, tmp_path):
    _, run = recorded(make_rig, tmp_path)
    cmd = edited_replay(run, tmp_path, {"interpreter.sha256": "0" * 64, "tools.numpy": "1.0.0"})
    refused = subprocess.run(cmd, capture_output=True, text=True, cwd=REPO, timeout=120)
    assert refused.returncode == 1 and "Traceback" not in refused.stderr, refused.stderr
    assert "  interpreter.sha256: was 000000000000, now " in refused.stderr
    assert f"  tools.numpy: was 1.0.0, now {metadata.version('numpy')}" in refused.stderr
    went = subprocess.run([*cmd, "--ignore-manifest"], capture_output=True, text=True, cwd=REPO, timeout=120)
    assert went.returncode == 0, went.stdout + went.stderr
    assert "manifest differs: tools.numpy: was 1.0.0" in went.stdout and "same outputs" in went.stdout


def test_differences_are_one_line_each_and_ignore_where_a_checkout_lives():
    was = {
        "interpreter": {"path": "/a/micropython", "sha256": "a" * 64},
        "shim": {"sha256": "x", "files": {"t.py": "1"}},
    }
    now = {
        "interpreter": {"path": "/b/micropython", "sha256": "a" * 64},
        "shim": {"sha256": "y", "files": {"t.py": "2"}},
    }
    assert manifest.differences(was, now) == ["shim file t.py: was 1, now 2"]
    now["tools"] = {"numpy": "2.4.6"}
    assert manifest.differences(was, now)[-1] == "tools.numpy: not in the recording, now 2.4.6"


def test_a_newer_harness_or_tool_is_told_but_does_not_stop_a_replay(make_rig, tmp_path):
    """A regression check replays an old recording with a newer harness: its commit and its
    tools' versions are listed, and the replay runs (a commit made while a run was recorded
    stopped every replay before)."""
    _, run = recorded(make_rig, tmp_path)
    cmd = edited_replay(run, tmp_path, {"harness.commit": "0" * 40, "tools.numpy": "1.0.0"})
    went = subprocess.run(cmd, capture_output=True, text=True, cwd=REPO, timeout=120)
    assert went.returncode == 0, went.stdout + went.stderr
    assert "manifest differs: harness.commit: was 0000000000000000000000000000000000000000" in went.stdout, went.stdout
    assert "manifest differs: tools.numpy: was 1.0.0" in went.stdout and "same outputs" in went.stdout

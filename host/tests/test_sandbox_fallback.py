"""Where the sandbox cannot start (no bwrap, a kernel that refuses namespaces), a run goes
on under the shim's confinement; how loudly it says so depends on whose firmware it is
(host/rig/targets/sandbox.py, docs/security.md): a received folder (outside the user's own git
work tree and the harness's examples) gets a warning block on stderr, the user's own a
note; the manifest records how it ran; "require" refuses the run."""

import json
import shutil

import pytest

from host.core.paths import REPO
from host.rig.targets import sandbox
from host.tests.conftest import run_cli

pytestmark = pytest.mark.hil

REFUSED = "the kernel refuses new namespaces (forced by the test)"


@pytest.fixture
def no_sandbox(monkeypatch):
    """The sandbox unavailable, as on a machine without bwrap or user namespaces."""
    monkeypatch.setattr(sandbox, "refusal", lambda: REFUSED)
    monkeypatch.setattr(sandbox, "_said", set())
    monkeypatch.delenv(sandbox.ENV, raising=False)


def firmware_folder(where):
    folder = where / "pico_bot"
    folder.mkdir(parents=True)
    shutil.copy(REPO / "examples" / "pico_bot" / "main.py", folder)
    shutil.copy(REPO / "examples" / "pico_bot" / "rig.toml", folder)
    return folder


def run(folder, out):
    code, _stdout, err = run_cli("run", folder / "rig.toml", "--duration", "0.2", "--out", out, "--no-plots")
    return code, err, json.loads((out / "manifest.json").read_text()) if (out / "manifest.json").is_file() else None


def test_a_received_firmware_without_the_sandbox_is_warned_of_in_a_block_and_in_its_manifest(no_sandbox, tmp_path):
    folder = firmware_folder(tmp_path / "downloads")  # (pytest's cwd is a work tree; this is outside it)
    with pytest.warns(sandbox.SandboxWarning, match="runs WITHOUT the sandbox"):
        code, err, manifest = run(folder, tmp_path / "out")
    assert code == 0, err
    lines = [line for line in err.splitlines() if line.startswith("mpy-fil: WARNING")]
    assert len(lines) >= 8, f"expected a warning block, got:\n{err}"
    text = "\n".join(lines)
    assert str(folder) in text and REFUSED in text and f"{sandbox.ENV}=require" in text, text
    assert "note:" not in err, err
    assert manifest["sandbox"] == {"setting": "auto", "running": False, "why": REFUSED, "received": True}, manifest


def test_the_users_own_firmware_without_the_sandbox_gets_a_note_and_its_manifest_says_so(
    no_sandbox, tmp_path, monkeypatch
):
    repo = tmp_path / "my_robot"
    (repo / ".git").mkdir(parents=True)  # the user's own repository, the command run inside it
    folder = firmware_folder(repo / "firmware")
    monkeypatch.chdir(repo)
    code, err, manifest = run(folder, tmp_path / "out")
    assert code == 0, err
    assert "WARNING" not in err and err.count("mpy-fil: note: the firmware runs without a sandbox") == 1, err
    assert manifest["sandbox"] == {"setting": "auto", "running": False, "why": REFUSED, "received": False}, manifest


def test_a_received_firmware_with_the_sandbox_required_is_not_started_and_the_message_says_why(
    no_sandbox, tmp_path, monkeypatch
):
    folder = firmware_folder(tmp_path / "downloads")
    monkeypatch.setenv(sandbox.ENV, "require")
    code, err, manifest = run(folder, tmp_path / "out")
    assert code != 0 and manifest is None, err
    assert f"the sandbox is required ({sandbox.ENV}=require) but {REFUSED}" in err, err
    assert f"the firmware in {folder} was not started" in err, err


def test_a_rig_file_that_requires_the_sandbox_names_itself_when_it_cannot_start(no_sandbox, tmp_path):
    folder = firmware_folder(tmp_path / "downloads")
    rig = folder / "rig.toml"
    rig.write_text(rig.read_text().replace("[board.pins]", '[board]\nsandbox = "require"\n\n[board.pins]', 1))
    code, err, _manifest = run(folder, tmp_path / "out")
    assert code != 0, err
    assert 'the sandbox is required ([board] sandbox = "require" in the rig file)' in err, err


@pytest.mark.parametrize(
    ("where", "cwd", "received"),
    [
        ("elsewhere/fw", "mine", True),  # a folder beside one's own repository
        ("mine/fw", "mine", False),  # in the repository the command runs in
        ("mine/fw", "elsewhere", True),  # one's own repository, but run from somewhere with no work tree
    ],
)
def test_whose_firmware_it_is_follows_the_work_tree_the_command_runs_in(tmp_path, where, cwd, received):
    (tmp_path / "mine" / ".git").mkdir(parents=True)
    (tmp_path / "elsewhere").mkdir()
    assert sandbox.received(tmp_path / where, tmp_path / cwd) is received


def test_the_harness_own_examples_are_never_received(tmp_path):
    assert not sandbox.received(REPO / "examples" / "pico_bot", tmp_path)

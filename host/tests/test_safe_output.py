"""No command writes outside the folder it names, or over its own input (issue 40,
``docs/security.md``): for each command that writes (run, replay, plot, diff, shrink,
init, import-wokwi, campaign, scenario, setup) a link where it would write, or an output
folder that is (or holds, or lies inside) its input, is refused with exit code 2 and a
message naming it, and nothing outside is written: the link's target is unchanged, no file
is made at a dangling link's target, the input is as it was. A FIFO in a folder a command
reads is named and skipped, never opened; Wokwi's MicroPython template (a folder per
board, one ``main.py`` at the root) runs as it is laid out."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from host.artefacts import integrity
from host.core import interpreter, paths, safefs
from host.core.errors import OutputRefused
from host.tests.conftest import run_cli

HERE = Path(__file__).parent
PROJECT = HERE / "wokwi_projects" / "devkit_v1_button"  # a Wokwi project: diagram.json, main.py
SCENARIO = HERE / "wokwi_scenarios" / "button_irq"  # a rig.toml, main.py and press.test.yaml


@pytest.fixture(scope="module")
def recorded(tmp_path_factory) -> Path:
    """A recorded run's trace folder (copied by each test that uses it)."""
    out = tmp_path_factory.mktemp("recorded") / "run"
    code, _, err = run_cli("run", "--app", "rover", "--duration", "1", "--out", out, "--no-plots")
    assert code == 0, err
    return out


def snapshot(folder: Path) -> dict:
    """Every entry below ``folder`` (links not followed): its bytes, or where it points."""
    found = {}
    for top, dirs, files in os.walk(folder):
        for name in [*dirs, *files]:
            path = Path(top, name)
            rel = path.relative_to(folder).as_posix()
            if path.is_symlink():
                found[rel] = ("link", os.readlink(path))
            elif path.is_file():
                found[rel] = path.read_bytes()
            else:
                found[rel] = "folder"
    return found


class World:
    """A test's folders: ``victim`` outside everything a command is given (a file
    ``keep.txt`` in it), ``trace`` a copy of a recorded run, ``tmp`` the rest."""

    def __init__(self, tmp: Path, recorded: Path):
        self.tmp = tmp
        self.victim = tmp / "victim"
        self.victim.mkdir()
        (self.victim / "keep.txt").write_text("the link's target\n")
        self.trace = tmp / "trace"
        shutil.copytree(recorded, self.trace)

    def link(self, at: Path, to: Path) -> Path:
        at.parent.mkdir(parents=True, exist_ok=True)
        at.symlink_to(to)
        return at

    def project(self, source: Path = PROJECT, name: str = "proj") -> Path:
        folder = self.tmp / name
        shutil.copytree(source, folder, ignore=shutil.ignore_patterns("build"))
        return folder


def _run_out_link(w):
    return ["run", "--app", "rover", "--duration", "1", "--no-plots", "--out", w.link(w.tmp / "o", w.victim)]


def _run_console_link(w):
    w.link(w.tmp / "o" / "console.log", w.victim / "keep.txt")
    return ["run", "--app", "rover", "--duration", "1", "--no-plots", "--out", w.tmp / "o"]


def _run_trace_log_dangling(w):
    w.link(w.tmp / "o" / "trace.jsonl", w.victim / "new.txt")
    return ["run", "--app", "rover", "--duration", "1", "--no-plots", "--out", w.tmp / "o"]


def _run_out_is_firmware(w):
    proj = w.project(SCENARIO)
    return ["run", proj / "rig.toml", "--duration", "1", "--no-plots", "--out", proj]


def _run_default_build_link(w):
    proj = w.project(SCENARIO)
    w.link(proj / "build", w.victim)
    return ["run", proj / "rig.toml", "--duration", "1", "--no-plots"]


def _campaign(out):
    """A campaign of the rover's, one seed of 1 s on one worker, into ``out``."""
    return ["campaign", "rover", "--seeds", "1", "--seconds", "1", "--workers", "1", "--out", out]


CASES = {
    # command: [(case, argv of the world, the message's words), ...]
    "run": [
        ("its --out a link", _run_out_link, "o is a link to"),
        ("console.log a link", _run_console_link, "console.log is a link to"),
        ("trace.jsonl a dangling link", _run_trace_log_dangling, "trace.jsonl is a link to"),
        ("--out the firmware folder", _run_out_is_firmware, "is the firmware folder"),
        ("the default build/ a link", _run_default_build_link, "build is a link to"),
    ],
    "replay": [
        ("--out its own recording", lambda w: ["replay", w.trace, "--out", w.trace], "is the trace folder TRACE"),
        ("--out around it", lambda w: ["replay", w.trace, "--out", w.tmp], "holds the trace folder TRACE"),
        ("--out inside it", lambda w: ["replay", w.trace, "--out", w.trace / "x"], "lies inside the trace folder"),
        (
            "its replay/ a link",
            lambda w: ["replay", w.trace, *(() if w.link(w.trace / "replay", w.victim) else ())],
            "replay is a link to",
        ),
    ],
    "plot": [
        (
            "its plots/ a link",
            lambda w: ["plot", w.trace, *(() if w.link(w.trace / "plots", w.victim) else ())],
            "plots is a link to",
        ),
        ("--out its trace folder", lambda w: ["plot", w.trace, "--out", w.trace], "is the trace folder TRACE"),
        (
            "--out a dangling link",
            lambda w: ["plot", w.trace, "--out", w.link(w.tmp / "p", w.victim / "new")],
            "p is a link to",
        ),
    ],
    "diff": [
        (
            "B's diff/ a link",
            lambda w: ["diff", w.trace, w.trace, *(() if w.link(w.trace / "diff", w.victim) else ())],
            "diff is a link to",
        ),
        ("--out A", lambda w: ["diff", w.trace, w.trace, "--out", w.trace], "is the trace folder A"),
    ],
    "shrink": [
        ("--out its run", lambda w: ["shrink", w.trace, "--out", w.trace], "is the run RUN"),
        ("--out a link", lambda w: ["shrink", w.trace, "--out", w.link(w.tmp / "s", w.victim)], "s is a link to"),
    ],
    "init": [
        (
            "rig.toml a dangling link",
            lambda w: ["init", w.link(w.project() / "rig.toml", w.victim / "new.toml").parent],
            "rig.toml is a link to",
        ),
        (
            "rig.toml a link to a file",
            lambda w: ["init", w.link(w.project() / "rig.toml", w.victim / "keep.txt").parent],
            "rig.toml is a link to",
        ),
    ],
    "import-wokwi": [
        (
            "rig.toml a dangling link",
            lambda w: ["import-wokwi", w.link(w.project() / "rig.toml", w.victim / "new.toml").parent],
            "rig.toml is a link to",
        ),
        (
            "--force over a link",
            lambda w: ["import-wokwi", w.link(w.project() / "rig.toml", w.victim / "keep.txt").parent, "--force"],
            "rig.toml is a link to",
        ),
    ],
    "campaign": [
        ("its runs/ a link", lambda w: _campaign(w.link(w.tmp / "c" / "runs", w.victim).parent), "runs is a link to"),
        (
            "its results.jsonl a link",
            lambda w: _campaign(w.link(w.tmp / "c" / "results.jsonl", w.victim / "keep.txt").parent),
            "results.jsonl is a link to",
        ),
        (
            "--replay into a replay/ that is a link",
            lambda w: ["campaign", "--replay", "none/room/1", "--out", _campaign_folder(w)],
            "replay is a link to",
        ),
    ],
    "scenario": [
        (
            "--out a link",
            lambda w: ["scenario", w.project(SCENARIO) / "press.test.yaml", "--out", w.link(w.tmp / "s", w.victim)],
            "s is a link to",
        ),
        (
            "the default build/ a link",
            lambda w: ["scenario", w.link(w.project(SCENARIO) / "build", w.victim).parent / "press.test.yaml"],
            "build is a link to",
        ),
        (
            "--out the firmware folder",
            lambda w: ["scenario", w.project(SCENARIO) / "press.test.yaml", "--out", w.tmp / "proj"],
            "is the firmware folder",
        ),
    ],
}


def _campaign_folder(w) -> Path:
    """A campaign's folder (its campaign.json, as a campaign writes it) whose replay/ is a link."""
    from host.campaign import load_campaign

    folder = w.tmp / "c"
    folder.mkdir()
    safefs.write_text(folder / "campaign.json", __import__("json").dumps(load_campaign("rover").to_dict(), default=str))
    w.link(folder / "replay", w.victim)
    return folder


TABLE = [pytest.param(command, *case, id=f"{command}: {case[0]}") for command, cases in CASES.items() for case in cases]


@pytest.mark.parametrize("command, case, argv, words", TABLE)
def test_every_command_refuses_to_write_through_a_link_or_over_its_input(
    command, case, argv, words, tmp_path, recorded
):
    w = World(tmp_path, recorded)
    args = argv(w)
    victim, trace = snapshot(w.victim), snapshot(w.trace)
    code, out, err = run_cli(*args)
    assert code == 2, f"mpy-fil {command} ({case}): exit {code}, expected 2\n{out}\n{err}"
    assert words in err and "Traceback" not in err, f"expected {words!r} in:\n{err}"
    assert snapshot(w.victim) == victim, f"{command} ({case}) wrote through the link into {w.victim}"
    assert snapshot(w.trace) == trace, f"{command} ({case}) changed the trace folder it read"


def test_setup_refuses_a_link_in_the_per_user_cache_and_builds_nothing_there(tmp_path, monkeypatch):
    victim = tmp_path / "victim"
    victim.mkdir()
    cache = tmp_path / "cache"
    (cache / "mpy-fil").parent.mkdir()
    (cache / "mpy-fil").symlink_to(victim)
    monkeypatch.setenv("XDG_CACHE_HOME", str(cache))
    monkeypatch.delenv("MICROPYTHON", raising=False)
    monkeypatch.setenv("PATH", str(tmp_path / "no-bin"))
    monkeypatch.setattr(paths, "CHECKOUT", False)  # (as installed: the build goes to the per-user cache)

    def build_started():
        raise AssertionError("setup started a build through the link")

    monkeypatch.setattr(interpreter, "ensure_tools", build_started)
    code, out, err = run_cli("setup")
    assert code == 2 and f"{cache / 'mpy-fil'} is a link to {victim}" in err, f"exit {code}\n{out}\n{err}"
    assert not any(victim.iterdir()), "setup wrote into the link's target"


def test_a_link_left_at_a_files_temporary_name_is_removed_not_written_through(tmp_path):
    """Every file of a trace folder is written under ``<name>.part`` and renamed: a link put
    at that name (a folder handed over, a run killed) is never followed."""
    victim = tmp_path / "victim.txt"
    victim.write_text("the link's target\n")
    folder = tmp_path / "trace"
    folder.mkdir()
    (folder / "header.json.part").symlink_to(victim)
    integrity.write_text(folder / "header.json", "{}\n")
    assert victim.read_text() == "the link's target\n"
    assert (folder / "header.json").read_text() == "{}\n" and not (folder / "header.json").is_symlink()
    assert not (folder / "header.json.part").exists()


def test_a_link_at_a_files_name_is_refused_or_replaced_never_followed(tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("kept\n")
    (tmp_path / "a").symlink_to(victim)
    with pytest.raises(OutputRefused, match="a is a link to"):
        safefs.open_write(tmp_path / "a")
    with pytest.raises(OutputRefused, match="a is a link to"):
        safefs.write_new(tmp_path / "a", "x")
    safefs.write_text(tmp_path / "a", "new\n")  # (replaced: the link itself goes)
    assert victim.read_text() == "kept\n" and (tmp_path / "a").read_text() == "new\n"


@pytest.mark.parametrize("command", ["init", "import-wokwi", "check"])
def test_a_fifo_in_a_folder_a_command_reads_is_named_and_never_opened(tmp_path, command):
    """Opening a FIFO to read waits until something writes to it: for ever."""
    proj = tmp_path / "proj"
    shutil.copytree(PROJECT, proj)
    os.mkfifo(proj / "helper.py")
    target = proj / "rig.toml" if command == "check" else proj
    if command == "check":
        assert run_cli("import-wokwi", proj)[0] == 0
    done = subprocess.run(
        [sys.executable, "-m", "host.cli", command, str(target)],
        cwd=paths.REPO,
        capture_output=True,
        text=True,
        timeout=60,  # (without the fix: killed here)
    )
    assert done.returncode in (0, 1) and "Traceback" not in done.stderr, done.stderr
    if command == "init":
        assert f"skipped {proj / 'helper.py'}: a FIFO" in done.stderr, done.stderr


def test_a_board_folder_of_wokwis_micropython_template_runs_the_main_py_at_its_root(tmp_path):
    """github.com/wokwi/wokwi-vscode-micropython: ``esp32/diagram.json``, ``esp32/wokwi.toml``
    (its firmware image), ..., and one ``main.py`` at the root that mpremote puts on the board."""
    repo = tmp_path / "repo"
    shutil.copytree(PROJECT, repo / "esp32")
    (repo / "esp32" / "main.py").rename(repo / "main.py")
    (repo / "esp32" / "wokwi.toml").write_text(
        '[wokwi]\nversion = 1\nelf = "ESP32_GENERIC.bin"\nfirmware = "ESP32_GENERIC.bin"\nrfc2217ServerPort = 4000\n'
    )
    code, out, err = run_cli("run", repo / "esp32", "--duration", "0.5", "--no-plots", "--out", tmp_path / "out")
    assert code == 0, out + err
    code, out, err = run_cli("import-wokwi", repo / "esp32")
    assert code == 0 and f"wrote {repo / 'rig-esp32.toml'}" in out, out + err
    code, out, err = run_cli("check", repo / "rig-esp32.toml")
    assert code == 0 and f"firmware: {repo} (entry main.py)" in out, out + err


def test_replay_refuses_out_onto_its_own_recording(tmp_path, recorded):
    """The library's replay() as the command line's: its recording is what it compares with."""
    from host.rig.loop.replay import replay

    trace = tmp_path / "trace"
    shutil.copytree(recorded, trace)
    before = snapshot(trace)
    for out in (trace, trace / "signals", tmp_path):
        with pytest.raises(OutputRefused, match="the trace folder replayed"):
            replay(trace, out)
    assert snapshot(trace) == before
    code, out, err = run_cli("replay", trace, "--out", trace)
    assert code == 2 and "writing there would overwrite it" in err and "same outputs" not in out, out + err
    assert snapshot(trace) == before

"""A user's own robot under pytest and `make hil RIG=`: only the tests beside the rig run,
everything is written beside the rig, the firmware's own files are no tests, a rig alone is a
test of its budgets, rerun lines run as printed, FIRMWARE= runs only the flashed app."""

import json
import os
import re
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from host.core.errors import ConfigError
from host.core.paths import REPO
from host.pytest_plugin import userpath

PICO = REPO / "examples" / "pico_bot"
SESSION_TIMEOUT_S = 240
MY_TEST = """\
def test_mybot_says_press_start(make_rig):
    rig = make_rig("rig.toml", seed=1)  # beside this file, whatever the current directory
    rig.run_for(0.5)
    assert "pico_bot: press start" in rig.console
"""
FIRMWARE_TEST = "import machine\n\n\ndef test_pin():\n    machine.Pin(2)\n"  # (the firmware's, for the board)


def mybot(where: Path, tests: dict[str, str] | None = None) -> Path:
    """pico_bot's main.py and rig file in ``where``, with these files beside them."""
    where.mkdir(parents=True)
    for name in ("main.py", "rig.toml"):
        shutil.copy(PICO / name, where / name)
    for name, text in (tests or {}).items():
        (where / name).write_text(textwrap.dedent(text))
    return where


def make_hil(*args: str, cwd: Path = REPO, env: dict | None = None) -> subprocess.CompletedProcess:
    """`make hil` as the Makefile runs it (host/pytest_plugin/hil_run.py), one worker."""
    cmd = [sys.executable, "-m", "host.pytest_plugin.hil_run", "--workers", "1", *args]
    return subprocess.run(
        cmd, cwd=cwd, capture_output=True, text=True, timeout=SESSION_TIMEOUT_S, env={**os.environ, **(env or {})}
    )


def everything_under(folder: Path) -> set[str]:
    return {p.relative_to(folder).as_posix() for p in folder.rglob("*")}


def test_the_makefile_hands_rig_firmware_and_long_to_the_checked_runner():
    done = subprocess.run(
        ["make", "-n", "--no-print-directory", "hil", "RIG=a b/rig.toml", "FIRMWARE=x", "LONG=0", "WORKERS=3"],
        cwd=REPO,
        capture_output=True,
        text=True,
        env={**os.environ, "MICROPYTHON": os.environ.get("MICROPYTHON", "/bin/true")},
    )
    line = next((x for x in done.stdout.splitlines() if "hil_run" in x), done.stdout)
    assert '-m host.pytest_plugin.hil_run --workers 3 --long 0 --rig "a b/rig.toml" --firmware "x"' in line, line


def test_make_test_prints_the_reasons_of_skipped_tests_and_leaves_no_temp_folder():
    done = subprocess.run(
        ["make", "-n", "--no-print-directory", "test"],
        cwd=REPO,
        capture_output=True,
        text=True,
        env={**os.environ, "MICROPYTHON": os.environ.get("MICROPYTHON", "/bin/true")},
    )
    assert re.search(r"-m pytest .*-rs\b", done.stdout), done.stdout
    assert "tmp_path_retention_policy=failed" in done.stdout, "a passed test's temp folder is left in $TMPDIR"


@pytest.mark.parametrize("given", ["RIG=/nowhere/mybot", "RIG=folder-without-a-rig", "FIRMWARE=build/vboard/typo/fs"])
def test_a_rig_or_firmware_that_does_not_exist_is_one_line_and_exit_2_before_pytest(tmp_path, given):
    (tmp_path / "folder-without-a-rig").mkdir()
    key, value = given.split("=", 1)
    done = make_hil(f"--{key.lower()}", value, cwd=tmp_path)
    assert done.returncode == 2, done.stdout + done.stderr
    assert done.stderr.count("\n") == 1 and done.stderr.startswith(f"make hil: {given}"), done.stderr
    assert "test session starts" not in done.stdout and not done.stdout.strip(), done.stdout


@pytest.mark.hil
def test_make_hil_rig_runs_only_the_tests_beside_the_rig_and_writes_only_beside_it(tmp_path):
    """Before: pytest on the rig folder's parent, the whole parent collected; build/hil and
    .pytest_cache in the parent; make_rig("rig.toml") looked in the current directory. (RIG=
    the rig file itself starts this same session: the next test.)"""
    parent = tmp_path / "robots"
    (parent / "other").mkdir(parents=True)
    (parent / "test_not_mine.py").write_text("def test_not_mine():\n    assert False, 'the parent ran'\n")
    bot = mybot(parent / "mybot", {"test_mybot.py": MY_TEST, "pin_test.py": FIRMWARE_TEST})
    (bot / "sub").mkdir()
    (bot / "sub" / "test_below.py").write_text("def test_below():\n    assert False, 'a folder below ran'\n")
    before = everything_under(parent)
    done = make_hil("--rig", str(bot))
    out = done.stdout + done.stderr
    assert done.returncode == 0 and "1 passed" in done.stdout, out[-3000:]
    assert "not_mine" not in out and "below" not in out and "pin_test" not in out, out[-3000:]
    assert (bot / "build" / "hil" / "report.html").is_file()
    assert (bot / "build" / "hil" / "test_mybot" / "test_mybot_says_press_start" / "rig0").is_dir()
    new = everything_under(parent) - before
    # (and Python's own __pycache__ beside the test, unless PYTHONPYCACHEPREFIX puts it elsewhere, as make does)
    mine = [p for p in new if not p.startswith("mybot/__pycache__")]
    assert all(p.startswith("mybot/build/") or p == "mybot/build" for p in mine), sorted(mine)[:10]
    assert not [p for p in new if "__pycache__" in p and not p.startswith("mybot/")], new


def test_make_hil_rig_given_the_rig_file_starts_the_session_its_folder_starts(tmp_path, monkeypatch):
    """RIG=<folder>/rig.toml and RIG=<folder>, absolute or relative: the same pytest arguments in
    the same folder (hil_run's main execs pytest with nothing else of the argument), so the
    session the test above runs on the folder is the rig file's too."""
    from argparse import Namespace

    from host.pytest_plugin.hil_run import pytest_args

    bot = mybot(tmp_path / "robots" / "mybot", {"test_mybot.py": MY_TEST, "pin_test.py": FIRMWARE_TEST})
    monkeypatch.chdir(tmp_path)
    sessions = {
        rig: pytest_args(Namespace(rig=rig, long="1", workers="1"))
        for rig in (str(bot), str(bot / "rig.toml"), "robots/mybot", "robots/mybot/rig.toml")
    }
    assert len({repr(session) for session in sessions.values()}) == 1, sessions
    args, folder = sessions[str(bot / "rig.toml")]
    assert folder == bot and args[-1] == "test_mybot.py", sessions


@pytest.mark.hil
def test_a_rig_with_no_test_beside_it_runs_its_budgets_as_a_test_and_says_how_to_write_one(tmp_path):
    """Before: "no tests ran", Error 5, no hint."""
    bot = mybot(tmp_path / "mybot", {"pin_test.py": FIRMWARE_TEST})
    done = make_hil("--rig", str(bot))
    assert done.returncode == 0, (done.stdout + done.stderr)[-3000:]
    assert f"no test beside {bot / 'rig.toml'}: running the rig's own budgets as a test" in done.stdout
    assert 'def test_mybot_keeps_its_budgets(make_rig):\n        rig = make_rig("rig.toml", seed=1)' in done.stdout
    assert "1 passed" in done.stdout and "pin_test" not in done.stdout, done.stdout[-2000:]
    assert "test_rig_budgets" in done.stdout  # (the budget table names the generated test)
    # the test it shows, written beside the rig file as printed, passes
    shown = done.stdout.split("A test of your own", 1)[1].split("\n", 1)[1].split("\n\n", 1)[0]
    (bot / "test_mybot.py").write_text("\n".join(line.removeprefix("    ") for line in shown.splitlines()) + "\n")
    again = subprocess.run(  # (pytest on it, as its author runs it: make hil's report adds nothing to check here)
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "test_mybot.py"],
        cwd=bot,
        capture_output=True,
        text=True,
        timeout=SESSION_TIMEOUT_S,
    )
    assert again.returncode == 0 and "1 passed" in again.stdout, (again.stdout + again.stderr)[-3000:]


def test_pytest_on_a_firmware_folder_leaves_out_the_firmwares_own_files(tmp_path):
    """Before: `ModuleNotFoundError: No module named 'machine'` collecting the firmware's
    own tests, and no rig setting to leave more out."""
    bot = mybot(
        tmp_path / "mybot",
        {
            "test_mybot.py": MY_TEST,
            "pin_test.py": FIRMWARE_TEST,
            "test_timing.py": "import utime\n\n\ndef test_ms():\n    utime.ticks_ms()\n",
            "test_viper.py": "@micropython.viper\ndef f(x: int) -> int:\n    return x\n\n\ndef test_f():\n    pass\n",
            "test_bench_only.py": "def test_on_the_bench():\n    pass\n",
        },
    )
    (bot / "lib").mkdir()
    (bot / "lib" / "test_driver.py").write_text("from machine import I2C\n\n\ndef test_i2c():\n    I2C(0)\n")
    (bot / "rig.toml").write_text((bot / "rig.toml").read_text() + '\n[tests]\nexclude = ["test_bench_*.py"]\n')
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--collect-only", str(bot)],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 0, done.stdout[-3000:]
    collected = [line for line in done.stdout.splitlines() if "::" in line]
    assert collected == ["mybot/test_mybot.py::test_mybot_says_press_start"], done.stdout[-3000:]


def test_a_firmware_files_reason_names_its_rig_file_and_what_it_imports(tmp_path):
    bot = mybot(tmp_path / "mybot", {"pin_test.py": FIRMWARE_TEST, "test_mine.py": MY_TEST})
    reason = userpath.firmware_file(bot / "pin_test.py", tmp_path)
    assert reason == f"in the firmware folder of {bot / 'rig.toml'}, imports machine"
    assert userpath.firmware_file(bot / "test_mine.py", tmp_path) is None
    (bot / "rig.toml").write_text((bot / "rig.toml").read_text() + '\n[tests]\nexclude = [""]\n')
    from host.rig.config.rigfile import load_rig

    with pytest.raises(ConfigError, match=r"\[tests\] exclude: expected file name patterns"):
        load_rig(bot / "rig.toml")


def test_make_rig_resolves_a_rig_path_against_the_test_file_then_the_current_directory(tmp_path, monkeypatch):
    bot = mybot(tmp_path / "mybot")
    monkeypatch.chdir(tmp_path)
    assert userpath.resolve_rig("rig.toml", bot / "test_mybot.py") == str(bot / "rig.toml")
    elsewhere = tmp_path / "elsewhere" / "test_x.py"
    assert userpath.resolve_rig("mybot/rig.toml", elsewhere) == str(tmp_path / "mybot/rig.toml")
    assert userpath.resolve_rig("rover", bot / "test_mybot.py") == "rover"
    with pytest.raises(ConfigError) as caught:
        userpath.resolve_rig("rigg.toml", bot / "test_mybot.py")
    assert str(caught.value) == (
        f"make_rig: no rig file 'rigg.toml': tried it relative to {bot} (the test file's folder) "
        f"and {tmp_path} (the current directory)"
    )


@pytest.mark.hil
def test_a_failed_tests_rerun_line_runs_as_printed_from_anywhere(tmp_path):
    """Before: `python -m pytest 'test_mybot.py::…' (from <the parent folder>)`: not the
    interpreter with the plugin, and a node id the folder named does not hold."""
    failing = MY_TEST.replace('assert "pico_bot: press start"', 'assert "never printed"')
    bot = mybot(tmp_path / "mybot", {"test_mybot.py": failing})
    done = make_hil("--rig", str(bot))
    assert done.returncode == 1, (done.stdout + done.stderr)[-3000:]
    rerun = re.search(r"^rerun: (.*)$", done.stdout, re.M)
    assert rerun, done.stdout[-3000:]
    again = subprocess.run(
        rerun.group(1),
        shell=True,
        cwd="/",
        capture_output=True,
        text=True,
        timeout=SESSION_TIMEOUT_S,
        env={k: v for k, v in os.environ.items() if k not in ("VIRTUAL_ENV", "PYTHONPATH")} | {"PATH": "/usr/bin:/bin"},
    )
    assert "1 failed" in again.stdout and "test_mybot_says_press_start" in again.stdout, again.stdout[-3000:]
    assert "never printed" in again.stdout
    assert not (tmp_path / ".pytest_cache").exists() and not (tmp_path / "build").exists()
    kept = bot / "build" / "hil" / "test_mybot" / "test_mybot_says_press_start" / "rig0"
    assert (kept / "header.json").is_file(), "the rerun records the whole trace"


@pytest.mark.hil
def test_firmware_runs_only_the_flashed_apps_scenarios_from_flash_and_says_which(tmp_path):
    """Before: every scenario ran, nothing said which used the flashed files."""
    bot = mybot(tmp_path / "mybot")
    fs = tmp_path / "vboard" / "fs"
    fs.mkdir(parents=True)
    shutil.copy(bot / "main.py", fs / "main.py")
    flashed = {"app": str(bot / "rig.toml"), "board": "pins", "files": ["main.py"]}
    (fs.parent / "flashed.json").write_text(json.dumps(flashed))
    (bot / "test_both.py").write_text(
        textwrap.dedent(
            """\
            import os

            def test_mine(make_rig):
                rig = make_rig("rig.toml", seed=1)
                rig.run_for(0.5)
                assert str(rig.firmware_folders[0]) == os.environ["HIL_FIRMWARE"]

            def test_the_rover(make_rig):
                make_rig("rover", seed=1).run_for(0.5)
            """
        )
    )
    done = make_hil("--rig", str(bot), "--firmware", str(fs))
    out = done.stdout
    assert done.returncode == 0 and "1 passed, 1 skipped" in out, out[-3000:]
    assert f"ran from flash: 1 tests ({flashed['app']} flashed in {fs})" in out, out[-3000:]
    assert re.search(r"PASSED +test_both.py::test_mine", out), out[-3000:]
    assert f"FIRMWARE={fs} holds {flashed['app']}; this test runs app rover, not the flashed files" in out


def test_make_hil_rig_of_ours_writes_under_the_projects_build_and_does_not_overwrite_its_report():
    from argparse import Namespace

    from host.pytest_plugin.hil_run import pytest_args

    args, folder = pytest_args(Namespace(rig="examples/pico_bot", long="1", workers="2"))
    assert folder == PICO and args[-1] == "test_pico_bot.py", args
    assert args[args.index("--hil-report") + 1] == str(REPO / "build" / "hil" / "pico_bot" / "report.html")
    assert f"cache_dir={REPO / 'build' / '.pytest_cache'}" in args

"""mpy-fil's command line: --help for every command; a bad argument is reported by name
with exit code 2 and no traceback."""

import contextlib
import io
import json
import subprocess
import sys
from pathlib import Path

import pytest

from host.artefacts.folder import reseal
from host.core.paths import REPO


def cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "host.cli", *args], cwd=REPO, capture_output=True, text=True, timeout=60
    )


def cli_here(*args: str) -> tuple[int, str]:
    """mpy-fil's main() in this process: (exit code, what it wrote to stderr)."""
    from host.cli import main

    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            code = main(list(args))
        except SystemExit as e:  # argparse's error(): exit 2 after its message
            code = e.code
    return code, err.getvalue()


@pytest.mark.parametrize("command", [(), ("run",), ("replay",), ("plot",)])
def test_every_command_has_help(command):
    done = cli(*command, "--help")
    assert done.returncode == 0, done.stderr
    assert done.stdout.startswith(f"usage: mpy-fil {' '.join(command)}".rstrip()), done.stdout


@pytest.mark.parametrize(
    "args, named",
    [
        (("run", "--app", "lawnmower"), "argument --app: invalid choice: 'lawnmower'"),
        (("run", "--board", "arduino_uno"), "argument --board: unknown board 'arduino_uno' for app rover"),
        (("run", "--world", "moon"), "argument --world: unknown world 'moon' for app rover"),
        (("run", "--param", "room_w"), "argument --param: expected NAME=VALUE"),
        (("run", "--param", "wheels=3"), "[plant] wheels: the differential has no such option"),
        (("run", "--param", "room_w_m=wide"), "rejects it: [plant] room_w_m: expected a number of metres"),
        (("run", "--param", "room_w_m=0.2"), "argument --param: rover's plant rejects"),
        (("run", "--duration", "0"), "argument --duration: expected a positive number of seconds"),
        (("run", "--duration", "-1"), "argument --duration: expected a positive number of seconds, got '-1'"),
        (("run", "--duration", "inf"), "argument --duration: expected a positive number of seconds, got 'inf'"),
        (("run", "--duration", "nan"), "argument --duration: expected a positive number of seconds, got 'nan'"),
        (("run", "--duration", "1e300"), "argument --duration: expected at most 864000 seconds (10 simulated days)"),
        (("run", "--duration", "864000.5"), "argument --duration: expected at most 864000 seconds"),
        (("run", "--duration", "1e-9"), "argument --duration: expected at least 0.000001 seconds (the clock's 1 us)"),
        (("run", "--duration", "ten"), "argument --duration: expected a number of seconds, got 'ten'"),
        (("run", "--seed", "one"), "argument --seed: expected a whole number from 0 to 4294967295, got 'one'"),
        (("run", "--seed", "-1"), "argument --seed: expected a whole number from 0 to 4294967295, got '-1'"),
        (("run", "--seed", "abc"), "argument --seed: expected a whole number from 0 to 4294967295, got 'abc'"),
        (("run", "--seed", "4294967296"), "argument --seed: expected a whole number from 0 to 4294967295"),
        (("run", "--seed", "2.5"), "argument --seed: expected a whole number from 0 to 4294967295, got '2.5'"),
        (("run", "--out", ""), "argument --out: expected a folder, got an empty name"),
        (("run", "--duration", "1", "--out", "/proc/x"), "argument --out: cannot write to the folder /proc/x"),
        (("run", "--param", "room_w_m=nan"), "argument --param: room_w_m: expected finite numbers, got 'nan'"),
        (("run", "--param", "v_max_m_s=-inf"), "argument --param: v_max_m_s: expected finite numbers, got '-inf'"),
        (("run", "--param", "start_pose=(1e999, 0, 0)"), "argument --param: start_pose: expected finite numbers"),
        (("run", "--param", "wheel_radius_m=0"), "rejects it: [plant] wheel_radius_m: expected a number of metres"),
        (("init", "/proc"), "argument DIR: cannot write to the folder /proc"),
        (("replay", "build/no-such-trace"), "argument TRACE: no trace folder at build/no-such-trace"),
        (("plot", "host"), "argument TRACE: host is not a trace folder (no header.json)"),
        (("fly",), "argument COMMAND: invalid choice: 'fly'"),
    ],
)
def test_a_bad_argument_is_named_with_exit_code_2_and_no_traceback(args, named):
    """In this process (any exception that escapes main() fails the test with its traceback);
    the next test holds a real process to the same."""
    code, stderr = cli_here(*args)
    assert code == 2, f"mpy-fil {' '.join(args)}: exit {code}, expected 2\n{stderr}"
    assert named in stderr, f"expected {named!r} in:\n{stderr}"
    assert stderr.count("error:") == 1, f"expected one message, got:\n{stderr}"


@pytest.mark.parametrize(
    "args, named",
    [
        (("run", "--duration", "inf"), "argument --duration: expected a positive number of seconds, got 'inf'"),
        (("run", "--seed", "-1"), "argument --seed: expected a whole number from 0 to 4294967295, got '-1'"),
        (("run", "--duration", "1", "--out", "/proc/x"), "argument --out: cannot write to the folder /proc/x"),
    ],
)
def test_the_process_exits_2_with_one_message_and_no_traceback(args, named):
    done = cli(*args)
    assert done.returncode == 2, f"mpy-fil {' '.join(args)}: exit {done.returncode}, expected 2\n{done.stderr}"
    assert named in done.stderr, f"expected {named!r} in:\n{done.stderr}"
    assert "Traceback" not in done.stderr and done.stderr.count("error:") == 1, done.stderr


def test_the_seed_and_duration_bounds_themselves_are_accepted():
    """0 and 2**32 - 1 are seeds; 10 simulated days is a duration: the parser takes them
    (the run itself is not started here)."""
    from host.cli import build_parser

    parser = build_parser()
    for seed in ("0", "4294967295"):
        assert parser.parse_args(["run", "--seed", seed]).seed == int(seed)
    assert parser.parse_args(["run", "--duration", "864000"]).duration == 864000.0
    assert parser.parse_args(["run", "--duration", "0.000001"]).duration == 1e-6


def fake_trace_folder(folder: Path, budgets: str | None = None) -> Path:
    folder.mkdir()
    header = {"format": "mpy-fil-trace/1", "app": "rover", "board": "rpi_pico", "mode": "lockstep", "seed": 0}
    (folder / "header.json").write_text(json.dumps({**header, "t_end_us": 0, "signals": {}}))
    (folder / "signals.csv").write_text("t_us,signal,value\n")
    (folder / "truth.csv").write_text("t_us\n0\n")
    if budgets is not None:
        (folder / "budgets.json").write_text(budgets)
    reseal(folder)  # (sealed as a run seals its folder: a damaged file is found by its form)
    return folder


@pytest.mark.parametrize("command", ["replay", "plot"])
def test_an_unwritable_out_folder_of_replay_and_plot_is_named_with_exit_code_2(tmp_path, command):
    trace = fake_trace_folder(tmp_path / "trace")
    code, stderr = cli_here(command, str(trace), "--out", "/proc/x")
    expected = "argument --out: cannot write to the folder /proc/x"
    assert code == 2 and expected in stderr, f"exit {code}, expected 2 and {expected!r}:\n{stderr}"


def test_a_damaged_file_of_a_trace_folder_is_named_with_exit_code_2(tmp_path):
    trace = fake_trace_folder(tmp_path / "trace", budgets="{not json")
    code, stderr = cli_here("plot", str(trace), "--out", str(tmp_path / "plots"))
    expected = f"trace folder {trace}: budgets.json is malformed"
    assert code == 2 and expected in stderr, f"exit {code}, expected 2 and {expected!r}:\n{stderr}"


def test_every_argument_error_of_every_command_is_one_line_with_exit_2():
    from hypothesis import HealthCheck, given, settings
    from hypothesis import strategies as st

    commands = st.sampled_from([[], ["run"], ["check"], ["init"], ["list"], ["replay"], ["plot"], ["campaign"]])
    junk = st.lists(
        st.sampled_from(["--seconds", "--seed", "--param", "--world", "--board", "--out", "--workers", "-x", "=", "x"])
        | st.text(min_size=1, max_size=12),
        max_size=4,
    )

    @settings(max_examples=120, derandomize=True, deadline=None, suppress_health_check=list(HealthCheck))
    @given(commands, junk)
    def check(command, extra):
        code, err = cli_here(*command, "--no-such-flag", *extra)
        lines = err.strip().splitlines()
        assert code == 2, (command, extra, code, err)
        assert len(lines) == 1 and "Traceback" not in err, (command, extra, err)
        assert lines[0].startswith("mpy-fil") and ": error: " in lines[0], lines

    check()

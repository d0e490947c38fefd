"""mpy-fil's command line: --help for every command; a bad argument is reported by name
with exit code 2 and no traceback."""

import subprocess
import sys

import pytest

from host.core.paths import REPO


def cli(*args: str) -> subprocess.CompletedProcess:
    return subprocess.run(
        [sys.executable, "-m", "host.cli", *args], cwd=REPO, capture_output=True, text=True, timeout=60
    )


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
        (("run", "--param", "wheels=3"), "argument --param: rover's plant has no option wheels"),
        (("run", "--param", "room_w_m=wide"), "argument --param: rover's plant rejects"),
        (("run", "--duration", "0"), "argument --duration: expected a positive number of seconds"),
        (("run", "--seed", "one"), "argument --seed: invalid int value: 'one'"),
        (("replay", "build/no-such-trace"), "argument TRACE: no trace folder at build/no-such-trace"),
        (("plot", "host"), "argument TRACE: host is not a trace folder (no header.json)"),
        (("fly",), "argument COMMAND: invalid choice: 'fly'"),
    ],
)
def test_a_bad_argument_is_named_with_exit_code_2_and_no_traceback(args, named):
    done = cli(*args)
    assert done.returncode == 2, f"mpy-fil {' '.join(args)}: exit {done.returncode}, expected 2\n{done.stderr}"
    assert named in done.stderr, f"expected {named!r} in:\n{done.stderr}"
    assert "Traceback" not in done.stderr, done.stderr

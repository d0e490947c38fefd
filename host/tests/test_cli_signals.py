"""Every stop signal is reported as itself, whenever it comes: ``mpy-fil``'s commands get
SIGINT (Ctrl-C), SIGTERM or SIGHUP while they start (the imports), while their firmware
runs and while ``run`` draws its plots; each says ``<command>: stopped by <SIGNAL>`` in one
line, no traceback, exits with 128 + the signal's number, and leaves nothing running."""

import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from host.tests.test_no_orphans import MPY_FIL, _kill, _micropythons, alive, descendants, program

pytestmark = pytest.mark.hil
SCENARIOS = Path(__file__).parent / "wokwi_scenarios"
CAMPAIGN = Path(__file__).parents[2] / "hil_tests" / "campaigns" / "duct_snag.toml"
STARTING_S = 0.4  # (at most: the handlers are in place sooner; the imports take over a second here)
ENDED_S = 60.0


def _terminal_signals() -> None:
    """(A session started in the background ignores SIGINT, and so would its children:
    mpy-fil keeps a signal ignored that it was started ignoring, as nohup asks.)"""
    for sig in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(sig, signal.SIG_DFL)


@pytest.fixture
def start():
    """Starts ``mpy-fil`` with its output (stdout and stderr) in one unbuffered pipe; at the
    end, whatever a failed test left of it is killed."""
    started = []

    def start(cmd) -> subprocess.Popen:
        env = {**os.environ, "PYTHONUNBUFFERED": "1"}
        proc = subprocess.Popen(
            cmd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, preexec_fn=_terminal_signals
        )
        started.append(proc)
        return proc

    yield start
    for proc in started:
        for pid in descendants(proc.pid) if proc.poll() is None else ():
            _kill(pid)
        proc.kill()
        proc.wait()
        proc.stdout.close()


def _catches(pid: int, sig: int) -> bool:
    """The process has a handler of its own for ``sig`` (/proc's SigCgt)."""
    try:
        status = Path(f"/proc/{pid}/status").read_text()
    except OSError:
        return False
    caught = int(next(line.split()[1] for line in status.splitlines() if line.startswith("SigCgt:")), 16)
    return bool(caught >> (sig - 1) & 1)


def stop_and_check(front: subprocess.Popen, sig: int, prog: str, family: set[int] = frozenset()) -> str:
    """Send ``sig``; the front end says ``<prog>: stopped by <SIGNAL>`` as its last line, no
    traceback, exits 128 + sig, and neither it nor anything it started runs any more."""
    family = set(family) | descendants(front.pid)
    front.send_signal(sig)
    out, _ = front.communicate(timeout=ENDED_S)
    name = signal.Signals(sig).name
    got = front.returncode
    assert got == 128 + sig, f"expected exit {128 + sig} for {name}, got {got}:\n{out[-3000:]}"
    assert "Traceback" not in out, out[-3000:]
    assert out.rstrip().splitlines()[-1] == f"{prog}: stopped by {name}", out[-3000:]
    deadline = time.monotonic() + 5
    while (left := {p: program(p) for p in family if alive(p)}) and time.monotonic() < deadline:
        time.sleep(0.05)
    assert not left, f"still running after {name}: {left}"
    return out


def _record(tmp_path: Path, seconds: float) -> Path:
    out = tmp_path / "recorded"
    cmd = [str(MPY_FIL), "run", "--duration", str(seconds), "--out", str(out), "--no-plots"]
    subprocess.run(cmd, check=True, capture_output=True, timeout=300)
    return out


def _long_scenario(tmp_path: Path) -> Path:
    """The button firmware, waiting for a line it never prints (a day, in simulated time)."""
    folder = tmp_path / "button"
    shutil.copytree(SCENARIOS / "button_irq", folder)
    scenario = folder / "never.test.yaml"
    steps = "  - wait-serial: 'ready'\n  - wait-serial: 'never printed'\n"
    scenario.write_text(f"name: 'never'\nversion: 1\nsteps:\n{steps}")
    return scenario


def _failed_run(tmp_path: Path) -> Path:
    """A campaign run that failed, for shrink: the bench with a stuck battery among
    harmless faults (host/tests/test_shrink.py's), one seed, 4 s."""
    from host.campaign import load_campaign
    from host.campaign.runner import run_campaign
    from host.tests.test_shrink import BENCH, HARMLESS, STUCK_BATT, toml_faults

    faults = tmp_path / "faults.toml"
    faults.write_text(f'[[faultsets]]\nname = "one-matters"\n{toml_faults([*HARMLESS, STUCK_BATT])}\n')
    campaign = load_campaign(str(BENCH), faults_file=str(faults), seeds=1, seconds=4.0)
    (result,) = run_campaign(campaign, tmp_path / "campaign", workers=1)
    assert not result["passed"], result
    return tmp_path / "campaign" / "runs" / "one-matters" / "default" / "1"


def commands(tmp_path: Path) -> dict[str, list[str]]:
    """Each command a user runs for long, with arguments that run it."""
    return {
        "run": ["run", "--duration", "86400", "--out", str(tmp_path / "run"), "--no-plots"],
        "campaign": ["campaign", str(CAMPAIGN), "--workers", "2", "--seeds", "20", "--out", str(tmp_path / "camp")],
        "scenario": ["scenario", str(_long_scenario(tmp_path)), "--timeout", "86400s", "--out", str(tmp_path / "sc")],
        "shrink": ["shrink", str(tmp_path / "campaign/runs/one-matters/default/1"), "--out", str(tmp_path / "shrunk")],
        "replay": ["replay", str(tmp_path / "recorded"), "--out", str(tmp_path / "replayed")],
    }


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
@pytest.mark.parametrize("command", ["run", "campaign", "scenario", "shrink", "replay"])
def test_a_signal_while_a_command_starts_is_one_line_naming_it_and_its_exit_code(start, tmp_path, command, sig):
    """Before: Ctrl-C in the first second printed a KeyboardInterrupt traceback, SIGTERM
    ended it with no word. The signal comes as soon as the command's handlers are in place
    (or STARTING_S), well inside its imports: main has not read its arguments yet."""
    front = start([str(MPY_FIL), *commands(tmp_path)[command]])
    deadline = time.monotonic() + STARTING_S
    while not _catches(front.pid, signal.SIGTERM) and time.monotonic() < deadline:
        time.sleep(0.002)
    stop_and_check(front, sig, "mpy-fil")


MID_RUN = [
    ("run", signal.SIGINT, 1),
    ("run", signal.SIGTERM, 1),
    ("run", signal.SIGHUP, 1),
    ("campaign", signal.SIGTERM, 2),
    ("campaign", signal.SIGINT, 2),
    ("scenario", signal.SIGTERM, 1),
    ("replay", signal.SIGTERM, 1),
    ("shrink", signal.SIGTERM, 1),
]


@pytest.mark.parametrize(("command", "sig", "firmwares"), MID_RUN, ids=[f"{c}-{s.name}" for c, s, _ in MID_RUN])
def test_a_signal_while_the_firmware_runs_stops_the_command_naming_it(start, tmp_path, command, sig, firmwares):
    """Before: SIGTERM to a campaign said "stopped by SIGINT" and exited 130."""
    if command == "replay":
        _record(tmp_path, 300.0)  # (its replay still runs 0.3 s after it starts: about 2 s here)
    if command == "shrink":
        _failed_run(tmp_path)
    front = start([str(MPY_FIL), *commands(tmp_path)[command]])
    deadline = time.monotonic() + 60
    while not _micropythons(firmwares)([program(p) for p in descendants(front.pid)]):
        assert front.poll() is None and time.monotonic() < deadline, front.stdout.read()
        time.sleep(0.05)
    time.sleep(0.3)  # (well inside the run)
    out = stop_and_check(front, sig, f"mpy-fil {command}", descendants(front.pid))
    if command == "run":
        assert "(partial: stopped at t=" in out, out[-2000:]


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
def test_a_signal_while_run_draws_its_plots_says_so_and_keeps_the_whole_trace_folder(start, tmp_path, sig):
    """Before: SIGTERM while the plots were drawn ended mpy-fil run with no word."""
    out = tmp_path / "run"
    front = start([str(MPY_FIL), "run", "--duration", "2", "--out", str(out)])
    seen = ""
    while "plots: drawing them" not in seen:
        line = front.stdout.readline()
        assert line, seen
        seen += line
    text = stop_and_check(front, sig, "mpy-fil run")
    assert f"plots: stopped; the trace folder {out} is whole" in text, text[-2000:]
    assert (out / "trace.jsonl").is_file() and (out / "header.json").is_file()


SWALLOWED = """
import gc, signal, sys, weakref
from host.core import stop_signals

sys.unraisablehook = stop_signals._stopped_unraisable
stop_signals.install()


class Thing:
    pass


def callback(_ref):  # (as importlib's module-lock callback: an exception here is ignored)
    stop_signals.stop(signal.SIGINT, None)


try:
    thing = Thing()
    ref = weakref.ref(thing, callback)
    del thing
    gc.collect()
    for _ in range(100_000):
        pass
    print("went on")
except stop_signals.Stopped as e:
    print("stopped by", e.signal_name)
"""


def test_a_stop_raised_where_python_ignores_exceptions_is_delivered_again():
    """Found by the start-up test above under load: SIGINT came while importlib's module-lock
    callback ran, Python printed "Exception ignored" and the command went on (argparse's exit
    2). The program's unraisable hook delivers the signal again at the next line."""
    done = subprocess.run([sys.executable, "-c", SWALLOWED], capture_output=True, text=True, timeout=60)
    assert done.stdout.strip() == "stopped by SIGINT", (
        f"expected the swallowed SIGINT delivered again, got stdout {done.stdout!r}, stderr {done.stderr[-2000:]!r}"
    )

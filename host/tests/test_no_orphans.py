"""No process outlives the command that started it (docs/reliability.md, docs/flash.md).

Each front end is started, its descendants and the ptys they hold are read from /proc once
the firmware runs, the front end gets SIGKILL or SIGTERM, and every descendant must be gone
within seconds, and no process that held one of their ptys still holds it."""

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

from host.core.paths import REPO
from host.device import vboard

pytestmark = pytest.mark.hil
MPY_FIL = Path(sys.executable).parent / "mpy-fil"
APPEAR_S = 30.0  # (a loaded machine: an xdist session starts two workers, each a rig and a board)
GONE_S = 5.0
FRONT_S = 30.0


def _stat(pid: int) -> list[str] | None:
    """/proc/<pid>/stat after the command name: state, ppid, ..., or None once gone."""
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except (OSError, IndexError):
        return None


def _parents() -> dict[int, int]:
    found = {}
    for entry in Path("/proc").glob("[0-9]*"):
        fields = _stat(int(entry.name))
        if fields is not None:
            found[int(entry.name)] = int(fields[1])
    return found


def descendants(pid: int) -> set[int]:
    parents = _parents()
    found, todo = set(), [pid]
    while todo:
        parent = todo.pop()
        for child, ppid in parents.items():
            if ppid == parent and child not in found:
                found.add(child)
                todo.append(child)
    return found


def alive(pid: int) -> bool:
    fields = _stat(pid)
    return fields is not None and fields[0] != "Z"  # (a zombie holds nothing; init reaps it)


def program(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
    except OSError:
        return ""


def ptys(pids) -> set[str]:
    held = set()
    for pid in pids:
        for fd in Path(f"/proc/{pid}/fd").glob("*"):
            try:
                target = os.readlink(fd)
            except OSError:
                continue
            if target.startswith("/dev/pts/"):
                held.add(target)
    return held


def _kill(pid: int) -> None:
    try:
        os.kill(pid, signal.SIGKILL)
    except ProcessLookupError:
        pass


def holders(paths: set[str]) -> dict[int, set[str]]:
    """Every live process that has one of these ptys open (a pty's number is reused once
    closed: compare holders from before and after)."""
    found = {}
    for pid in _parents():
        mine = ptys([pid]) & paths if alive(pid) else set()
        if mine:
            found[pid] = mine
    return found


def wait_for(front: subprocess.Popen, ready) -> set[int]:
    """The front end's descendants once ``ready(their command lines)`` says the firmware runs."""
    deadline = time.monotonic() + APPEAR_S
    while time.monotonic() < deadline:
        assert front.poll() is None, f"the front end ended early:\n{front.stdout.read()}"
        family = descendants(front.pid)
        if ready([program(p) for p in family]):
            return family
        time.sleep(0.05)
    raise AssertionError(f"not ready within {APPEAR_S} s: {[program(p) for p in descendants(front.pid)]}")


def kill_and_check(front: subprocess.Popen, sig: int, family: set[int]) -> str:
    """Send ``sig`` to the front end: within ``GONE_S`` no process holds the firmware's ptys
    any more; the front end ends (within ``FRONT_S``: an interrupted pytest session reports
    first), and by then, give or take ``GONE_S``, so has every process it started (pytest-xdist
    workers included). Says how long each took."""
    held = ptys(family | {front.pid})
    assert held, "expected the firmware's ptys among the descendants' open files"
    sharers = holders(held)  # (a process of theirs the walk missed would be among them)
    t0 = time.monotonic()
    front.send_signal(sig)
    try:
        still = _wait_gone(lambda: {p: paths for p, paths in holders(held).items() if p in sharers})
        assert not still, f"their ptys still held {GONE_S} s after {signal.Signals(sig).name}: {still}"
        released = time.monotonic() - t0
        front.wait(timeout=FRONT_S)
        ended = time.monotonic() - t0
        left = _wait_gone(lambda: {p: program(p) for p in family if alive(p)})
        assert not left, f"still running {GONE_S} s after the front end ended ({signal.Signals(sig).name}): {left}"
    finally:
        for pid in family:  # (a failing test leaves nothing either)
            if alive(pid):
                _kill(pid)
    last = time.monotonic() - t0
    name = signal.Signals(sig).name
    return f"{name}: ptys released in {released:.2f} s, it ended in {ended:.2f} s, all {len(family)} in {last:.2f} s"


def _wait_gone(what) -> dict:
    """Poll ``what()`` until it is empty or ``GONE_S`` passed; its last value."""
    deadline = time.monotonic() + GONE_S
    while (found := what()) and time.monotonic() < deadline:
        time.sleep(0.02)
    return found


@pytest.fixture
def start():
    """Starts a front end; at the end, whatever a failed test left of it is killed."""
    started = []

    def start(cmd, cwd=REPO) -> subprocess.Popen:
        env = {**os.environ, "PYTHONUNBUFFERED": "1"}
        proc = subprocess.Popen(
            cmd, cwd=cwd, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True
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


def _micropythons(n: int):
    return lambda cmds: sum("micropython" in c.split(" ", 1)[0] for c in cmds) >= n


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM])
def test_a_stopped_mpy_fil_run_leaves_nothing_running(start, tmp_path, sig):
    cmd = [str(MPY_FIL), "run", "--app", "rover", "--duration", "86400", "--out", str(tmp_path / "run"), "--no-plots"]
    front = start(cmd)
    family = wait_for(front, _micropythons(1))
    print("mpy-fil run,", kill_and_check(front, sig, family))


HIL_TEST = """
    import pytest
    from host.device import vboard

    @pytest.mark.parametrize("n", [0, 1])
    def test_a_long_run_beside_a_virtual_board(rig, tmp_path, n):
        home = tmp_path / "board"
        vboard.start_background("esp32_devkitc", home=home, wired=False)
        try:
            rig.run_for(86400)
        finally:
            vboard.stop_background("esp32_devkitc", home)
"""


@pytest.mark.parametrize("workers", [0, 2])
@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM])
def test_a_stopped_hil_session_leaves_nothing_running(start, tmp_path, sig, workers):
    (tmp_path / "test_long.py").write_text(textwrap.dedent(HIL_TEST))
    # (without hypothesis's plugin, which imports hypothesis at every session's end: seconds here)
    cmd = [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "-p", "no:hypothesispytest"]
    cmd += ["--hil-keep", "none", "--basetemp", str(tmp_path / "tmp"), "test_long.py"]  # (killed: no temp left)
    cmd += ["-n", str(workers)] if workers else ["-p", "no:xdist", "-x"]
    front = start(cmd, cwd=tmp_path)
    # each test runs a rig and a bare virtual board (two interpreters); with workers, two at once
    family = wait_for(front, _micropythons(4 if workers else 2))
    print(f"pytest -n {workers},", kill_and_check(front, sig, family))


FLASH = "import sys, pathlib; from host.device import flash, vboard; vboard.VBOARD_ROOT = pathlib.Path(sys.argv[1]); "
FLASH += "raise SystemExit(flash.main(['--app', 'rover']))"


@pytest.mark.parametrize("sig", [signal.SIGKILL, signal.SIGTERM])
def test_a_stopped_flash_leaves_no_virtual_board_running(start, tmp_path, sig):
    """``make flash`` without PORT (``python -m host.device.flash``, its board folder in tmp):
    stopped while mpremote talks to the virtual board it started."""
    front = start([sys.executable, "-c", FLASH, str(tmp_path)])
    family = wait_for(front, lambda cmds: _micropythons(1)(cmds) and any("mpremote" in c for c in cmds))
    print("flash,", kill_and_check(front, sig, family))
    assert not (tmp_path / "esp32_devkitc" / "port").exists(), "expected the server to remove its port file"


def test_a_killed_virtual_board_server_takes_its_interpreter_with_it(tmp_path):
    home = tmp_path / "board"
    vboard.start_background("esp32_devkitc", home=home, wired=False)
    server = int((home / "vboard.pid").read_text())
    try:
        interpreters = descendants(server)
        assert interpreters, "expected the server's interpreter"
        os.kill(server, signal.SIGKILL)
        deadline = time.monotonic() + GONE_S
        while time.monotonic() < deadline and any(alive(p) for p in interpreters | {server}):
            time.sleep(0.02)
            vboard._gone(server)  # (reaps it: this process started it)
        assert not any(alive(p) for p in interpreters), [program(p) for p in interpreters]
    finally:
        vboard.stop_background("esp32_devkitc", home)


def test_a_detached_virtual_board_outlives_its_starter_and_ends_when_idle(tmp_path):
    home = tmp_path / "board"
    cmd = [sys.executable, "-m", "host.device.vboard", "start", "--bare", "--home", str(home), "--idle-exit-s", "2"]
    done = subprocess.run(cmd, cwd=REPO, capture_output=True, text=True, timeout=60)
    assert done.returncode == 0 and done.stdout.startswith("/dev/pts/"), done
    server = int((home / "vboard.pid").read_text())
    family = descendants(server) | {server}
    try:
        assert alive(server), "expected vboard start's server to outlive the command"
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and any(alive(p) for p in family):
            time.sleep(0.05)
        assert not any(alive(p) for p in family), "expected the idle server to end after 2 s with no client"
        assert not (home / "port").exists() and not (home / "vboard.pid").exists()
    finally:
        vboard.stop_background("esp32_devkitc", home)

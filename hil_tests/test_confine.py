"""The firmware is confined to its board (issue 28, docs/security.md): a received trace
folder runs no firmware the user did not name."""

import json
import os
import shutil
import subprocess
import sys

import pytest

from host.artefacts.folder import reseal
from host.core.errors import ConfigError
from host.core.paths import FIRMWARE, REPO
from host.rig.loop.replay import FirmwareChoice, replay

pytestmark = [pytest.mark.hil, pytest.mark.xdist_group("test_confine")]

HOSTILE_MAIN = """\
import os
print("HOSTILE FIRMWARE RAN")
open("pwned.txt", "w").write("from a trace folder")
"""


@pytest.fixture(scope="module")
def rover_trace(tmp_path_factory):
    """A short recorded rover run (shared by the tests that craft folders from it)."""
    from host.rig import Recording, Rig, RigSpec

    folder = tmp_path_factory.mktemp("rover-seed5")
    with Rig(RigSpec("rover", seed=5), Recording(trace=True, record=True, artefacts=folder)) as rig:
        rig.run_for(1.0)
    return folder


def hostile_folder(rover_trace, tmp_path):
    """A copy of a real trace folder whose header names a rig file with a hostile firmware
    beside it (as a folder handed over by someone else could)."""
    evil = tmp_path / "evil"
    evil.mkdir()
    rig = (FIRMWARE / "apps" / "rover" / "rig.toml").read_text()
    (evil / "rig.toml").write_text(rig)
    (evil / "main.py").write_text(HOSTILE_MAIN)
    trace = tmp_path / "received"
    shutil.copytree(rover_trace, trace)
    header = json.loads((trace / "header.json").read_text())
    header["spec"]["app"] = str(evil / "rig.toml")
    (trace / "header.json").write_text(json.dumps(header))
    reseal(trace)
    return trace, evil


def test_replay_refuses_the_firmware_a_received_folder_names(rover_trace, tmp_path):
    trace, evil = hostile_folder(rover_trace, tmp_path)
    with pytest.raises(ConfigError, match="--trust-folder") as e:
        replay(trace, tmp_path / "replay")
    assert str(evil / "rig.toml") in str(e.value)
    assert not list(tmp_path.rglob("pwned.txt")), "the hostile firmware ran"


def test_replay_runs_the_firmware_the_user_names_and_says_so(rover_trace, tmp_path):
    trace, _evil = hostile_folder(rover_trace, tmp_path)
    ours = FIRMWARE / "apps" / "rover"
    result = replay(trace, tmp_path / "replay", choice=FirmwareChoice(app="rover"))
    assert result.same, result.difference
    assert str(ours) in result.firmware and "--app" in result.firmware, result.firmware
    assert not list(tmp_path.rglob("pwned.txt")), "the hostile firmware ran"


def test_a_header_naming_a_firmware_folder_needs_a_flag_too(rover_trace, tmp_path):
    trace = tmp_path / "received"
    shutil.copytree(rover_trace, trace)
    header = json.loads((trace / "header.json").read_text())
    header["spec"]["main_dir"] = str(tmp_path)
    (trace / "header.json").write_text(json.dumps(header))
    reseal(trace)
    with pytest.raises(ConfigError, match=f"main_dir {tmp_path}"):
        replay(trace, tmp_path / "replay")


def test_mpy_fil_replay_says_which_firmware_and_refuses_a_hostile_one_in_one_line(rover_trace, tmp_path):
    trace, _evil = hostile_folder(rover_trace, tmp_path)
    run = [sys.executable, "-m", "host.cli", "replay", str(trace), "--out", str(tmp_path / "r")]
    done = subprocess.run(run, capture_output=True, text=True, cwd=REPO, timeout=120)
    assert done.returncode == 2 and done.stderr.count("\n") == 1, done.stderr
    assert "HOSTILE" not in done.stdout + done.stderr and not list(tmp_path.rglob("pwned.txt"))
    # (the crafted header names another firmware than the one its manifest.json recorded)
    trusted = [*run, "--trust-folder", "--ignore-manifest"]
    done = subprocess.run(trusted, capture_output=True, text=True, cwd=REPO, timeout=120)
    assert "--trust-folder" in done.stdout, done.stdout + done.stderr  # it says which one it ran
    own = subprocess.run(
        [sys.executable, "-m", "host.cli", "replay", str(rover_trace), "--out", str(tmp_path / "o")],
        capture_output=True,
        text=True,
        cwd=REPO,
        timeout=120,
    )
    assert own.returncode == 0 and "our app rover" in own.stdout, own.stdout + own.stderr


# -- hostile firmware: what it reaches on the host -----------------------------------------

PROBE = """\
import os

def attempt(what, f):
    try:
        result = f()
    except Exception as e:
        print("REFUSED", what, type(e).__name__, e)
    else:
        print("REACHED", what, repr(result)[:80])

"""


ENOENT = ("REFUSED", "OSError [Errno 2] ENOENT")


def run_firmware(tmp_path, body, rig_lines="", coverage=None, watchdog_s=5.0):
    """Run ``body`` as a firmware's main.py (after PROBE) on the rover's rig (its coverage
    measured into ``coverage``, a path, when given; ``watchdog_s``: the wall-clock wait for a
    firmware that computes long between two waits); its console lines by what they tried,
    and the run's folder."""
    fw = tmp_path / "fw"
    fw.mkdir(exist_ok=True)
    (fw / "main.py").write_text(PROBE + body)
    rig = (FIRMWARE / "apps" / "rover" / "rig.toml").read_text()
    rig = rig.replace('dir = "."', f'dir = "{fw}"').replace(
        "harness_lib = true", "harness_lib = true\nallow_exit = true"
    )
    rig = rig.replace('name = "esp32_devkitc"', 'name = "esp32_devkitc"\n' + rig_lines, 1)
    (tmp_path / "rig.toml").write_text(rig)
    from host.rig import Recording, Rig, RigSpec

    out = tmp_path / "run"
    spec = RigSpec(str(tmp_path / "rig.toml"), seed=1, watchdog_s=watchdog_s)
    with Rig(spec, Recording(record=True, artefacts=out, coverage=coverage)) as rig:
        rig.run_for(0.5)
    said = {}
    for line in rig.console.splitlines():
        verdict, _, rest = line.partition(" ")
        if verdict in ("REACHED", "REFUSED"):
            what, _, how = rest.partition(" ")
            said[what] = (verdict, how)
    return said, out


def test_firmware_cannot_read_host_files(tmp_path):
    home = os.path.expanduser("~")
    said, _ = run_firmware(
        tmp_path,
        f"""
attempt("passwd", lambda: open("/etc/passwd").read())
attempt("dotdot", lambda: open("../../../../../../etc/passwd").read())
attempt("ssh", lambda: os.listdir("{home}/.ssh"))
attempt("makefile", lambda: open("{REPO}/Makefile").read())
attempt("root", lambda: os.listdir("/"))
attempt("up", lambda: os.listdir("/.."))
""",
    )
    for what in ("passwd", "dotdot", "ssh", "makefile"):
        assert said[what] == ENOENT, (what, said)  # ENOENT, as on a board
    assert said["root"][0] == "REACHED" and "main.py" in said["root"][1] and "etc" not in said["root"][1], said
    assert said["up"] == said["root"], said  # / has no parent


def test_firmware_writes_stay_on_its_board_and_are_kept(tmp_path):
    said, out = run_firmware(
        tmp_path,
        f"""
attempt("tmp", lambda: open("{tmp_path}/outside.txt", "w").write("x"))
attempt("up", lambda: open("../../outside.txt", "w").write("x"))
attempt("log", lambda: open("log.txt", "w").write("hello"))
attempt("mkdir", lambda: os.mkdir("data"))
attempt("nested", lambda: open("/data/n.txt", "w").write("n"))
attempt("missing", lambda: open("nothing.txt"))
attempt("remove_main", lambda: os.remove("main.py"))
""",
    )
    assert said["tmp"] == ENOENT, said
    assert said["up"][0] == "REACHED" and said["log"][0] == "REACHED" and said["nested"][0] == "REACHED", said
    assert said["missing"] == ENOENT, said
    assert not (tmp_path / "outside.txt").exists() and not (tmp_path.parent / "outside.txt").exists()
    assert sorted(p.name for p in (tmp_path / "fw").iterdir()) == ["main.py"], "the sources were written to"
    assert (out / "board_fs" / "log.txt").read_text() == "hello" and (out / "board_fs" / "outside.txt").is_file()
    header = json.loads((out / "header.json").read_text())
    assert header["board_fs"] == ["data/n.txt", "log.txt", "outside.txt"], header.get("board_fs")


def test_firmware_has_no_host_process_environment_ffi_socket_or_thread(tmp_path):
    import socket

    listener = socket.socket()
    listener.bind(("127.0.0.1", 0))
    listener.listen(1)
    listener.settimeout(0)
    port = listener.getsockname()[1]
    marker = tmp_path / "system-ran"
    try:
        said, _ = run_firmware(
            tmp_path,
            f"""
attempt("system", lambda: os.system("touch {marker}"))
attempt("getenv", lambda: os.getenv("HOME"))
attempt("ffi", lambda: __import__("ffi").open("libc.so.6").func("i", "system", "s")("touch {marker}"))
def connect():
    import socket
    s = socket.socket()
    s.connect(socket.getaddrinfo("127.0.0.1", {port})[0][-1])
    return s
attempt("socket", connect)
attempt("thread", lambda: __import__("_thread").start_new_thread(print, ("thread",)))
attempt("termios", lambda: __import__("termios"))
attempt("vfs", lambda: __import__("vfs").VfsPosix("/"))
""",
        )
        try:
            conn, _ = listener.accept()
            conn.close()
            connected = True
        except BlockingIOError:
            connected = False
    finally:
        listener.close()
    assert said["system"][:1] == ("REFUSED",) and said["system"][1].startswith("AttributeError"), said
    assert said["getenv"][1].startswith("AttributeError"), said
    for what in ("ffi", "termios"):
        assert said[what][0] == "REFUSED" and said[what][1].startswith("ImportError"), (what, said)
    # the ESP32 port has _thread: the board's, on the one virtual clock (host/shim/_hilthread.py)
    assert said["thread"][0] == "REACHED", said
    # the rover's ESP32 has a radio: its socket is the board's, with no network in range (no route)
    assert said["socket"][0] == "REFUSED" and said["socket"][1].startswith("OSError"), said
    assert said["vfs"][1].startswith("AttributeError"), said
    assert not marker.exists() and not connected


def test_a_rig_file_allows_a_module_by_name_with_its_reason(tmp_path):
    said, _ = run_firmware(
        tmp_path,
        'attempt("thread", lambda: __import__("_thread").get_ident() > 0)\n'
        'attempt("termios", lambda: __import__("termios"))\n',
        'allow_modules = {_thread = "the ESP32 port has threads"}',
    )
    assert said["thread"] == ("REACHED", "True") and said["termios"][0] == "REFUSED", said


def test_the_flash_has_its_size_and_statvfs_agrees(tmp_path):
    said, out = run_firmware(
        tmp_path,
        """
st = os.statvfs("/")
print("FLASH", st[0] * st[2], st[0] * st[3])
free = st[0] * st[3]
def fill():
    with open("big.bin", "wb") as f:
        for i in range(free // 1024 + 8):
            f.write(bytes(1024))
attempt("fill", fill)
after = os.statvfs("/")
print("FREE", after[0] * after[3])
attempt("remove", lambda: os.remove("big.bin"))
print("FREED", os.statvfs("/")[0] * os.statvfs("/")[3] == free)
""",
        'flash_size = "64K"',
    )
    console = (out / "console.log").read_text()
    assert "FLASH 65536 " in console, console
    assert said["fill"] == ("REFUSED", "OSError 28"), said  # ENOSPC (MicroPython names few errnos: a board says 28 too)
    assert "FREE 0" in console and "FREED True" in console, console


# -- defence in depth: a firmware that gets round the shim meets the sandbox --------------

GET_ROUND = """
import sys
import builtins
sys.modules.pop("vfs", None)
sys.modules.pop("socket", None)  # (the board's, on the rover's ESP32: the unix port's again)
del builtins.__import__  # the unix port's own import again
import vfs
host = vfs.VfsPosix()
attempt("passwd", lambda: host.open("/etc/passwd", "r").read())
attempt("sources", lambda: host.open("{repo}/Makefile", "r").read())
attempt("tmp", lambda: host.open("{tmp}/reached", "w"))  # (the test's own folder: nothing left on the host)
def connect():
    import socket
    s = socket.socket()
    s.connect(socket.getaddrinfo("127.0.0.1", {port})[0][-1])
    return s
attempt("socket", connect)
"""


def get_round(tmp_path, monkeypatch, mode):
    import socket

    monkeypatch.setenv("MPY_FIL_SANDBOX", mode)
    listener = socket.socket()
    listener.bind(("127.0.0.1", 0))
    listener.listen(1)
    try:
        said, _ = run_firmware(tmp_path, GET_ROUND.format(repo=REPO, tmp=tmp_path, port=listener.getsockname()[1]))
    finally:
        listener.close()
    return said


def test_without_the_sandbox_a_firmware_that_gets_round_the_shim_reaches_the_host(tmp_path, monkeypatch):
    """What the sandbox is for: the shim's confinement is a board's view, not a wall."""
    said = get_round(tmp_path, monkeypatch, "off")
    assert said["passwd"][0] == "REACHED" and said["socket"][0] == "REACHED", said


def test_in_the_sandbox_a_firmware_that_gets_round_the_shim_reaches_nothing(tmp_path, monkeypatch):
    from host.rig.targets import sandbox

    if sandbox.refusal():
        pytest.skip(f"no sandbox on this machine: {sandbox.refusal()}")
    said = get_round(tmp_path, monkeypatch, "require")
    assert said["passwd"] == ENOENT and said["sources"] == ENOENT, said
    assert said["tmp"][0] == "REFUSED", said  # (a read-only view: only the board's folder is writable)
    assert said["socket"][0] == "REFUSED" and said["socket"][1].startswith("OSError"), said


def test_a_required_sandbox_that_cannot_start_refuses_the_run(tmp_path, monkeypatch):
    from host.core.errors import SetupError
    from host.rig.targets import sandbox

    monkeypatch.setattr(sandbox, "refusal", lambda: "the kernel refuses new namespaces (a test)")
    monkeypatch.setenv("MPY_FIL_SANDBOX", "require")
    with pytest.raises(SetupError, match="the sandbox is required"):
        run_firmware(tmp_path, "")


def test_a_firmware_package_imports_relatively_on_its_board(tmp_path):
    pkg = tmp_path / "fw" / "lib" / "pkg"
    pkg.mkdir(parents=True)
    (pkg / "__init__.py").write_text("from . import helper\nfrom .helper import VALUE\n")
    (pkg / "helper.py").write_text("VALUE = 42\n")
    said, _ = run_firmware(tmp_path, 'attempt("pkg", lambda: __import__("pkg").VALUE)\n')
    assert said["pkg"] == ("REACHED", "42"), said


def test_mpy_fil_run_lists_what_the_firmware_wrote_on_its_flash(tmp_path):
    run_firmware(tmp_path, 'open("log.txt", "w").write("hello")\n')  # (writes the rig file and firmware)
    out = tmp_path / "cli"
    cmd = [sys.executable, "-m", "host.cli", "run", str(tmp_path / "rig.toml"), "--duration", "0.5", "--out", str(out)]
    done = subprocess.run([*cmd, "--no-plots"], capture_output=True, text=True, cwd=REPO, timeout=120)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "board_fs/log.txt" in done.stdout and (out / "board_fs" / "log.txt").read_text() == "hello", done.stdout
    assert sorted(p.name for p in (tmp_path / "fw").iterdir()) == ["main.py"], "the sources were written to"


def test_a_board_folder_left_by_a_killed_harness_goes_with_the_next_run(tmp_path, monkeypatch):
    import signal
    import tempfile

    from host.rig import Rig, RigSpec

    monkeypatch.setenv("TMPDIR", str(tmp_path))
    monkeypatch.setattr(tempfile, "tempdir", None)  # (read TMPDIR again)
    code = "from host.rig import Rig, RigSpec\nRig(RigSpec('rover', seed=1)).start()\nprint('up', flush=True)\n"
    code += "import time\ntime.sleep(60)\n"
    proc = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, text=True, cwd=REPO)
    try:
        assert proc.stdout.readline() == "up\n"
    finally:
        os.kill(proc.pid, signal.SIGKILL)
        proc.wait()
        proc.stdout.close()
    assert len(list(tmp_path.glob("mpy-fil-board-*"))) == 1, "expected the killed run's board folder"
    with Rig(RigSpec("rover", seed=1)):
        pass
    assert not list(tmp_path.glob("mpy-fil-board-*")), "the killed run's board folder is still there"

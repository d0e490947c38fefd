"""The board's flash (issue 40): only what ``make flash`` puts on a board goes in the per-run
copy, counted as littlefs counts it, and nothing the shim leaves reachable holds the host."""

import json
import os

import pytest

from hil_tests.test_confine import run_firmware
from host.core.errors import ConfigError

pytestmark = [pytest.mark.hil, pytest.mark.xdist_group("test_board_flash")]

FLASH_64K = 'flash_size = "64K"'


def test_a_sparse_write_past_the_flash_is_refused_and_never_reaches_the_host(tmp_path):
    said, out = run_firmware(
        tmp_path,
        """
def sparse():
    with open("sparse.bin", "wb") as f:
        f.seek(1 << 30)
        f.write(b"x")
attempt("sparse", sparse)
def big():
    with open("big.bin", "wb") as f:
        for i in range(20 * 1024):
            f.write(bytes(1024))
attempt("big", big)
st = os.statvfs("/")
print("FREE", st[0] * st[3], "SIZE", os.stat("big.bin")[6])
os.remove("big.bin")
def two_handles():
    a = open("two.bin", "wb")
    a.write(bytes(8192))
    b = open("two.bin", "wb")  # (truncates what a still writes past)
    for i in range(64):
        a.write(bytes(1024))
attempt("two", two_handles)
def round_the_count():
    f = open("round.bin", "wb")
    return f._op("attr", f._key, "write")
attempt("round", round_the_count)
def renames():
    with open("r.bin", "wb") as f:
        f.write(bytes(8192))
    for i in range(100):
        os.rename("r.bin", "r.bin")  # (onto itself: frees nothing)
    with open("more.bin", "wb") as f:
        for i in range(64):
            f.write(bytes(1024))
os.remove("two.bin")
attempt("renames", renames)
""",
        FLASH_64K,
    )
    console = (out / "console.log").read_text()
    for what in ("sparse", "big", "two", "renames"):
        assert said[what] == ("REFUSED", "OSError 28"), (what, said)
    assert said["round"] == ("REFUSED", "AttributeError write"), said
    size = int(console.split("SIZE ")[1].split()[0])
    free = int(console.split("FREE ")[1].split()[0])
    assert size < 64 * 1024 and free < 4096, console  # (what the flash held, and no more)
    kept = sum(p.stat().st_size for p in (out / "board_fs").rglob("*") if p.is_file())
    assert kept <= 64 * 1024, kept


def test_empty_files_and_folders_take_the_flashs_metadata_blocks_until_enospc(tmp_path):
    said, out = run_firmware(
        tmp_path,
        """
print("FREE0", os.statvfs("/")[3])
n = 0
def many():
    global n
    while n < 30000:
        open("f%05d" % n, "w").close()
        n += 1
attempt("many", many)
print("FILES", n)
def dirs():
    for i in range(1000):
        os.mkdir("d%d" % i)
attempt("dirs", dirs)
st = os.statvfs("/")
print("STATVFS", st[0], st[2], st[3])
""",
        FLASH_64K,
    )
    console = (out / "console.log").read_text()
    files = int(console.split("FILES ")[1].split()[0])
    free = int(console.split("FREE0 ")[1].split()[0])
    assert said["many"] == ("REFUSED", "OSError 28"), said
    # each new pair of 2 blocks holds 2 KiB of entries of 18 bytes (12 of tags, a 6-letter name)
    per_pair = 2048 // 18
    assert (free // 2) * per_pair <= files <= (free // 2 + 1) * per_pair, console
    assert said["dirs"] == ("REFUSED", "OSError 28") and "STATVFS 4096 16 " in console, said


def test_a_symlinked_data_file_in_the_firmware_folder_is_refused_by_name(tmp_path):
    fw = tmp_path / "fw"
    fw.mkdir()
    os.symlink("/etc/passwd", fw / "passwd.json")
    with pytest.raises(ConfigError, match=r"passwd\.json is a symbolic link \(to /etc/passwd\)"):
        run_firmware(tmp_path, 'print(open("passwd.json").read())\n')


def test_tests_build_and_trace_folders_beside_the_firmware_are_not_on_its_flash(tmp_path):
    fw = tmp_path / "fw"
    (fw / "build" / "runs" / "old").mkdir(parents=True)
    (fw / "build" / "runs" / "old" / "header.json").write_text("{}")
    (fw / "trace1").mkdir()
    (fw / "trace1" / "trace.jsonl").write_text("")
    (fw / "trace1" / "console.log").write_text("")
    (fw / "assets").mkdir()
    (fw / "assets" / "manifest.json").write_text("{}")  # (one alone: the firmware's own data)
    (fw / "trace1" / "data.json").write_text("{}")
    (fw / "test_main.py").write_text("def test_x():\n    pass\n")
    (fw / "conftest.py").write_text("")
    (fw / "config.json").write_text('{"speed": 1}')
    said, out = run_firmware(tmp_path, 'attempt("ls", lambda: sorted(os.listdir("/")))\n')
    assert said["ls"] == ("REACHED", repr(["assets", "config.json", "lib", "main.py"])), said
    files = json.loads((out / "manifest.json").read_text())["firmware"]["files"]
    assert not [name for name in files if "build" in name or "test_" in name or "trace1" in name], files
    assert "config.json" in files and "main.py" in files and "assets/manifest.json" in files


WALK_WATCHDOG_S = 60.0
"""The walk computes for seconds between its sleeps under the line tracer on a loaded machine
(the rig's usual 5 s watchdog stopped it under a load of 6 on 2 cores)."""
WALK = """
import sys, builtins, vfs, machine, time, select
HOSTISH = ("system", "getenv", "VfsPosix", "putenv", "unsetenv")
HOST_MODULES = ("ffi", "socket", "usocket", "termios", "_thread")
seen = {}
found = []
visits = [0]  # (objects walked, re-walks included)
seen[id(seen)] = seen[id(found)] = seen[id(visits)] = -1  # (the walk's own)
def host_handle(value):
    kind = type(value).__name__
    if kind != "module" and kind != "type":
        try:
            fd = value.fileno()
        except Exception:
            fd = None
        if isinstance(fd, int) and fd > 2:  # (the console's 0, 1, 2: a board's too)
            return "a host file (%s, fd %d)" % (kind, fd)
    if kind == "VfsPosix" or (hasattr(vfs, "VfsPosix") and value is vfs.VfsPosix):
        return "a VfsPosix"
    if kind == "module" and getattr(value, "__name__", "") in HOST_MODULES:
        return "module " + value.__name__
    for name in HOSTISH:
        try:
            if hasattr(value, name) and kind != "str":
                return "has " + name
        except Exception:
            pass
    if isinstance(value, str) and (value.startswith("{board}") or value.startswith("{repo}")):
        return "host path " + value[:60]
    return None
def walk(value, where, depth):
    key = id(value)
    if seen.get(key, 99) <= depth or len(seen) > 40000:
        return  # (met again nearer a root: walked again, deeper)
    seen[key] = depth
    visits[0] += 1
    if visits[0] % 500 == 0:
        time.sleep_ms(1)  # (the host hears from the walk: its watchdog waits 5 s of wall time for a message)
    bad = host_handle(value)
    if bad:
        found.append(where + ": " + bad if len(found) < 30 else "")
        return
    if depth > 7 or isinstance(value, (int, float, str, bytes, bool)) or value is None:
        return
    if isinstance(value, dict):
        for k in list(value):
            if k == "executable":
                continue  # (the unix port's own sys: a ROM attribute; the board's sys has none, below)
            if type(value[k]).__name__ == "bound_method":  # (kept: its object out of sight, a file's write the file)
                found.append(where + "[" + repr(k)[:30] + "]: a bound method" if len(found) < 30 else "")
            walk(k, where + " key " + repr(k)[:30], depth + 1)
            walk(value[k], where + "[" + repr(k)[:30] + "]", depth + 1)
        return
    if isinstance(value, (list, tuple)):
        for i, item in enumerate(value):
            walk(item, where + "[" + str(i) + "]", depth + 1)
        return
    try:
        names = dir(value)
    except Exception:
        return
    for name in names + ["__globals__", "__self__", "__func__", "__dict__", "__class__"]:
        if name in ("__init__", "__new__") and depth:
            pass
        if name == "executable":
            continue  # (as above)
        try:
            item = getattr(value, name)
        except Exception:
            continue
        walk(item, where + "." + name, depth + 1)
roots = {"sys.modules": sys.modules, "builtins": builtins, "mounts": vfs.mount(), "machine": machine,
         "time": time, "select": select, "sys": sys}
for name in {private}:
    try:
        roots[name] = __import__(name)
    except ImportError as e:
        print("NOIMPORT", name, e)
    else:
        print("IMPORTED", name)
for name in sorted(roots):
    walk(roots[name], name, 0)
for hit in found[:30]:
    print("HOST", hit)
print("WALKED", len(seen), "FOUND", len(found), "EXECUTABLE", hasattr(sys, "executable"))
"""


def test_open_takes_a_path_never_a_host_file_descriptor_as_on_a_board(tmp_path, monkeypatch):
    monkeypatch.setenv("MPY_FIL_SANDBOX", "off")
    said, _ = run_firmware(
        tmp_path,
        """
import io
import _hilboot
for fd in range(0, 12):
    attempt("open%d" % fd, lambda: open(fd, "rb"))
attempt("io", lambda: io.open(3, "rb"))
attempt("shim_io", lambda: _hilboot.io.open(3, "rb"))
attempt("path", lambda: open("main.py").read(6))
""",
    )
    refused = ("REFUSED", "TypeError can't convert 'int' object to str implicitly")
    for what in [f"open{fd}" for fd in range(12)] + ["io", "shim_io"]:
        assert said[what] == refused, (what, said)
    assert said["path"][0] == "REACHED", said


def test_nothing_the_shim_leaves_reachable_holds_a_host_handle_with_the_sandbox_off(tmp_path, monkeypatch):
    """Attribute walks over everything reachable from vfs, machine, sys.modules, time,
    select and builtins (functions' __globals__ too) meet no VfsPosix, no host os or host
    module and no host path of the board's copy or the shim."""
    monkeypatch.setenv("MPY_FIL_SANDBOX", "off")
    import tempfile

    from host.core.paths import REPO
    from host.rig.targets.boardfs import PREFIX

    board = os.path.join(tempfile.gettempdir(), PREFIX)
    walk = WALK.replace("{board}", board).replace("{repo}", str(REPO)).replace("{private}", "()")
    said, out = run_firmware(tmp_path, walk, coverage=tmp_path / "coverage.data", watchdog_s=WALK_WATCHDOG_S)
    console = (out / "console.log").read_text()
    hits = [line for line in console.splitlines() if " HOST " in line]
    assert "WALKED" in console and not hits, "\n".join(hits[:30])
    assert int(console.split("WALKED ")[1].split()[0]) < 40000, "the walk stopped at its bound"
    assert "EXECUTABLE False" in console, "expected the board's sys without executable (the unix port's alone)"
    assert (tmp_path / "coverage.data").exists()  # (the coverage file was open while it walked)


SHIM_PRIVATE = sorted(
    name[:-3]
    for name in os.listdir(os.path.join(os.path.dirname(__file__), "..", "host", "shim"))
    if name.startswith("_") and name.endswith(".py") and name != "__init__.py"
) + ["_hilfast"]


def test_the_shims_private_modules_imported_by_firmware_reach_neither_the_link_nor_the_coverage_file(
    tmp_path, monkeypatch
):
    """A firmware that imports the shim's own modules (_hil, _hilcov, _hilboot, ...: on the
    path as /_hil) and walks them, sandbox off, finds no host file: not the link's pty (a
    board has no such object), not the coverage file."""
    monkeypatch.setenv("MPY_FIL_SANDBOX", "off")
    import tempfile

    from host.core.paths import REPO
    from host.rig.targets.boardfs import PREFIX

    board = os.path.join(tempfile.gettempdir(), PREFIX)
    walk = WALK.replace("{board}", board).replace("{repo}", str(REPO)).replace("{private}", repr(SHIM_PRIVATE))
    said, out = run_firmware(tmp_path, walk, coverage=tmp_path / "coverage.data", watchdog_s=WALK_WATCHDOG_S)
    console = (out / "console.log").read_text()
    imported = [line.split()[-1] for line in console.splitlines() if " IMPORTED " in line]
    hits = [line for line in console.splitlines() if " HOST " in line]
    assert "_hil" in imported and "_hilcov" in imported, console[-2000:]
    assert "WALKED" in console and not hits, "\n".join(hits[:30])
    assert int(console.split("WALKED ")[1].split()[0]) < 40000, "the walk stopped at its bound"


def test_mpy_fil_run_writes_at_the_users_repository_root_never_in_the_firmware_folder(tmp_path):
    import shutil
    import subprocess
    import sys

    from host.core.paths import REPO

    repo = tmp_path / "robot"
    bot = repo / "firmware" / "bot"
    shutil.copytree(REPO / "examples" / "pico_bot", bot, ignore=shutil.ignore_patterns("build", "__pycache__"))
    (repo / "pyproject.toml").write_text("[project]\nname = 'robot'\n")
    before = {p.relative_to(bot) for p in bot.rglob("*")}
    done = subprocess.run(
        [sys.executable, "-m", "host.cli", "run", str(bot / "rig.toml"), "--seconds", "1"],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=tmp_path,
    )
    assert done.returncode == 0, done.stdout[-2000:] + done.stderr[-2000:]
    assert f"trace folder: {repo / 'build' / 'runs'}" in done.stdout, done.stdout
    assert {p.relative_to(bot) for p in bot.rglob("*")} == before, "the run wrote into the firmware folder"
    manifest = json.loads(next((repo / "build" / "runs").glob("*/manifest.json")).read_text())
    assert manifest["project"] == {"root": str(repo), "commit": None}, manifest["project"]
    assert sorted(manifest["firmware"]["files"]) == ["main.py"], manifest["firmware"]["files"]


def test_print_and_json_write_through_a_file_on_the_flash_as_on_a_board(tmp_path):
    said, _ = run_firmware(
        tmp_path,
        """
import json
def printed():
    with open("p.txt", "w") as f:
        print("hello", 1, file=f)
    return open("p.txt").read()
attempt("print", printed)
def dumped():
    with open("j.json", "w") as f:
        json.dump({"a": 1}, f)
    with open("j.json") as f:
        return json.load(f)
attempt("json", dumped)
def full():
    with open("big.txt", "w") as f:
        while True:
            print("x" * 1000, file=f)
attempt("full", full)
def closed():
    a = open("a.txt", "w")
    a.close()
    b = open("b.txt", "w")
    try:
        a.write("into b?")
    finally:
        b.close()
attempt("closed", closed)
print("B", repr(open("b.txt").read()))
""",
        FLASH_64K,
    )
    assert said["print"] == ("REACHED", "'hello 1\\n'") and said["json"] == ("REACHED", "{'a': 1}"), said
    assert said["full"] == ("REFUSED", "OSError 28"), said
    assert said["closed"] == ("REFUSED", "ValueError "), said  # (a closed file stays closed)

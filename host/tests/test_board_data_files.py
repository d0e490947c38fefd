"""A firmware folder's data files reach the board, as ``mpremote cp -r`` of the folder puts
them there: a library's image, its text, a web server's pages (docs/shim.md, "The board's
filesystem"); what is the host's (the rig file, pytest's files, documentation, build/,
trace folders) never does. One rule for the per-run copy, the manifest and ``make flash``."""

import hashlib

import pytest

from host.core.errors import ConfigError
from host.rig.loop.manifest import firmware_part
from host.rig.targets.boardfs import BoardFs, flash_files, on_board
from host.rig.targets.firmware import Firmware
from host.tests.conftest import results, shim_app

# A 128x64 PBM as Pololu's 3pi+ 2040 library ships its splash screen (extras/splash.pbm):
# a text header, then raw bits holding every byte value (NUL, newline, 0xff: a text-mode
# read or a copy that stops at a NUL would show)
PBM = b"P4\n# made by hand\n128 64\n" + bytes(range(256)) * 4
NOTES = "first line\nsecond line, with UTF-8: \u00b5s\n"

DATA = {  # path in the firmware folder: bytes, each a file the board gets
    "robotlib/__init__.py": b"",
    "robotlib/display.py": b"def load(name):\n    with open(name, 'rb') as f:\n        return f.read()\n",
    "robotlib/extras/splash.pbm": PBM,
    "robotlib/notes.txt": NOTES.encode(),
    "www/index.html": b"<html><body>hello</body></html>\n",
    "www/style.css": b"body { color: red }\n",
    "www/app.js": b"console.log(1)\n",
    "www/index.html.gz": bytes([0x1F, 0x8B, 8, 0, 0, 0, 0, 0]),
    "fonts/font5x8.bin": bytes(range(40)),
    "readings.csv": b"t,v\n0,1\n",
    "certs/ca.pem": b"-----BEGIN CERTIFICATE-----\n",
    "wifi.cfg": b"ssid password\n",
    "config.json": b'{"speed": 3}\n',
}
HOST = {  # what stays on the host, each for its reason
    "rig.toml": b"[firmware]\n",  # the rig file
    "as_built.toml": b"",  # other TOML: the tools'
    "pyproject.toml": b"",
    "press.test.yaml": b"",  # Wokwi's test scenario
    "README.md": b"# bot\n",  # documentation
    "robotlib/README.rst": b"",
    "Makefile": b"all:\n",  # the repository's tools, and a file with no suffix
    "Dockerfile": b"FROM python\n",
    "LICENSE": b"MIT\n",
    "robotlib/LICENSE.txt": b"MIT\n",
    "requirements.txt": b"pytest\n",
    "test_bot.py": b"def test(): pass\n",  # pytest's
    "conftest.py": b"",
    "bot_test.py": b"",
    "stubs.pyi": b"",  # an editor's stubs, CPython's bytecode, an editor's backup
    "robotlib/display.cpython-312.pyc": b"",
    "main.py~": b"",
    "seen.log": b"x",  # what a rig's external part's program leaves in the rig file's folder
    "pid": b"123",
    "dev.pid": b"123",
    ".gitignore": b"build/\n",  # hidden
    ".vscode/settings.json": b"{}",
    "build/flash/x.bin": b"x",  # the host's folders
    "tests/data.txt": b"x",
    "node_modules/x.js": b"x",
    "htmlcov/index.html": b"x",
    "venv/lib.py": b"x",
    "old_run/header.json": b"{}",  # a trace folder
    "old_run/console.log": b"",
}
MAIN = """import os
import robotlib.display as display
pbm = display.load("robotlib/extras/splash.pbm")
print("R pbm", (len(pbm), pbm[:3], pbm.count(b"\\x00"), pbm.count(b"\\n")))
with open("/robotlib/notes.txt") as f:
    print("R notes", f.read().splitlines())
print("R root", sorted(os.listdir("/")))
print("R robotlib", sorted(os.listdir("robotlib")))
print("R size", os.stat("www/index.html.gz")[6])
"""


def make_folder(folder, files):
    for name, data in files.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_bytes(data)


@pytest.fixture
def firmware_folder(tmp_path):
    fw = tmp_path / "fw"
    make_folder(fw, {"main.py": MAIN.encode(), **DATA, **HOST})
    return fw


def test_a_firmware_folders_data_files_go_on_the_board_and_the_hosts_files_never(firmware_folder):
    files, folders = flash_files(firmware_folder)
    want = sorted(["main.py", *DATA])
    assert [rel for rel, _ in files] == want, f"expected the code and data files {want}, got {files}"
    assert folders == ["certs", "fonts", "robotlib", "robotlib/extras", "www"], folders
    firmware = Firmware(firmware_folder, [firmware_folder])
    assert sorted(on_board(firmware)) == want
    manifest = firmware_part(firmware)["files"]
    assert manifest["robotlib/extras/splash.pbm"]["sha256"] == hashlib.sha256(PBM).hexdigest(), manifest
    assert not set(manifest) & set(HOST), f"expected none of the host's files in the manifest, got {sorted(manifest)}"
    board = BoardFs(firmware)
    try:
        copied = {p.relative_to(board.root).as_posix(): p.read_bytes() for p in board.root.rglob("*") if p.is_file()}
    finally:
        board.remove()
    want = {"main.py": MAIN.encode(), **DATA}
    assert copied == want, f"expected the board's copy byte for byte, got {sorted(copied)}"


def test_a_data_file_changes_the_firmwares_identity_and_a_host_file_does_not(firmware_folder):
    firmware = Firmware(firmware_folder, [firmware_folder])
    first = firmware.identity()["sha256"]
    (firmware_folder / "README.md").write_text("# edited\n")
    (firmware_folder / "rig.toml").write_text("[firmware]\n# edited\n")
    assert firmware.identity()["sha256"] == first, "a README or rig file edit changed the firmware's identity"
    (firmware_folder / "robotlib" / "notes.txt").write_text("changed\n")
    assert firmware.identity()["sha256"] != first, "a data file the board reads did not change the identity"


def test_the_flash_size_counts_data_files_and_names_the_largest(tmp_path):
    fw = tmp_path / "fw"
    make_folder(fw, {"main.py": b"print(1)\n", "www/video.bin": bytes(70 * 1024), "www/index.html": b"x" * 100})
    with pytest.raises(
        ConfigError,
        match=r"its 3 files take 7\d+ bytes, more than the board's 65536-byte flash.*"
        r"the largest: www/video\.bin \(71680 bytes\), www/index\.html \(100 bytes\), main\.py",
    ):
        BoardFs(Firmware(fw, [fw], flash_bytes=64 * 1024))


@pytest.mark.hil
def test_a_library_reads_its_image_and_its_text_at_run_time_as_on_a_board(make_rig, firmware_folder):
    rig = make_rig(shim_app(), main_dir=firmware_folder, allow_exit=True)
    rig.run_for(0.1)
    rig.stop()
    r = results(rig.console)
    assert r.get("pbm") == (len(PBM), b"P4\n", PBM.count(0), PBM.count(b"\n")), rig.console
    assert r.get("notes") == NOTES.splitlines(), rig.console
    root = sorted(["main.py", "lib", "robotlib", "www", "fonts", "certs", "readings.csv", "wifi.cfg", "config.json"])
    assert r.get("root") == root, f"expected the board's / to hold {root}, got {r.get('root')}:\n{rig.console}"
    assert r.get("robotlib") == ["__init__.py", "display.py", "extras", "notes.txt"], rig.console
    assert r.get("size") == 8, rig.console


@pytest.mark.hil
def test_make_flash_stages_the_data_files_as_they_are(monkeypatch, tmp_path, firmware_folder):
    from host.device import flash
    from host.rig.config.app import Code
    from host.rig.config.apps import App, apps

    board = "esp32_devkitc"
    app = App("databot", board, make_plant=None, wiring={}, code=Code(folder=firmware_folder))
    monkeypatch.setitem(apps(), "databot", app)
    out, files = flash.stage("databot", board, root=tmp_path / "staged")
    for name, data in DATA.items():
        if name.endswith(".py"):
            assert name[:-3] + ".mpy" in files, f"expected {name} compiled, got {files}"
        else:
            assert name in files and (out / name).read_bytes() == data, f"expected {name} as it is, got {files}"
    assert not set(files) & set(HOST), f"expected none of the host's files staged, got {files}"

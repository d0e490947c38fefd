"""What goes on the board (issue 40): one rule for the per-run copy, the manifest and
``make flash``; the host reads back no more than the flash holds; artefacts never land in
the firmware folder; the manifest tells the harness's commit from the user's."""

import os
import subprocess
from pathlib import Path

import pytest

from host.core import paths, provenance
from host.core.errors import ConfigError
from host.rig.targets.boardfs import BoardFs, flash_files, on_board
from host.rig.targets.firmware import Firmware


def firmware_in(folder: Path, flash_bytes: int = 64 * 1024) -> Firmware:
    return Firmware(folder, [folder], flash_bytes=flash_bytes)


def test_a_file_past_the_flash_is_named_and_never_read_or_copied(tmp_path):
    fw = tmp_path / "fw"
    fw.mkdir()
    (fw / "main.py").write_text("print(1)\n")
    board = BoardFs(firmware_in(fw))
    try:
        with open(board.root / "huge.bin", "wb") as f:  # (as a firmware round the shim could)
            f.seek(1 << 30)
            f.write(b"x")
        (board.root / "log.txt").write_text("hello")
        os.symlink("/etc/passwd", board.root / "passwd.txt")
        names = board.keep(tmp_path / "kept")
    finally:
        board.remove()
    assert names == ["log.txt"], names
    assert sorted(p.name for p in (tmp_path / "kept").iterdir()) == ["log.txt"]
    assert board.faults == [
        f"board_fs/huge.bin: {(1 << 30) + 1} bytes, more than the 65536-byte flash holds "
        "(written round the shim's filesystem): not kept"
    ], board.faults


def test_one_rule_for_the_board_copy_the_manifest_and_make_flash(tmp_path):
    fw = tmp_path / "fw"
    (fw / "drivers").mkdir(parents=True)
    (fw / "build" / "runs").mkdir(parents=True)
    (fw / "tests").mkdir()
    (fw / "old_run").mkdir()
    for name in ("main.py", "drivers/motor.py", "mission.json", "build/runs/x.json", "tests/helper.py"):
        (fw / name).write_text("x = 1\n")
    for name in ("test_main.py", "conftest.py", "main_test.py", "old_run/header.json", "old_run/manifest.json"):
        (fw / name).write_text("{}\n")
    files, folders = flash_files(fw)
    assert [rel for rel, _ in files] == ["drivers/motor.py", "main.py", "mission.json"], files
    assert folders == ["drivers"], folders
    firmware = firmware_in(fw)
    assert sorted(on_board(firmware)) == ["drivers/motor.py", "main.py", "mission.json"]
    board = BoardFs(firmware)
    try:
        copied = sorted(p.relative_to(board.root).as_posix() for p in board.root.rglob("*") if p.is_file())
    finally:
        board.remove()
    assert copied == ["drivers/motor.py", "main.py", "mission.json"], copied


@pytest.mark.parametrize("link", ["data.json", "lib", "main.py"])
def test_a_link_in_the_firmware_folder_is_refused_by_name(tmp_path, link):
    fw = tmp_path / "fw"
    fw.mkdir()
    if link != "main.py":
        (fw / "main.py").write_text("print(1)\n")
    target = "/etc" if link == "lib" else "/etc/passwd"
    os.symlink(target, fw / link)
    with pytest.raises(ConfigError, match=rf"firmware folder {fw}: {link} is a symbolic link \(to {target}\)"):
        firmware_in(fw).files()


def test_a_users_artefacts_go_to_its_repository_build_never_in_the_firmware_folder(tmp_path):
    repo = tmp_path / "robot"
    bot = repo / "firmware" / "bot"
    bot.mkdir(parents=True)
    (repo / "pyproject.toml").write_text("[project]\nname = 'robot'\n")
    (bot / "rig.toml").write_text("[firmware]\n")
    assert paths.output_root(bot / "rig.toml") == repo / "build"
    alone = tmp_path / "alone"  # (no repository around it: the rig file's folder is its root)
    alone.mkdir()
    (alone / "rig.toml").write_text("[firmware]\n")
    assert paths.output_root(alone / "rig.toml") == alone / "build"


def test_the_manifest_names_the_users_commit_apart_from_the_harnesss(tmp_path):
    repo = tmp_path / "robot"
    repo.mkdir()
    git = ["git", "-C", str(repo), "-c", "user.name=t", "-c", "user.email=t@t"]
    subprocess.run([*git, "init", "-q"], check=True)
    (repo / "rig.toml").write_text("[firmware]\n")
    subprocess.run([*git, "add", "rig.toml"], check=True)
    subprocess.run([*git, "commit", "-qm", "first"], check=True)
    head = subprocess.run([*git, "rev-parse", "HEAD"], capture_output=True, text=True, check=True).stdout.strip()
    provenance.project_commit.cache_clear()
    found = provenance.project_commit(repo)
    assert found == {"root": str(repo), "commit": head}, found
    assert provenance.commit() != head
    assert provenance.project_commit(paths.REPO) is None  # (our own checkout: the harness's commit only)


class PosixHost:
    """The unix port's VfsPosix as _hilfs uses it, for CPython."""

    def stat(self, path):
        return tuple(os.stat(path))

    def ilistdir(self, path):
        return [(e.name, 0x4000 if e.is_dir() else 0x8000, 0) for e in os.scandir(path)]

    def open(self, path, mode):
        return open(path, mode, buffering=0)  # (VfsPosix's files write through, unbuffered)

    remove, rename, mkdir, rmdir = (staticmethod(f) for f in (os.remove, os.rename, os.mkdir, os.rmdir))


@pytest.mark.parametrize("seed", [7, 8, 9])
def test_the_flashs_count_after_any_changes_is_what_a_fresh_count_of_its_files_gives(tmp_path, seed):
    import random

    from host.shim import _hilfs

    root = tmp_path / "flash"
    root.mkdir()
    board = _hilfs._board(PosixHost(), str(root), str(tmp_path / "shim"), 64 * 1024)
    rng = random.Random(seed)
    names = ["a", "b", "d/c", "d/e", "d", "x/y", "x"]
    refused = 0
    for _ in range(400):
        name = rng.choice(names)
        op = rng.choice(["write", "write", "append", "sparse", "remove", "rename", "mkdir", "rmdir"])
        try:
            if op in ("write", "append", "sparse"):
                with board.open(name, "ab" if op == "append" else "wb") as f:
                    if op == "sparse":
                        f.seek(rng.choice([100, 5000, 70000]))
                    f.write(bytes(rng.choice([0, 10, 128, 129, 4000, 9000, 30000])))
            elif op == "remove":
                board.remove(name)
            elif op == "rename":
                board.rename(name, rng.choice(names))
            elif op == "mkdir":
                board.mkdir(name)
            else:
                board.rmdir(name)
        except OSError as e:
            refused += e.errno == 28 or e.args[:1] == (28,)
        fresh = _hilfs._board(PosixHost(), str(root), str(tmp_path / "shim"), 64 * 1024)
        assert board.statvfs("/") == fresh.statvfs("/"), (op, name, sorted(p.name for p in root.rglob("*")))
        held = sum(p.stat().st_size for p in root.rglob("*") if p.is_file())
        assert held <= 64 * 1024, held
    assert refused, "expected the 64K flash to fill at least once"


def test_the_flashs_blocks_are_littlefss():
    from host.shim._hilfs import data_blocks, entry_bytes, pair_blocks

    assert [data_blocks(n) for n in (0, 128, 129, 4096, 4097, 8188, 8189)] == [0, 0, 1, 1, 2, 2, 3]
    # (block 0 holds 4096 bytes, block 1 4092: 1 pointer, block 2 4088: 2 pointers; lfs_ctz_index)
    assert data_blocks(1 << 20) == 257 and entry_bytes("log.txt", 5) == 24 and entry_bytes("lib") == 23
    assert [pair_blocks(b) for b in (0, 2048, 2049)] == [2, 2, 4]


def test_a_replay_is_not_refused_for_the_users_commit_alone():
    from host.rig.loop.manifest import differences

    recorded = {"firmware": {"sha256": "a"}, "harness": {"commit": "h"}}
    now = {"firmware": {"sha256": "a"}, "harness": {"commit": "h"}, "project": {"root": "/r", "commit": "c"}}
    assert differences(recorded, now) == []
    assert differences({**recorded, "project": {"root": "/r", "commit": "b"}}, now) == []


def test_a_firmware_bigger_than_its_flash_is_refused_before_it_runs(tmp_path):
    fw = tmp_path / "fw"
    fw.mkdir()
    (fw / "main.py").write_text("print(1)\n")
    (fw / "table.json").write_text("[" + "0," * 40_000 + "0]")
    with pytest.raises(ConfigError, match=r"its 2 files take 80\d+ bytes, more than the board's 65536-byte flash"):
        BoardFs(firmware_in(fw))

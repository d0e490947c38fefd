"""The trace header's firmware hash covers every file the firmware can import, the entry
included (docs/reliability.md)."""

import pytest

from host.core.errors import ConfigError
from host.rig.targets.firmware import Firmware


def _tree(root, files):
    for rel, text in files.items():
        path = root / rel
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return root


def test_an_entry_file_is_in_the_hash_and_one_outside_the_firmware_folder_is_refused(tmp_path):
    """The entry is on the board's flash like every other file (issue 40): inside the
    firmware folder, hashed; one outside it (``../a/app.py``) is refused by name."""
    board = _tree(tmp_path / "board", {"lib/drv.py": "X = 1\n", "a/app.py": "print('a')\n", "b/app.py": "print('b')\n"})
    first = Firmware(board, [board / "lib"], entry="a/app.py").identity()
    second = Firmware(board, [board / "lib"], entry="b/app.py").identity()
    assert first["sha256"] != second["sha256"], f"two different entry files, one hash: {first} {second}"
    assert first["files"] == 2, first
    _tree(tmp_path / "a", {"app.py": "print('a')\n"})
    with pytest.raises(ConfigError, match=r"an entry '\.\./a/app\.py' that leaves it"):
        Firmware(board, [board, board / "lib"], entry="../a/app.py").identity()


def test_a_packages_init_and_a_data_file_change_the_hash_and_caches_do_not(tmp_path):
    board = _tree(
        tmp_path / "fw",
        {"main.py": "import pkg\n", "pkg/__init__.py": "A = 1\n", "cal.json": "{}", "__pycache__/x.py": "junk\n"},
    )
    firmware = Firmware(board, [board])
    before = firmware.identity()
    (board / "__pycache__" / "x.py").write_text("other junk\n")
    (board / ".hidden.py").write_text("secret\n")
    assert firmware.identity() == before, "a cache or hidden file is not firmware"
    (board / "pkg" / "__init__.py").write_text("A = 2\n")
    after_init = firmware.identity()
    assert after_init["sha256"] != before["sha256"], "a package's __init__.py is importable code"
    (board / "cal.json").write_text('{"k": 1}')
    assert firmware.identity()["sha256"] != after_init["sha256"], "a data file the firmware reads"


def test_the_same_file_on_two_folders_of_the_path_is_told_apart(tmp_path):
    one = _tree(tmp_path / "one", {"main.py": "import m\n", "m.py": "A = 1\n"})
    two = _tree(tmp_path / "two", {"x.py": ""})
    moved = _tree(tmp_path / "moved", {"main.py": "import m\n"})
    moved_lib = _tree(tmp_path / "moved_lib", {"m.py": "A = 1\n", "x.py": ""})
    a = Firmware(one, [one, two]).identity()
    b = Firmware(moved, [moved, moved_lib]).identity()
    assert a["sha256"] != b["sha256"], "which folder a module is found in decides what runs"

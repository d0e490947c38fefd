"""Imports as on a board (docs/shim.md, "Imports as on a board"): a relative import is made
in its importer's package (py/builtinimport.c evaluate_relative_import), and a module the
firmware brings wins over the loop's where the board's sys.path and built-ins let it."""

import pytest

pytestmark = pytest.mark.hil


def test_four_packages_with_a_util_each_import_their_own_at_import_and_call_time(run_case):
    rig, r = run_case("relative_same_names", 0.1)
    mine = ["p1", "p2", "p3", "p4"]
    assert r["utils"] == mine and r["names"] == mine and r["late"] == mine, rig.console
    assert r["nested"] == ("p1", "p1.sub", "p1/leaf", "p1.sub.Y"), rig.console
    assert r["lib"] == ("libpkg", "libpkg"), rig.console
    assert r["cross"] == "p1", f"p1's function called during p3's import took p3's util: {rig.console}"
    assert r["lazy"] == "asyncio", f"asyncio's lazy wait_for came from the firmware's p2.funcs: {rig.console}"
    assert r["main"] == "can't perform relative import", rig.console


def test_a_firmware_file_takes_a_name_from_the_loop_where_the_boards_path_gives_it(run_case):
    """On an ESP32: neopixel.py beside main.py comes before the frozen neopixel; lib/dht.py
    after it ('', '.frozen', '/lib'); esp is a built-in, before any file; rp2 the board has
    not; select is an extensible built-in, after every file."""
    rig, r = run_case("shadow_modules", 0.1)
    want = {"neopixel": "firmware", "dht": "board", "esp": "board", "rp2": "firmware", "select": "firmware"}
    assert r["origins"] == want, rig.console
    assert r["dht"] is True, rig.console


def test_a_firmware_machine_py_in_lib_is_its_machine_and_umachine_the_boards(run_case):
    rig, r = run_case("shadow_machine", 0.1)
    assert r == {"origin": "firmware", "pin": 1, "umachine": "board"}, rig.console

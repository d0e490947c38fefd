"""Imports as on a board (docs/shim.md, "Imports as on a board"): a relative import is made
in its importer's package (py/builtinimport.c evaluate_relative_import), and a module the
firmware brings wins over the loop's where the board's sys.path and built-ins let it."""

import pytest

from host.tests.conftest import FIRMWARE, bench_app, results

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


BOARDS = {
    "esp32_bench": {"esp": "board", "rp2": "firmware"},  # esp: a built-in; rp2: none on an ESP32
    "rpi_pico_bench": {"esp": "firmware", "rp2": "board"},  # rp2: imported by the port's _boot.py
}


@pytest.mark.parametrize("board", BOARDS)
def test_a_firmware_file_takes_a_name_from_the_loop_where_the_boards_path_gives_it(board):
    """neopixel.py beside main.py comes before the frozen neopixel; lib/dht.py after it
    ('', '.frozen', '/lib'); select is an extensible built-in, after every file; esp and rp2
    as the board has them."""
    from host.pytest_plugin import rig_from_keywords

    app = bench_app("shadow", {"body": "bench"}, board=board)
    rig = rig_from_keywords(app, main_dir=FIRMWARE / "shadow_modules", allow_exit=True)
    rig.start()
    try:
        rig.run_for(0.1)
    finally:
        rig.stop()
    r = results(rig.console)
    want = {"neopixel": "firmware", "dht": "board", "select": "firmware", **BOARDS[board]}
    assert r["origins"] == want, rig.console
    assert r["dht"] is True, rig.console


def test_a_firmware_machine_py_in_lib_is_its_machine_and_umachine_the_boards(run_case):
    rig, r = run_case("shadow_machine", 0.1)
    assert r == {"origin": "firmware", "pin": 1, "umachine": "board"}, rig.console

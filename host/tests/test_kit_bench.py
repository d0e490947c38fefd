"""The robot kits' case of ``make bench`` (``python -m host.bench --only-kits``,
docs/bench.md): each kit's demo folder is its rig with the button pressed and its firmware
beside it, a demo runs until its last line, and the report puts its real-time factor beside
issue 44's target of 20x and its floors: the link's exchanges at the raw round trip, and with
the interpreter's own CPU."""

import pytest

from host import bench


@pytest.mark.parametrize(("kit", "parts", "button", "driver", "last"), bench.KIT_DEMOS)
def test_each_kits_demo_folder_is_its_rig_with_the_button_pressed_and_its_firmware(
    tmp_path, kit, parts, button, driver, last
):
    if driver:
        try:
            bench.driver_folder(driver)
        except bench.DriverMissing as e:
            pytest.skip(str(e))
    rig_file = bench.kit_demo_folder(tmp_path, kit, parts, button, driver)
    text = rig_file.read_text()
    if button:  # (a kit without one: its demo starts by itself)
        assert f'name = "{button}"\npresses = [[0.2, 0.3]]\n' in text, f"{kit}: the button not pressed in {rig_file}"
    else:
        assert "presses = [[0.2, 0.3]]" not in text, f"{kit}: no button to press, yet one pressed in {rig_file}"
    main = (tmp_path / "main.py").read_text()
    assert f'print("{last}"' in main, f"{kit}: expected the demo to print {last!r} last; main.py:\n{main}"


def test_a_kits_demo_runs_until_its_last_line_and_is_reported_beside_the_floor(capsys):
    kit, *demo = next(d for d in bench.KIT_DEMOS if d[0] == "cytron_maker_pi_rp2040")
    run = bench.run_kit_demo(kit, *demo)
    assert run["ended"] and 1.0 < run["sim_s"] < 2.0, f"expected range_after at about 1.2 simulated s, got {run}"
    bench.report_kits([(kit, run), ("other", {"missing": "expected the driver x unpacked"})], raw_us=100.0)
    out = capsys.readouterr().out
    assert f"  {kit}: {run['sim_s']:.2f} simulated s in " in out and "(target 20x" in out, out
    link, host_free = bench.kit_floor(run, 100.0)
    per_s = run["exchanges"] / run["sim_s"]
    assert link == pytest.approx(1e6 / (per_s * 100.0)), (link, per_s)
    assert host_free <= link, f"expected the interpreter's CPU to lower the floor: {host_free}, {link}; {run}"
    assert f"floor: {link:.0f}x real time" in out and f"= 1 s / ({per_s:.0f} exchanges x raw 100 us)" in out, out
    assert "  other: not run: expected the driver x unpacked" in out, out

"""Bus reads the shim answers from the host's image (``host/rig/busimage.py``) read exactly
what they read when every transfer is its own exchange (without ``MPY_FIL_BUS_IMAGES=1``): each
bus test below is run both ways and every rig it makes must give the same bus readings
(every BUS record of ``trace.jsonl``: instant, bytes written, bytes read, outcome, register,
duration), the same console (notes included) and the same ground truth at its end, and the
image path must have answered some reads itself where the firmware polls (so the
comparison compares something). The slow ones, and the bench's bus-heavy robot, are
compared the same way by hil_tests/test_bus_image_slow.py."""

import importlib
import json

import pytest

from host.bench import run_imu_bot
from host.pytest_plugin import rig_from_keywords
from host.rig.busimage import ENV
from host.tests.conftest import FIRMWARE  # noqa: F401  (the bus tests' firmware folder)

BUS_TESTS = {  # module: (test, polls answered in the shim expected): the bus tests that read chips
    "test_buses": (
        ("test_a_register_read_takes_its_clocks_at_the_bus_frequency", False),
        ("test_spi_api_with_a_chip_select_pin_and_8_clocks_a_byte", False),
        ("test_published_lsm6dsox_driver_integrates_a_turn_in_place_within_3_degrees", True),
    ),
    "test_bus_drivers": (
        ("test_published_lis3mdl_driver_compass_follows_the_heading_after_a_hard_iron_calibration", False),
        ("test_published_qmc5883l_driver_compass_reads_the_heading_within_a_degree_twice_in_a_turn", True),
        ("test_hmc5883l_compass_read_as_its_public_drivers_read_it_gives_the_heading_within_a_degree", False),
        ("test_published_mpu6886_driver_integrates_a_turn_in_place_within_3_degrees", False),
    ),
    "test_bme280_humidity": (("test_a_bmp280_has_no_humidity", False),),
    "test_oled": (("test_published_ssd1306_driver_shows_the_text_framebuf_draws_on_i2c_and_spi", False),),
    "test_spi_clock_pins": (("test_a_transfer_reaches_the_chips_whose_clock_pin_is_the_spis_at_that_instant", False),),
}
SLOW_BUS_TESTS = {  # the same, minutes of polling between them: hil_tests/test_bus_image_slow.py (make hil)
    "test_chip_polls": (
        ("test_reset_bits_clear_after_the_datasheet_time_and_a_poll_that_never_ends_is_named_once", True),
    ),
    "test_bus_drivers": (
        ("test_vl53l0x_ranges_the_wall_along_its_ray_once_per_budget_and_the_robot_stops_at_it", True),
    ),
    "test_vl53l1x": (("test_a_vl53l1x_driver_ranges_the_wall_once_per_budget_and_the_robot_stops_at_it", False),),
}


def cases(tests: dict) -> list:
    return [(module, name, polls) for module, tests_ in tests.items() for name, polls in tests_]


CASES = cases(BUS_TESTS)


def bus_records(rig) -> list[str]:
    text = (rig.artefacts / "trace.jsonl").read_text()
    return [line for line in text.splitlines() if '"msg":"BUS"' in line]


def run_both(tmp_path, monkeypatch, call) -> list[tuple]:
    """``call(make_rig, tmp)`` with every transfer an exchange, then with images: per rig
    made, (bus records, console, truth, reads answered in the shim) each way."""
    out = {}
    for way, images in (("exchange", "0"), ("image", "1")):
        monkeypatch.setenv(ENV, images)
        rigs = []

        def make_rig(app="rover", _rigs=rigs, _folder=tmp_path / way, **kwargs):
            kwargs.setdefault("artefacts", _folder / f"rig{len(_rigs)}")
            kwargs["trace"] = True
            rig = rig_from_keywords(app, **kwargs)
            _rigs.append(rig)
            rig.start()
            return rig

        try:
            call(make_rig, tmp_path / way / "tmp")
        finally:
            for rig in rigs:
                rig.stop()
        out[way] = [(bus_records(r), r.console, r.plant.truth(), r.stats.bus_local) for r in rigs]
    return list(zip(out["exchange"], out["image"], strict=True))


def same(pairs, where: str, tmp_path) -> int:
    local = 0
    for i, (exchange, image) in enumerate(pairs):
        for name, a, b in zip(("bus records", "console", "truth"), exchange[:3], image[:3], strict=True):
            if a != b:
                where_first = ""
                if name == "bus records":
                    first = next((k for k, (x, y) in enumerate(zip(a, b)) if x != y), min(len(a), len(b)))
                    shown = [json.loads(r[first]) if first < len(r) else None for r in (a, b)]
                    where_first = f"first difference at record {first}: {shown}; "
                raise AssertionError(
                    f"{where} rig{i}: expected the same {name} with images as with an exchange a transfer; "
                    f"{where_first}artefacts in {tmp_path}"
                )
        assert exchange[3] == 0, f"{where} rig{i}: expected no read answered in the shim with {ENV}=0"
        local += image[3]
    return local


@pytest.mark.parametrize(("module", "name", "polls"), CASES, ids=[c[1][5:45] for c in CASES])
def test_a_bus_test_reads_the_same_bytes_with_images(tmp_path, monkeypatch, module, name, polls):
    compare(tmp_path, monkeypatch, module, name, polls)


def compare(tmp_path, monkeypatch, module: str, name: str, polls: bool) -> None:
    """The bus test ``module::name`` both ways, the same bus readings, console and truth."""
    test = getattr(importlib.import_module(f"host.tests.{module}"), name)

    def call(make_rig, tmp):
        tmp.mkdir(parents=True, exist_ok=True)
        args = {"make_rig": make_rig, "tmp_path": tmp}
        params = test.__code__.co_varnames[: test.__code__.co_argcount]
        test(**{p: args[p] for p in params})

    local = same(run_both(tmp_path, monkeypatch, call), f"{module}::{name}", tmp_path)
    if polls:
        assert local > 0, f"{module}::{name}: expected some polls answered in the shim, got none"


def bench_robot_both_ways(tmp_path, monkeypatch) -> None:
    """The bench's bus-heavy robot both ways: the same bus readings and summary, fewer exchanges."""
    runs = {}
    for way, images in (("exchange", "0"), ("image", "1")):
        monkeypatch.setenv(ENV, images)
        runs[way] = run_imu_bot(1000, record=True, trace=True, artefacts=tmp_path / way)
        text = (tmp_path / way / "trace.jsonl").read_text()
        runs[way]["bus"] = [line for line in text.splitlines() if '"msg":"BUS"' in line]
    a, b = runs["exchange"], runs["image"]
    assert a["bus"] == b["bus"], f"expected the same bus readings both ways; artefacts in {tmp_path}"
    assert a["printed"] == b["printed"], f"expected the same summary: {a['printed']} against {b['printed']}"
    assert b["bus_exchanges"] < a["bus_exchanges"] * 0.7, (
        f"expected the status polls answered in the shim: {b['bus_exchanges']} BUS exchanges against "
        f"{a['bus_exchanges']} transfers"
    )

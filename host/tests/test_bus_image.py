"""Bus reads the shim answers from the host's image (``host/rig/hardware/busimage.py``) read exactly
what they read when every transfer is its own exchange (``MPY_FIL_BUS_IMAGES=0``): each
bus test below is run both ways and every rig it makes must give the same bus readings
(every BUS record of ``trace.jsonl``: instant, bytes written, bytes read, outcome, register,
duration), the same console (notes included) and the same ground truth at its end, and the
image path must have answered some reads itself where the firmware polls or reads an
IMU's or a compass's samples as they come (its stream: so the comparison compares
something). The slow ones, and the bench's bus-heavy robot, are
compared the same way by hil_tests/test_bus_image_slow.py. Together they hold every chip of
the catalogue that firmware reads on a bus (``CHIPS``: ``test_every_bus_chip_is_compared``)."""

import importlib
import json

import pytest

from host.bench import KIT_DEMOS, run_imu_bot, run_kit_demo
from host.pytest_plugin import rig_from_keywords
from host.rig.hardware.busimage import ENV
from host.tests.conftest import FIRMWARE  # noqa: F401  (the bus tests' firmware folder)

# module: (test, reads answered in the shim expected (polls, an IMU's or a compass's samples
# read as a stream)[, its parameters]): the bus tests that read chips
BUS_TESTS = {
    "test_buses": (
        ("test_a_register_read_takes_its_clocks_at_the_bus_frequency", False),
        ("test_spi_api_with_a_chip_select_pin_and_8_clocks_a_byte", False),
        ("test_published_lsm6dsox_driver_integrates_a_turn_in_place_within_3_degrees", True),
    ),
    "test_bus_drivers": (
        ("test_published_lis3mdl_driver_compass_follows_the_heading_after_a_hard_iron_calibration", True),
        ("test_published_qmc5883l_driver_compass_reads_the_heading_within_a_degree_twice_in_a_turn", True),
        ("test_hmc5883l_compass_read_as_its_public_drivers_read_it_gives_the_heading_within_a_degree", True),
        ("test_published_mpu6886_driver_integrates_a_turn_in_place_within_3_degrees", True),
        ("test_published_pca9685_driver_turns_a_servo_on_channel_0_to_its_angle", False),
        ("test_published_lsm6dsox_driver_at_0x6b_turns_an_lsm6dso_part_90_degrees_within_3", True),
        (
            "test_published_bme280_driver_reads_a_set_temperature_and_pressure_through_the_calibration",
            False,
            {"chip": "bme280", "address": 0x76},
        ),
    ),
    "test_bme280_humidity": (
        ("test_a_bmp280_has_no_humidity", False),
        ("test_published_driver_reads_the_set_humidity_through_the_humidity_trimming", False, {"humidity_pct": 67.8}),
    ),
    "test_oled": (("test_published_ssd1306_driver_shows_the_text_framebuf_draws_on_i2c_and_spi", False),),
    "test_sh1106": (("test_an_sh1106_driver_at_column_offset_two_shows_what_framebuf_draws_on_i2c_and_spi", False),),
    "test_spi_clock_pins": (("test_a_transfer_reaches_the_chips_whose_clock_pin_is_the_spis_at_that_instant", False),),
    "test_apa102": (("test_a_dotstar_driver_sets_colours_and_brightness_the_strip_shows_over_time", False),),
    "test_wokwi_more_parts": (
        ("test_an_esp32_lcd1602_buzzer_and_ky040", False),
        ("test_a_pico_lcd2004_at_0x3f_its_four_rows_beeps_and_a_polled_knob", False),
        ("test_a_pico_dht11_read_by_the_dht_module_takes_the_protocols_time", False),
    ),
    "test_onewire": (
        ("test_a_public_ds18b20_example_reads_the_parts_temperature", False, {"board": "rpi_pico", "pin": 22}),
    ),
    "test_bus_image": (("ina219_read_while_the_motors_run", False),),  # (it reads the plant: never imaged)
    "test_ht16k33": (("test_an_ht16k33_matrix_shows_each_icon_upright_and_its_ram_reads_back", False),),
    "test_st7789": (("test_a_square_panel_upside_down_shows_what_st7789py_s_offsets_of_80_draw", False),),
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


CHIPS = {  # every catalogue part firmware reads on a bus -> where it is compared
    "lsm6dsox": "test_buses",
    "lsm6dso": "test_bus_drivers",
    "mpu6050": "test_buses",
    "mpu6886": "test_bus_drivers",  # (the mpu6050 part's chip option)
    "lis3mdl": "test_bus_drivers",
    "qmc5883l": "test_bus_drivers",
    "hmc5883l": "test_bus_drivers",
    "pca9685": "test_bus_drivers",
    "bmp280": "test_bme280_humidity",
    "bme280": "test_bus_drivers",  # (the bmp280 part's chip option)
    "ssd1306": "test_oled",
    "sh1106": "test_sh1106",
    "char_lcd": "test_wokwi_more_parts",
    "apa102_strip": "test_apa102",
    "dht": "test_wokwi_more_parts",
    "ds18b20": "test_onewire",
    "ina219": "test_bus_image",
    "ht16k33": "test_ht16k33",
    "st7789": "test_st7789",
    "vl53l0x": "test_bus_drivers (slow) and the bench robot",
    "vl53l1x": "test_vl53l1x (slow)",
}


def cases(tests: dict) -> list:
    return [
        (module, case[0], case[1], case[2] if len(case) > 2 else {})
        for module, tests_ in tests.items()
        for case in tests_
    ]


def case_id(case) -> str:
    module, name, _polls, params = case
    return name.removeprefix("test_")[:40] + "".join(f"-{v}" for v in params.values())


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


@pytest.mark.parametrize(("module", "name", "polls", "params"), CASES, ids=[case_id(c) for c in CASES])
def test_a_bus_test_reads_the_same_bytes_with_images(tmp_path, monkeypatch, module, name, polls, params):
    compare(tmp_path, monkeypatch, module, name, polls, params)


def test_every_bus_chip_is_compared():
    """Every part of the catalogue that sits on a bus (its engine a bus device) is in ``CHIPS``,
    and each module named there is compared."""
    from sim_plant.catalogue import parts

    on_bus = {kind for kind, part in parts().items() if getattr(part, "on_bus", False)}
    assert on_bus - set(CHIPS) == set(), (
        f"expected every bus part compared both ways, these are not: {on_bus - set(CHIPS)}"
    )
    modules = {m for m, _n, _p, _q in CASES + cases(SLOW_BUS_TESTS)}
    for kind, where in CHIPS.items():
        assert where.split(" ")[0] in modules, f"{kind}: expected {where} among the compared modules {sorted(modules)}"


def compare(tmp_path, monkeypatch, module: str, name: str, polls: bool, params=None) -> None:
    """The bus test ``module::name`` both ways, the same bus readings, console and truth."""
    test = getattr(importlib.import_module(f"host.tests.{module}"), name)

    def call(make_rig, tmp):
        tmp.mkdir(parents=True, exist_ok=True)
        args = {"make_rig": make_rig, "tmp_path": tmp, **(params or {})}
        names = test.__code__.co_varnames[: test.__code__.co_argcount]
        test(**{p: args[p] for p in names})

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
    assert b["bus_exchanges"] < a["bus_exchanges"] * 0.25, (
        f"expected the status polls and the samples answered in the shim: {b['bus_exchanges']} BUS exchanges "
        f"against {a['bus_exchanges']} transfers"
    )


def imu_chip(noise_dps: float = 0.05):
    """An LSM6DSOX on its own at 208 Hz (gyro and accelerometer), the plant's generator its own."""
    import numpy as np

    from sim_plant.buses import BusSet
    from sim_plant.catalogue.lsm6dsox import Lsm6dsoxChip

    rng = np.random.default_rng(7)
    chip = Lsm6dsoxChip(
        "imu", "i2c0", 0x6A, (0, 0, 0), gyro_bias_dps=(0.5, 0, -1), gyro_noise_dps=noise_dps,
        accel_noise_m_s2=0.02, rng=rng,
    )  # fmt: skip
    chip.power_on()
    bus = BusSet([chip])
    for reg in (0x10, 0x11):  # CTRL1_XL, CTRL2_G: 208 Hz
        bus.transfer(0, "i2c0", 0, 0x6A, 0, bytes((reg, 0x50)))
    return chip, bus, rng


STATUS, SAMPLE = (0x6A, b"\x1e", 1), (0x6A, b"\x22", 12)


def answer(entries: list, t_us: int, shape: tuple, counts: dict):
    """What the shim answers for ``shape`` at ``t_us`` from ``stream``'s entries, its count
    moved on (None: the host's)."""
    for read, a, b, need, then, got, _how in entries:
        if read == shape and a <= t_us < b and counts["n"] == need:
            counts["n"] = then
            return got
    return None


@pytest.mark.parametrize("skip", [None, 2])
def test_a_stream_answers_each_sample_at_its_tick_as_the_chip_reads_it_and_nothing_out_of_its_order(skip):
    """``busimage.stream``: an IMU's samples over its next ticks, its data-ready bits before
    and after each read, played on copies; the chip and the plant's generator are left as
    they were; a firmware polling and reading every tick gets each answer as the chip then
    reads it (the same bytes, the same samples drawn in the same order); one that lets a
    tick pass (``skip``) is answered nothing after it (the sample it reads next is drawn
    from where the generator is then: the host's)."""
    from host.rig.hardware.busimage import stream

    chip, bus, rng = imu_chip()
    period = chip.period_us()
    t0 = 3 * period + 100
    bus.transfer(t0 - 50, "i2c0", 0, 0x6A, 12, b"\x22")  # (the sample of this tick read already)
    state, rng_state = dict(chip.__dict__), rng.bit_generator.state
    horizon = t0 + 5 * period + 7
    entries = stream(chip, (STATUS, SAMPLE), t0, horizon, rng, True)
    assert chip.__dict__ == state and rng.bit_generator.state == rng_state, "expected the chip and generator untouched"
    counts, answered, hosts = {"n": 0}, 0, 0
    for k in range(6):
        if k == skip:
            continue
        t = t0 + k * period + 300
        for shape in (STATUS, SAMPLE, STATUS):
            if t >= horizon:
                break
            got = answer(entries, t, shape, counts)
            status, _count, real = bus.transfer(t, "i2c0", 0, *shape[:1], shape[2], shape[1])
            if got is None:
                hosts += 1
                continue
            answered += 1
            assert got == real, f"tick {k}, read {shape[1].hex()} at {t} us: expected {real.hex()}, imaged {got.hex()}"
    if skip is None:
        assert hosts == 0 and answered == 15, f"expected every read answered, {hosts} were not ({answered} were)"
    else:
        assert answered == 3 * skip and hosts > 0, (
            f"expected the reads before the tick let pass answered ({3 * skip}), none after: {answered}, {hosts}"
        )


INA219_MAIN = """
import time
from machine import I2C, PWM, Pin
i2c = I2C(0, freq=400_000)
buf = bytearray(2)
i2c.writeto_mem(0x40, 0x05, b"\\x10\\x00")  # calibration: 100 uA a count
pwm = PWM(Pin(25), freq=20000, duty_u16=0)
Pin(26, Pin.OUT, value=1)
total = 0
for i in range(120):
    if i == 40:
        pwm.duty_u16(40000)
    i2c.readfrom_mem_into(0x40, 0x02, buf)  # bus voltage
    i2c.readfrom_mem_into(0x40, 0x04, buf)  # current
    total += buf[0] << 8 | buf[1]
    time.sleep_ms(2)
print("R total", total)
"""


def ina219_read_while_the_motors_run(make_rig, tmp_path):
    """An INA219 polled for its bus voltage and current (twice a 2 ms step) while a motor
    starts: what the comparison runs for the INA219 (no bus test reads one)."""
    from host.tests.conftest import bench_app, results

    (tmp_path / "main.py").write_text(INA219_MAIN)
    plant = {
        "body": "differential",
        "parts": [
            {"kind": "dc_motor", "name": "motor_l", "bridge": "drv8833", "drives": "left", "time_constant_ms": 20},
            {"kind": "dc_motor", "name": "motor_r", "bridge": "drv8833", "drives": "right", "time_constant_ms": 20},
            {"kind": "battery", "name": "batt", "full_v": 7.4},
            {"kind": "ina219", "name": "power", "bus": "i2c0", "battery": "batt"},
        ],
    }
    app = bench_app(
        "ina219_polled", plant, wiring={"IN1": "motor_l.in1", "IN2": "motor_l.in2"}, pins={"IN1": 25, "IN2": 26}
    )
    rig = make_rig(app, main_dir=tmp_path, allow_exit=True)
    rig.run_for(0.4)
    assert "total" in results(rig.console), rig.console


def kit_demo_both_ways(tmp_path, monkeypatch, kit: str) -> None:
    """A kit's bench demo (host/bench.py, ``KIT_DEMOS``: the kits' firmware in its vendors'
    style) both ways: the same bus readings and console, and the gyro's sample reads answered
    in the shim (its stream)."""
    demo = next(d for k, *d in KIT_DEMOS if k == kit)
    runs = {}
    for way, images in (("exchange", "0"), ("image", "1")):
        monkeypatch.setenv(ENV, images)
        runs[way] = run_kit_demo(kit, *demo, trace=True, artefacts=tmp_path / way)
        text = (tmp_path / way / "trace.jsonl").read_text()
        runs[way]["bus"] = [line for line in text.splitlines() if '"msg":"BUS"' in line]
    a, b = runs["exchange"], runs["image"]
    assert a["ended"] and a["bus"], f"expected the demo to end and read its bus; console:\n{a['console'][-2000:]}"
    assert a["bus"] == b["bus"], f"{kit}: expected the same bus readings both ways; artefacts in {tmp_path}"
    assert a["console"] == b["console"], f"{kit}: expected the same console both ways; artefacts in {tmp_path}"
    assert a["bus_local"] == 0, f"{kit}: expected no read answered in the shim with {ENV}=0"
    assert b["bus_local"] > 0, f"{kit}: expected the gyro's reads answered in the shim, none were"


def test_a_sample_read_answered_in_the_shim_installs_its_trial_only_on_the_chip_its_window_found():
    """BUS_DONE of a stream's sample read (``busimage._install``): on the chip and the
    generator as its window found them, the chip becomes what the read made of the trial's
    copy and the generator moves on as the read drew (the same as playing the read on the
    chip: its bytes, its state, the next draw); on a chip changed since (a motion change
    the window did not see), nothing is installed and the host plays the read itself."""
    from host.rig.hardware.busimage import _install, play

    chip, bus, rng = imu_chip()
    period = chip.period_us()
    t0 = 3 * period + 100
    windows = play(chip, rng.bit_generator.state, 0, t0, t0 + 3 * period, (STATUS, SAMPLE), rng, 3)
    w = windows[0]
    assert w.a == t0 and w.change is not None, f"expected the tick's sample read to change the chip: {w.change}"
    bus.transfer(t0 + 10, "i2c0", 0, 0x6A, 1, b"\x1e")  # (the status poll: its pointer only)
    twin, twin_bus, twin_rng = imu_chip()
    twin_bus.transfer(t0 + 10, "i2c0", 0, 0x6A, 1, b"\x1e")
    status, _count, played = twin_bus.transfer(t0 + 20, "i2c0", 0, 0x6A, 12, b"\x22")
    assert status == 0 and played == w.change[1], f"expected the sample {w.change[1].hex()}, got {played.hex()}"
    assert _install(chip, w, rng), "expected the sample installed on the chip its window found"
    differ = sorted(k for k, v in chip.__dict__.items() if k != "rng" and twin.__dict__.get(k) != v)
    assert not differ and chip.__dict__.keys() == twin.__dict__.keys(), (
        f"expected the chip as the read played on it leaves it; differ: {differ}"
    )
    assert rng.standard_normal() == twin_rng.standard_normal(), "expected the generator moved on as the read drew"
    moved, moved_bus, moved_rng = imu_chip()
    moved_bus.transfer(t0 + 10, "i2c0", 0, 0x6A, 1, b"\x1e")
    moved.history.append((t0 + 15, 0.2, 0.5))  # (a motion change the window did not see)
    before = dict(moved.__dict__, history=list(moved.history), regs=list(moved.regs))
    assert not _install(moved, w, moved_rng), "expected nothing installed on a chip changed since its window"
    assert moved.__dict__ == before, "expected the changed chip untouched"

"""Bus transactions in the trace (docs/traces.md, docs/budgets.md): each transfer a
BUS record in trace.jsonl with its bus, register and duration, a decoded string signal
in signals.csv and the VCD, and the two bus budget kinds measured from them."""

import json

import pytest

from host.link import frames as F
from host.rig.config.budgets import BusLatencyBudget, BusSampleBudget
from host.rig.hardware.bustrace import describe, duration_us, transaction
from host.tests.conftest import FIRMWARE, results
from host.tests.test_buses import bench

pytestmark = pytest.mark.hil


def test_a_register_read_lasts_its_clocks_and_reads_as_text():
    """readfrom_mem(0x6a, 0x22, 6) at 400 kHz: start, address+W, register, restart,
    address+R, 6 bytes, stop = 9 x 9 + 3 = 84 clocks = 210 us."""
    tx = transaction(0, "i2c0", 400_000, F.BUS_XFER, 0x6A, 6, b"\x22", F.BUS_OK, 1, bytes(range(6)))
    assert tx.duration_us == 210 and tx.register == 0x22 and tx.reads
    assert describe(tx) == "0x6a reg 0x22 read 00 01 02 03 04 05 (210 us)"
    nack = transaction(0, "i2c0", 400_000, F.BUS_XFER, 0x50, 1, b"", F.BUS_NACK_ADDRESS, 0, b"")
    assert describe(nack) == "0x50 NACK (28 us)"
    spi = transaction(0, "spi1", 1_000_000, F.BUS_SPI_XFER, 0, 0, b"\x8f\x00", F.BUS_OK, 2, b"\x00\x6c")
    assert (spi.address, spi.register, spi.duration_us) == (None, 0x0F, 16)
    assert describe(spi) == "spi reg 0x0f read 6c (16 us)"
    assert duration_us(F.BUS_XFER, 400_000, F.BUS_STUCK, 0, 1, 0) is None


def test_transactions_are_in_the_trace_the_vcd_and_the_bus_budgets(make_rig, tmp_path):
    latency = BusLatencyBudget("gyro_read", "i2c0", limit_us=200, address=0x6A)
    period = BusSampleBudget("gyro_period", "i2c0", address=0x6A, register=0x22, period_us=20_000, tolerance_us=500)
    ready = BusSampleBudget("gyro_ready", "i2c0", address=0x6A, register=0x22, ready="imu.int", limit_us=300)
    app = bench()
    app.make_budgets = lambda plant: [latency, period, ready]
    rig = make_rig(
        app, main_dir=FIRMWARE / "bus_sampling", allow_exit=True, artefacts=tmp_path, record=True, trace=True
    )
    rig.run_for(1.5)
    rig.stop()
    assert results(rig.console)["done"] == 1, rig.console
    records = [json.loads(line) for line in (tmp_path / "trace.jsonl").read_text().splitlines()]
    reads = [r for r in records if r.get("msg") == "BUS" and r.get("register") == 0x22]
    assert len(reads) == 50 and {(r["bus"], r["address"], r["duration_us"]) for r in reads} == {("i2c0", 0x6A, 210)}
    signals = (tmp_path / "signals.csv").read_text()
    assert signals.count(",bus:i2c0,0x6a reg 0x22 read ") == 50
    vcd = (tmp_path / "trace.vcd").read_text()
    assert "$scope module buses $end" in vcd and "$var string 1" in vcd
    assert "0x6a\\x20reg\\x200x22\\x20read" in vcd
    # the two register writes take 73 us, the 50 reads 210: over the 200 us limit
    assert latency.count == 52 and latency.misses == 50 and latency.histogram == {73: 2, 210: 50}
    # 30 reads 20 ms apart (the read's own 210 us on top of the sleep), then 20 at the 208 Hz data-ready
    assert period.count == 49 and period.histogram[20_210] == 29 and period.misses == 20, period.stats()
    # from each rise of INT1 (once the firmware enables it) to the read: its 100 us polling at most
    assert ready.count == 20 and ready.misses == 0 and ready.stats()["max"] <= 300, ready.stats()


RIG = """
name = "bus_budgets"
[firmware]
entry = "main.py"
[board.pins]
IMU_INT = 34
[plant]
body = "bench"
[[plant.parts]]
kind = "lsm6dsox"
name = "imu"
bus = "i2c0"
[wiring]
IMU_INT = "imu.int"
[budgets.gyro_read]
kind = "bus_latency"
source = "i2c0"
address = 0x6a
limit_us = 250
[budgets.gyro_period]
kind = "bus_sample"
source = "i2c0"
register = 0x22
period_us = 20000
tolerance_us = 500
[budgets.gyro_ready]
kind = "bus_sample"
source = "i2c0"
register = 0x22
ready = "imu.int"
limit_us = 300
"""


def _load(tmp_path, text: str):
    from host.rig.config.rigfile import load_rig

    (tmp_path / "main.py").write_text("")
    (tmp_path / "rig.toml").write_text(text)
    app = load_rig(tmp_path / "rig.toml")
    return app.make_budgets(app.make_plant())


def test_a_rig_file_declares_the_bus_budget_kinds(tmp_path):
    budgets = {b.name: b for b in _load(tmp_path, RIG)}
    assert isinstance(budgets["gyro_read"], BusLatencyBudget) and budgets["gyro_read"].address == 0x6A
    assert budgets["gyro_period"].limit_text() == "20000 +- 500 us"
    assert budgets["gyro_ready"].limit_text() == "<= 300 us from imu.int"


@pytest.mark.parametrize(
    "old, new, message",
    [
        (
            'source = "i2c0"\naddress',
            'source = "i2c1"\naddress',
            "no device of the plant is on bus 'i2c1' (buses: i2c0)",
        ),
        ("period_us = 20000\n", "", "missing period_us"),
        ('ready = "imu.int"\nlimit_us = 300', 'ready = "imu.int"', "missing limit_us"),
        ('ready = "imu.int"', 'ready = "imu.nope"', "the plant has no signal 'imu.nope'"),
    ],
)
def test_a_bus_budget_on_a_bus_no_device_is_on_or_missing_its_figures_is_refused(tmp_path, old, new, message):
    from host.core.errors import ConfigError

    with pytest.raises(ConfigError, match=message.replace("(", r"\(").replace(")", r"\)")):
        _load(tmp_path, RIG.replace(old, new, 1))

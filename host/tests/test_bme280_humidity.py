"""The bmp280 part's BME280 humidity (Bosch BME280 datasheet, 4.2.3 and 5.4) read by the
published driver micropython-bme280 2.1.3 (host/core/drivers.txt), unchanged: the
trimming registers dig_H1..dig_H6 as it unpacks them, the raw reading the datasheet's
32-bit compensation turns into the set humidity, ctrl_hum taken at a write of ctrl_meas."""

import pytest

from host.core.drivers import driver_folder
from host.tests.conftest import FIRMWARE, bench_app, results
from sim_plant.catalogue.bmp280 import TRIM_H, humidity_q22_10, raw_readings, t_fine

pytestmark = pytest.mark.hil


def run(make_rig, chip: str, humidity_pct: float):
    baro = {"kind": "bmp280", "name": "baro", "bus": "i2c0", "chip": chip}
    plant = {"body": "bench", "parts": [{**baro, "temperature_c": 21.37, "humidity_pct": humidity_pct}]}
    app = bench_app("bme280_humidity", plant, lib_dirs=(driver_folder("micropython-bme280"),))
    rig = make_rig(app, main_dir=FIRMWARE / "bme280_humidity", allow_exit=True)
    rig.run_for(0.5)
    rig.stop()
    return rig, results(rig.console)


@pytest.mark.parametrize("humidity_pct", [12.3, 67.8])
def test_published_driver_reads_the_set_humidity_through_the_humidity_trimming(make_rig, humidity_pct):
    rig, r = run(make_rig, "bme280", humidity_pct)
    assert "measured" in r, f"the firmware did not finish; console:\n{rig.console}"
    assert r["dig_h"] == list(TRIM_H), "dig_H4/dig_H5 share 0xE5 (datasheet table 16): the driver's unpacking"
    adc_t, _adc_p, adc_h = r["raw"]
    assert (adc_t, adc_h) == tuple(raw_readings(21.37, 101_325.0, humidity_pct)[::2])
    # the datasheet's compensation, with the datasheet's t_fine: the set humidity, as near as a
    # raw reading gets (the compensation's steps here: 0.012 %RH every second raw count)
    fine = t_fine(adc_t)
    assert humidity_q22_10(adc_h, fine) / 1024 == pytest.approx(humidity_pct, abs=0.006)
    off = [abs(humidity_q22_10(raw, fine) / 1024 - humidity_pct) for raw in range(adc_h - 8, adc_h + 9)]
    assert off[8] == min(off), off
    # the driver's t_fine is its own (dig_T2 >> 11: 1.51 degrees low, test_bus_drivers.py), and
    # humidity depends on it: what it prints is the same formula on its t_fine
    driver_fine = (((adc_t >> 3) - (27504 << 1)) * (26435 >> 11)) + (
        ((((adc_t >> 4) - 27504) * ((adc_t >> 4) - 27504)) >> 12) * -1000 >> 14
    )
    assert r["humidity_q10"] == humidity_q22_10(adc_h, driver_fine), rig.console
    assert r["humidity_q10"] / 1024 == pytest.approx(humidity_pct, abs=1.5), "a 1.5 degree error moves %RH a little"
    assert r["values"][2] == "%d.%02d%%" % (r["humidity_q10"] // 1024, r["humidity_q10"] % 1024 * 100 // 1024)
    assert r["skipped"] == [0x80, 0x00], "osrs_h 0 at the ctrl_meas write: the output reads 0x8000 (skipped)"
    assert r["after_sleep"] == [0x80, 0x00], "a ctrl_meas write in sleep mode starts no conversion"
    assert r["measured"] == [adc_h >> 8, adc_h & 0xFF], "osrs_h 1 taken at the write that starts one"


def test_a_bmp280_has_no_humidity(make_rig):
    rig, r = run(make_rig, "bmp280", 50.0)
    assert "measured" in r, rig.console
    assert r["dig_h"] == [0, 0, 0, 0, 0, 0], "no humidity trimming on a BMP280"
    assert r["raw"][2] == 0x8000 and r["measured"] == [0x80, 0x00]

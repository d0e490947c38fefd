"""Published MicroPython drivers for the bus parts (host/core/drivers.txt, fetched pinned
by make setup into build/drivers/), each run unchanged through a firmware written as its
README or examples show, asserting the physics: a servo on a PCA9685 reaches its angle,
the LIS3MDL compass follows the heading, the MPU-6886's integrated gyro reads a turn, the
LSM6DSO at 0x6B, the QMC5883L compass, the BME280/BMP280 barometer; and the vl53l0x and
hmc5883l parts read as their drivers read them (no MicroPython driver of either is on PyPI)."""

import math

import pytest

from host.core.drivers import driver_folder
from host.tests.conftest import FIRMWARE, bench_app, results
from host.tests.test_buses import SPIN_PINS, SPIN_WIRING, TURN

pytestmark = pytest.mark.hil


def run_driver(make_rig, case: str, plant: dict, driver: str, duration_s: float, probe=None, **app):
    """Run firmware ``case`` with ``driver``'s folder on its path (and the bench robot's
    TB6612, which the spin and compass firmwares import); ``probe(rig)`` (if
    given) is called at each second of virtual time; returns (rig, results, probes)."""
    the_app = bench_app(case, plant, lib_dirs=(driver_folder(driver), TURN), **app)
    rig = make_rig(the_app, main_dir=FIRMWARE / case, allow_exit=True)
    probes = []
    for _ in range(int(duration_s)):
        rig.run_for(1.0)
        if probe is not None:
            probes.append(probe(rig))
    rig.stop()
    return rig, results(rig.console), probes


PAN = {
    "body": "bench",
    "parts": [
        {"kind": "servo", "name": "pan", "min_pulse_us": 750, "max_pulse_us": 2250, "range_deg": 180},
        {"kind": "pca9685", "name": "pwm", "bus": "i2c0", "drives": ["pan.pwm"]},
    ],
}


def test_published_pca9685_driver_turns_a_servo_on_channel_0_to_its_angle(make_rig):
    """micropython-pca9685 0.1.0's Servo helper (750 to 2250 us for 180 degrees) on a servo
    of that span: 90 then 30 degrees. The driver sets PRE_SCALE to 25 MHz / 4096 / 50 Hz
    = 122 where the datasheet's formula wants 121 (its frequency is 49.6 Hz, not 50), so
    its pulses are 0.8 % long: the horn is within 1.5 degrees."""
    rig, r, angles = run_driver(
        make_rig, "pca9685_servo", PAN, "micropython-pca9685", 3.0, lambda rig: rig.plant.truth()["pan_angle_deg"]
    )
    assert "angle" in r, rig.console
    assert r["frequency"] == pytest.approx(25e6 / 4096 / 122)
    assert angles[0] == pytest.approx(90, abs=1.5), angles
    assert angles[-1] == pytest.approx(30, abs=1.5), angles
    assert rig.plant.truth()["pwm_freq_hz"] == pytest.approx(25e6 / 4096 / 123)


MOTORS = [
    {"kind": "dc_motor", "name": "motor_l", "bridge": "tb6612", "drives": "left"},
    {"kind": "dc_motor", "name": "motor_r", "bridge": "tb6612", "drives": "right"},
]


def angle_off(a_deg: float, b_deg: float) -> float:
    return abs((a_deg - b_deg + 180) % 360 - 180)


def test_published_lis3mdl_driver_compass_follows_the_heading_after_a_hard_iron_calibration(make_rig):
    """micropython-lis3mdl 0.2.0, unchanged, as its quickstart sets it up: a turn and a
    half in place, the hard-iron offset from each axis' extremes, then the heading: within
    3 degrees of the body's true compass heading; without the calibration it is far off."""
    compass = {"kind": "lis3mdl", "name": "compass", "bus": "i2c1", "hard_iron_ut": [12.0, -7.0, 3.0]}
    plant = {"body": "differential", "start_pose": [1.5, 1.0, 0.3], "parts": [*MOTORS, compass]}
    rig, r, _ = run_driver(
        make_rig, "lis3mdl_compass", plant, "micropython-lis3mdl", 9.0, wiring=SPIN_WIRING, pins=SPIN_PINS
    )
    truth_deg = rig.plant.truth()["compass_heading_deg"]
    assert "heading_deg" in r, rig.console
    assert r["offset_ut"] == pytest.approx([12.0, -7.0], abs=0.6), r
    assert r["radius_ut"] == pytest.approx([20.0, 20.0], abs=0.6), r
    assert angle_off(r["heading_deg"], truth_deg) < 3, (r["heading_deg"], truth_deg)
    assert angle_off(r["raw_deg"], truth_deg) > 10, (r["raw_deg"], truth_deg)
    assert r["z_ut"] == pytest.approx(-44 + 3, abs=2)


def test_published_lsm6dsox_driver_at_0x6b_turns_an_lsm6dso_part_90_degrees_within_3(make_rig):
    """micropython-lsm6dsox 0.1.0, unchanged, given address=0x6B, against the lsm6dso part
    (the kits' wiring, SA0 high: nothing answers at 0x6A): the robot spins left until the
    integrated gyro says 90 degrees; the true turn agrees within 3; gravity reads 9.8 m/s2."""
    imu = {"kind": "lsm6dso", "name": "imu", "bus": "i2c1", "gyro_bias_dps": [0.0, 0.0, 0.3]}
    plant = {"body": "differential", "start_pose": [1.5, 1.0, 0.0], "parts": [*MOTORS, imu]}
    rig, r, _ = run_driver(make_rig, "imu_spin", plant, "micropython-lsm6dsox", 6.0, wiring=SPIN_WIRING, pins=SPIN_PINS)
    truth_deg = math.degrees(rig.plant.truth()["theta_rad"])
    assert "heading_deg" in r, rig.console
    assert rig.plant.bus_device("i2c1", 0x6B) is not None and rig.plant.bus_device("i2c1", 0x6A) is None
    assert truth_deg > 80, f"the body turned {truth_deg:.1f} degrees; console:\n{rig.console}"
    assert abs(r["heading_deg"] - truth_deg) < 3, (r["heading_deg"], truth_deg)
    assert r["accel_z"] == pytest.approx(9.8, abs=0.2)


def test_published_qmc5883l_driver_compass_reads_the_heading_within_a_degree_twice_in_a_turn(make_rig):
    """micropython-qmc5883l 0.1.2, unchanged, as its docstring sets it up (200 Hz, 2 gauss):
    the robot turns, stops and reads its heading, twice: each within 1 degree of the body's
    true compass heading then. The driver waits for the status register's bit 2 (DOR, a
    sample skipped) rather than DRDY: ten readings take two samples' time each, 100 ms."""
    compass = {"kind": "qmc5883l", "name": "compass", "bus": "i2c1"}
    plant = {"body": "differential", "start_pose": [1.5, 1.0, 0.3], "parts": [*MOTORS, compass]}
    seen = []
    rig, r, _ = run_driver(
        make_rig,
        "qmc5883l_compass",
        plant,
        "micropython-qmc5883l",
        6.0,
        lambda rig: seen.append(rig.plant.truth()["compass_heading_deg"]),
        wiring=SPIN_WIRING,
        pins=SPIN_PINS,
    )
    assert r.get("done") == "second", rig.console
    first, second = seen[1], seen[3]  # (stopped at 2 s and 4 s, read by 2.1 s and 4.1 s)
    assert angle_off(first, second) > 20, (first, second)
    assert angle_off(r["first_deg"], first) < 1, (r["first_deg"], first)
    assert angle_off(r["second_deg"], second) < 1, (r["second_deg"], second)
    assert r["first_ms"] == pytest.approx(100, abs=15)
    assert r["z_gauss"] == pytest.approx(-0.44, abs=0.02)


def test_hmc5883l_compass_read_as_its_public_drivers_read_it_gives_the_heading_within_a_degree(make_rig):
    """No HMC5883L driver is published on PyPI: a firmware reading the hmc5883l part as the
    public drivers do (identification, 15 Hz, gain 1090, continuous, X Z Y big-endian) turns,
    stops and reads its heading, twice: each within 1 degree of the body's true heading."""
    compass = {"kind": "hmc5883l", "name": "compass", "bus": "i2c1"}
    plant = {"body": "differential", "start_pose": [1.5, 1.0, 0.3], "parts": [*MOTORS, compass]}
    the_app = bench_app("hmc5883l_compass", plant, wiring=SPIN_WIRING, pins=SPIN_PINS, lib_dirs=(TURN,))
    rig = make_rig(the_app, main_dir=FIRMWARE / "hmc5883l_compass", allow_exit=True)
    seen = []
    for _ in range(7):
        rig.run_for(1.0)
        seen.append(rig.plant.truth()["compass_heading_deg"])
    rig.stop()
    r = results(rig.console)
    assert r.get("done") == "second", rig.console
    first, second = seen[1], seen[4]  # (still by 2 s and 5 s; read from 2.1 s and 4.8 s)
    assert angle_off(first, second) > 20, (first, second)
    assert angle_off(r["first_deg"], first) < 1, (r["first_deg"], first)
    assert angle_off(r["second_deg"], second) < 1, (r["second_deg"], second)
    assert r["z_gauss"] == pytest.approx(-0.44, abs=0.01)


@pytest.mark.parametrize("chip, address", [("bme280", 0x76), ("bmp280", 0x77)])
def test_published_bme280_driver_reads_a_set_temperature_and_pressure_through_the_calibration(make_rig, chip, address):
    """micropython-bme280 2.1.3, unchanged (forced mode, its own wait, a burst read of 0xF7..):
    its raw readings, compensated by the datasheet's formulas with the trimming registers,
    are the part's temperature (0.01 degrees) and pressure (0.2 Pa). The driver's own
    temperature is 1.51 degrees low: it shifts dig_T2 before multiplying (``* (dig_T2 >> 11)``
    where the datasheet has ``* dig_T2) >> 11``), and its pressure, from that t_fine, 231 Pa."""
    from sim_plant.catalogue.bmp280 import pressure_q24_8, t_fine, temperature_centi

    baro = {"kind": "bmp280", "name": "baro", "bus": "i2c0", "address": address, "chip": chip}
    plant = {"body": "bench", "parts": [{**baro, "temperature_c": 21.37, "pressure_pa": 99_876.5}]}
    rig, r, _ = run_driver(make_rig, "bme280_weather", plant, "micropython-bme280", 1.0)
    assert "raw" in r, rig.console
    assert r["chip_id"] == {"bme280": 0x60, "bmp280": 0x58}[chip]
    adc_t, adc_p, _hum = r["raw"]
    assert temperature_centi(adc_t) == 2137
    assert pressure_q24_8(adc_p, t_fine(adc_t)) / 256 == pytest.approx(99_876.5, abs=0.2)
    assert r["temperature_c"] == pytest.approx(19.86, abs=0.005), "the driver's dig_T2 >> 11"
    assert r["pressure_pa"] == pytest.approx(99_645.6, abs=0.1)


def test_published_mpu6886_driver_integrates_a_turn_in_place_within_3_degrees(make_rig):
    """micropython-mpu6886 0.1.0, unchanged, as its README sets it up (on I2C(1): its README's
    pins 21 and 22 drive the motors here), against the mpu6050 part answering WHO_AM_I 0x19:
    the robot spins left until the integrated gyro says 90 degrees; the true turn agrees
    within 3 (the firmware the LSM6DS-class tests run, which takes the IMU that answers)."""
    imu = {"kind": "mpu6050", "name": "imu", "bus": "i2c1", "who_am_i": 0x19, "gyro_bias_dps": [0.0, 0.0, 0.3]}
    plant = {"body": "differential", "start_pose": [1.5, 1.0, 0.0], "parts": [*MOTORS, imu]}
    rig, r, _ = run_driver(make_rig, "imu_spin", plant, "micropython-mpu6886", 6.0, wiring=SPIN_WIRING, pins=SPIN_PINS)
    truth_deg = math.degrees(rig.plant.truth()["theta_rad"])
    assert "heading_deg" in r, rig.console
    assert r["whoami"] == 0x19
    assert r["temperature"] == pytest.approx(25.0), "the MPU-6886's temperature formula"
    assert truth_deg > 80, f"the body turned {truth_deg:.1f} degrees; console:\n{rig.console}"
    assert abs(r["heading_deg"] - truth_deg) < 3, (r["heading_deg"], truth_deg)


def test_vl53l0x_ranges_the_wall_along_its_ray_once_per_budget_and_the_robot_stops_at_it(make_rig):
    """A firmware reading the vl53l0x part as its drivers do (back-to-back): the first range
    is the wall's along the mount's ray within the datasheet's 3 %; a range every 33 ms
    (the timing budget); the robot stops 0.3 m from the wall."""
    tof = {"kind": "vl53l0x", "name": "tof", "bus": "i2c0", "mount": {"x_m": 0.05}}
    plant = {"body": "differential", "start_pose": [2.0, 1.0, 0.0], "parts": [*MOTORS, tof]}
    pins = {"PWMA": 16, "AIN1": 17, "AIN2": 18, "PWMB": 4, "BIN1": 23, "BIN2": 19}
    app = bench_app("tof", plant, wiring=SPIN_WIRING, pins=pins)
    rig = make_rig(app, main_dir=FIRMWARE / "tof_stop", allow_exit=True)
    rig.run_for(8.0)
    truth = rig.plant.truth()
    rig.stop()
    r = results(rig.console)
    assert r.get("ident") == [0xEE, 0xAA, 0x10], rig.console
    assert r["first_mm"] == pytest.approx(950, rel=0.03)  # the wall at x = 3 m, the chip at 2.05 m
    assert r["stop_mm"] <= 300
    assert r["period_ms"] == pytest.approx(33, abs=1.5)
    assert truth["tof_range_m"] == pytest.approx(0.3, abs=0.05), truth["tof_range_m"]

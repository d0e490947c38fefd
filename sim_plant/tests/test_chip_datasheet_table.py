"""Every register chip of the catalogue against its datasheet, as a table: the reset values
and identity registers it answers at power-on, its self-clearing bits (set by a write, read
back set until the datasheet's time has passed in virtual time, then clear; a software
reset puts the registers back, a reboot keeps them), its data-ready and overrun bits (set at
the configured output data rate, cleared as documented, never while powered down), and
its list of modelled registers (a write elsewhere is named once)."""

import importlib
import pkgutil

import pytest

import sim_plant.catalogue as catalogue
from sim_plant import buses as B
from sim_plant.catalogue.assembly import assemble

MOTORS = [
    {"kind": "dc_motor", "name": "motor_l", "bridge": "tb6612", "drives": "left"},
    {"kind": "dc_motor", "name": "motor_r", "bridge": "tb6612", "drives": "right"},
]
CHIPS = {  # class name -> (its part, its address)
    "Lsm6dsoxChip": ({"kind": "lsm6dsox"}, 0x6A),
    "Mpu6050Chip": ({"kind": "mpu6050"}, 0x68),
    "Lis3mdlChip": ({"kind": "lis3mdl", "noise_ut": 0.0}, 0x1C),
    "Vl53l0xChip": ({"kind": "vl53l0x"}, 0x29),
    "Pca9685Chip": ({"kind": "pca9685", "drives": []}, 0x40),
    "Ina219Chip": ({"kind": "ina219"}, 0x40),
    "Qmc5883lChip": ({"kind": "qmc5883l", "noise_ut": 0.0}, 0x0D),
    "Hmc5883lChip": ({"kind": "hmc5883l", "noise_ut": 0.0}, 0x1E),
    "Bmp280Chip": ({"kind": "bmp280"}, 0x76),
}
SELF_CLEARING = {  # class name -> {(register, bit, clear_us, resets the registers)}, from the datasheets
    "Lsm6dsoxChip": {(0x12, 0x80, 10_000, False), (0x12, 0x01, 50, True)},  # CTRL3_C BOOT, SW_RESET
    "Mpu6050Chip": {(0x6B, 0x80, 100_000, True)},  # PWR_MGMT_1 DEVICE_RESET
    "Lis3mdlChip": {(0x21, 0x08, 5_000, False), (0x21, 0x04, 50, True)},  # CTRL_REG2 REBOOT, SOFT_RST
    "Vl53l0xChip": set(),  # (SYSRANGE_START's bit 0 reads 0 once the measurement starts: at once)
    "Pca9685Chip": set(),  # (MODE1's RESTART reads 0: the restart is a write's, at once)
    "Ina219Chip": set(),  # (CONFIGURATION's RST: the reset is immediate, its own word path)
    "Qmc5883lChip": {(0x0A, 0x80, 350, True)},  # control 2 SOFT_RST (the power-on time)
    "Hmc5883lChip": set(),  # (no reset bit)
    "Bmp280Chip": set(),  # (reset 0xE0: 0xB6 resets at once, reads 0)
}
KEPT = {
    "Lsm6dsoxChip": (0x10, 0x40),
    "Mpu6050Chip": (0x19, 0x09),
    "Lis3mdlChip": (0x20, 0x7C),
    "Qmc5883lChip": (0x09, 0x1D),
}
"""A configuration register and a value for it: a software reset undoes it, a reboot keeps it."""


def plant(name):
    part, _address = CHIPS[name]
    part = {"name": "chip", "bus": "i2c0", **part}
    return assemble({"body": "differential", "start_pose": [1.5, 1.0, 0.0], "parts": [*MOTORS, part]})


def read(p, name, reg, n=1):
    status, _acks, got = p.bus_transfer("i2c0", B.XFER, CHIPS[name][1], n, bytes((reg,)))
    assert status == B.OK
    return got


def write(p, name, reg, *values):
    assert p.bus_transfer("i2c0", B.XFER, CHIPS[name][1], 0, bytes((reg, *values)))[0] == B.OK


def register_chips() -> dict:
    """Every register chip class the catalogue's parts define, by name (not the modules
    beside them: the IMU chips' shared ``Imu`` in ``imu.py`` is no chip of its own)."""
    found = {}
    for info in pkgutil.iter_modules(catalogue.__path__):
        if info.name in catalogue.NOT_ENTRIES:
            continue
        module = importlib.import_module(f"sim_plant.catalogue.{info.name}")
        for obj in vars(module).values():
            if isinstance(obj, type) and issubclass(obj, B.RegisterDevice) and obj.__module__ == module.__name__:
                found[obj.__name__] = obj
    return found


def test_the_table_covers_every_register_chip_and_each_lists_its_modelled_registers():
    chips = register_chips()
    assert set(chips) == set(CHIPS) == set(SELF_CLEARING), "a new chip needs its rows here"
    for name, cls in chips.items():
        assert cls.MODELLED, f"{name} lists no modelled registers"
        declared = {(b.reg, b.mask, b.clear_us, b.resets) for b in cls.SELF_CLEARING}
        assert declared == SELF_CLEARING[name], name
        assert all(b.source for b in cls.SELF_CLEARING), f"{name}: a self-clearing bit cites no datasheet"


@pytest.mark.parametrize("name", sorted(CHIPS))
def test_each_chip_answers_its_reset_values_at_power_on(name):
    p = plant(name)
    chip = p.bus_device("i2c0", CHIPS[name][1])
    for reg, value in chip.RESET.items():
        assert read(p, name, reg) == bytes((value,)), f"{name} register 0x{reg:02x}"


ROWS = [(name, *row) for name, rows in sorted(SELF_CLEARING.items()) for row in sorted(rows)]


@pytest.mark.parametrize("name, reg, bit, clear_us, resets", ROWS)
def test_a_self_clearing_bit_reads_set_until_the_datasheet_time_then_clear(name, reg, bit, clear_us, resets):
    p = plant(name)
    kept_reg, kept = KEPT[name]
    p.advance_to(1_000)
    write(p, name, kept_reg, kept)
    write(p, name, reg, read(p, name, reg)[0] | bit)
    assert read(p, name, reg)[0] & bit, "set at once"
    p.advance_to(1_000 + clear_us - 1)
    assert read(p, name, reg)[0] & bit, "still set a microsecond before its time"
    p.advance_to(1_000 + clear_us)
    assert not read(p, name, reg)[0] & bit, "clear at its time"
    reset_value = p.bus_device("i2c0", CHIPS[name][1]).RESET.get(kept_reg, 0)
    assert read(p, name, kept_reg)[0] == (reset_value if resets else kept)


DATA_READY = [  # chip, the writes that start it, status register, bit, (register, bytes) a read clears, period_us
    ("Lsm6dsoxChip", ((0x11, 0x40),), 0x1E, 0x02, (0x22, 6), round(1e6 / 104)),  # CTRL2_G 104 Hz; GDA
    ("Mpu6050Chip", ((0x6B, 0x00), (0x1A, 0x01), (0x19, 9)), 0x3A, 0x01, (0x3A, 1), 10_000),  # 1 kHz / 10
    ("Lis3mdlChip", ((0x22, 0x00),), 0x27, 0x08, (0x28, 6), 100_000),  # continuous at 10 Hz; ZYXDA
    ("Qmc5883lChip", ((0x09, 0x01),), 0x06, 0x01, (0x00, 6), 100_000),  # continuous at 10 Hz; DRDY
]


@pytest.mark.parametrize("name, setup, status, bit, clear, period_us", DATA_READY)
def test_data_ready_sets_at_each_output_data_rate_tick_and_clears_when_read(name, setup, status, bit, clear, period_us):
    p = plant(name)
    for _ in range(10):  # powered down (the reset state): never ready
        p.advance_to(p.t_us + 100_000)
        assert not read(p, name, status)[0] & bit, f"{name} data ready while powered down"
    for reg, value in setup:
        write(p, name, reg, value)
    t_us = B.tick_after(p.t_us, period_us) + period_us // 3
    for _ in range(3):
        p.advance_to(t_us)
        read(p, name, *clear)
        assert not read(p, name, status)[0] & bit, "cleared by the read"
        p.advance_to(B.tick_after(t_us, period_us) - 1)
        assert not read(p, name, status)[0] & bit, "not before the next tick"
        t_us = B.tick_after(t_us, period_us)
        p.advance_to(t_us)
        assert read(p, name, status)[0] & bit, "set at the tick"


def test_the_compass_overrun_bits_set_when_a_sample_is_overwritten_unread_and_clear_with_each_axis_read():
    name = "Lis3mdlChip"
    p = plant(name)
    write(p, name, 0x22, 0x00)
    p.advance_to(150_000)
    read(p, name, 0x28, 6)
    p.advance_to(250_000)
    assert read(p, name, 0x27) == b"\x0f", "one new sample: ZYXDA, ZDA, YDA, XDA; no overrun"
    p.advance_to(350_000)
    assert read(p, name, 0x27) == b"\xff", "a second one over it: ZYXOR, ZOR, YOR, XOR too"
    read(p, name, 0x28, 2)  # the x axis alone
    assert read(p, name, 0x27) == b"\x66", "x read: XDA, XOR, ZYXDA, ZYXOR clear; y and z still new and overrun"
    read(p, name, 0x2A, 4)
    assert read(p, name, 0x27) == b"\x00"


def test_the_qmc5883l_says_a_sample_skipped_from_continuous_modes_start_and_clears_it_with_a_data_read():
    name = "Qmc5883lChip"
    p = plant(name)
    p.advance_to(50_000)
    write(p, name, 0x09, 0x01)  # continuous at 10 Hz, in the tick of 0 to 100 ms
    p.advance_to(150_000)
    assert read(p, name, 0x06) == b"\x01", "the first sample: DRDY"
    p.advance_to(250_000)
    assert read(p, name, 0x06) == b"\x05", "a second one, the first unread: DOR too"
    read(p, name, 0x00, 1)
    assert read(p, name, 0x06) == b"\x00", "a data register read clears both"
    p.advance_to(350_000)
    assert read(p, name, 0x06) == b"\x01"
    write(p, name, 0x0A, 0x40)  # ROL_PNT: 0x06 rolls over to 0x00
    assert read(p, name, 0x05, 3)[2:] == read(p, name, 0x00, 1)
    write(p, name, 0x09, 0x00)  # standby
    p.advance_to(650_000)
    assert read(p, name, 0x06) == b"\x00", "no samples in standby"


def test_the_hmc5883l_measures_continuously_or_once_and_its_rdy_clears_only_as_new_data_is_written():
    name = "Hmc5883lChip"
    p = plant(name)
    assert read(p, name, 0x0A, 3) == b"H43"
    assert read(p, name, 0x09) == b"\x00", "single mode at power-on waits: no data"
    write(p, name, 0x02, 0x00)  # continuous at 15 Hz: a sample every 66667 us
    p.advance_to(66_667 + 249)
    assert read(p, name, 0x09) == b"\x00", "clear for 250 us as the data is written"
    p.advance_to(66_667 + 250)
    assert read(p, name, 0x09) == b"\x01"
    read(p, name, 0x03, 6)
    assert read(p, name, 0x09) == b"\x01", "reading the data leaves RDY set"
    data = read(p, name, 0x03, 8)
    assert data[6:] == data[:2], "the pointer goes from 0x08 back to 0x03"
    assert int.from_bytes(read(p, name, 0x07, 2), "big", signed=True) == 218, "y: 20 uT at 1090 LSB/gauss"
    write(p, name, 0x01, 0xE0)  # gain 230 LSB/gauss
    assert int.from_bytes(read(p, name, 0x07, 2), "big", signed=True) == 46
    write(p, name, 0x02, 0x01)  # a single measurement
    p.advance_to(p.t_us + 6_000 - 1)
    assert read(p, name, 0x02) == b"\x01", "still measuring"
    p.advance_to(p.t_us + 1)
    assert read(p, name, 0x02) == b"\x03", "done: idle"
    chip = p.bus_device("i2c0", 0x1E)
    chip.field = (2000.0, 44.0, chip.field[2])  # 20 gauss: beyond the 8.1 gauss range
    write(p, name, 0x02, 0x01)
    p.advance_to(p.t_us + 6_000)
    assert -4096 in (int.from_bytes(read(p, name, reg, 2), "big", signed=True) for reg in (0x03, 0x07))


def test_the_barometers_compensation_turns_the_datasheets_example_into_its_results():
    from sim_plant.catalogue.bmp280 import pressure_q24_8, t_fine, temperature_centi

    assert t_fine(519888) == 128422 and temperature_centi(519888) == 2508  # BMP280 datasheet 3.12
    assert pressure_q24_8(415148, 128422) / 256 == pytest.approx(100653.27, abs=0.05)


def test_the_barometer_converts_once_when_forced_for_the_datasheets_time_and_resets_on_0xb6():
    name = "Bmp280Chip"
    p = plant(name)
    assert read(p, name, 0xD0) == b"\x58"
    assert read(p, name, 0x88, 6) == bytes.fromhex("706b436718fc"), "dig_T1..T3: 27504, 26435, -1000"
    assert read(p, name, 0xF7, 6) == bytes.fromhex("800000800000"), "no conversion yet"
    p.advance_to(1_000)
    write(p, name, 0xF4, 0b001_001_01)  # x1, x1, forced: 1.25 + 2.3 + 2.3 + 0.575 ms
    p.advance_to(1_000 + 6_425 - 1)
    assert read(p, name, 0xF3) == b"\x08", "measuring"
    assert read(p, name, 0xF4) == b"\x25"
    p.advance_to(1_000 + 6_425)
    assert read(p, name, 0xF3) == b"\x00"
    assert read(p, name, 0xF4) == b"\x24", "back to sleep"
    data = read(p, name, 0xF7, 6)
    adc_p, adc_t = int.from_bytes(data[:3], "big") >> 4, int.from_bytes(data[3:], "big") >> 4
    assert (adc_t, adc_p) != (0x80000, 0x80000)
    from sim_plant.catalogue.bmp280 import pressure_q24_8, t_fine, temperature_centi

    assert temperature_centi(adc_t) == 2500
    assert pressure_q24_8(adc_p, t_fine(adc_t)) / 256 == pytest.approx(101_325, abs=0.2)
    write(p, name, 0xE0, 0xB6)
    assert read(p, name, 0xF4) == b"\x00" and read(p, name, 0xF7, 3) == b"\x80\x00\x00"
    assert read(p, name, 0xE0) == b"\x00"
    t0 = p.t_us
    write(p, name, 0xF4, 0b001_001_11)  # normal: converting 6425 us, then t_sb (0.5 ms), again
    p.advance_to(t0 + 6_425)
    assert read(p, name, 0xF3) == b"\x00" and read(p, name, 0xF4) == b"\x27", "standing by, still normal"
    p.advance_to(t0 + 6_925)
    assert read(p, name, 0xF3) == b"\x08", "the next conversion"


def test_the_imu_data_ready_bits_follow_each_sensors_own_rate_and_its_own_outputs():
    name = "Lsm6dsoxChip"
    p = plant(name)
    write(p, name, 0x10, 0x10)  # CTRL1_XL: 12.5 Hz
    write(p, name, 0x11, 0x40)  # CTRL2_G: 104 Hz
    p.advance_to(100_000)
    assert read(p, name, 0x1E) == b"\x03"
    read(p, name, 0x22, 6)  # the gyro's outputs: GDA clears, XLDA stays
    assert read(p, name, 0x1E) == b"\x01"
    read(p, name, 0x28, 6)
    assert read(p, name, 0x1E) == b"\x00"
    p.advance_to(round(1e6 / 104) * 11)
    assert read(p, name, 0x1E) == b"\x02", "the gyro's next tick; the accelerometer's is at 160 ms"
    p.advance_to(160_000)
    assert read(p, name, 0x1E) == b"\x03"


def test_the_ranger_says_ready_after_its_timing_budget_and_clears_when_told():
    name = "Vl53l0xChip"
    p = plant(name)
    write(p, name, 0x00, 0x01)  # SYSRANGE_START: one measurement
    assert read(p, name, 0x00) == b"\x00", "bit 0 reads 0 once started"
    p.advance_to(33_000 - 1)
    assert not read(p, name, 0x13)[0] & 0x07
    p.advance_to(33_000)
    assert read(p, name, 0x13)[0] & 0x07
    write(p, name, 0x0B, 0x01)  # SYSTEM_INTERRUPT_CLEAR
    assert not read(p, name, 0x13)[0] & 0x07


def test_the_monitor_reset_bit_resets_at_once_and_conversion_ready_clears_with_the_power_read():
    name = "Ina219Chip"
    p = plant(name)
    write(p, name, 0x00, 0x01, 0x9F)
    assert read(p, name, 0x00, 2) == b"\x01\x9f"
    write(p, name, 0x00, 0x80, 0x00)  # RST
    assert read(p, name, 0x00, 2) == b"\x39\x9f", "the power-on configuration, RST clear"
    p.advance_to(2_000)  # a 12-bit shunt and bus conversion: 1064 us
    assert read(p, name, 0x02, 2)[1] & 0x02, "CNVR"
    read(p, name, 0x03, 2)
    assert not read(p, name, 0x02, 2)[1] & 0x02, "reading POWER clears CNVR"


def test_a_write_to_an_unmodelled_register_is_counted_and_named_once_per_chip():
    name = "Lsm6dsoxChip"
    p = plant(name)
    write(p, name, 0x17, 0x09)  # CTRL8_XL (micropython-lib's driver writes it)
    write(p, name, 0x17, 0x09)
    write(p, name, 0x58, 0x80)  # TAP_CFG2
    notes = p.bus_notes("i2c0")
    assert len(notes) == 1 and "register 0x17" in notes[0] and "plain memory" in notes[0], notes
    assert "CTRL3_C: BOOT" in notes[0], "the note lists what the model honours"
    assert p.bus_device("i2c0", 0x6A).unmodelled == {0x17: (0, 2), 0x58: (0, 1)}
    write(p, name, 0x10, 0x40)
    assert p.bus_notes("i2c0") == []


AUTO_INCREMENT = [  # chip, a register pair both plain to write, whether the pointer moves on at reset
    ("Lsm6dsoxChip", 0x10, True),  # CTRL3_C's IF_INC resets to 1
    ("Mpu6050Chip", 0x19, True),  # the MPU-6xxx always moves on
    ("Lis3mdlChip", 0x23, True),  # moves on (the drivers do not set the sub-address' bit 7)
    ("Vl53l0xChip", 0x40, True),
    ("Pca9685Chip", 0x06, False),  # MODE1's AI resets to 0
    ("Qmc5883lChip", 0x0B, True),  # (ROL_PNT only wraps 0x06 to 0x00)
    ("Hmc5883lChip", 0x00, True),  # (wraps 0x08 to 0x03, 0x0C to 0x00)
    ("Bmp280Chip", 0xF4, True),
]


@pytest.mark.parametrize("name, reg, moves_on", AUTO_INCREMENT)
def test_a_write_of_two_bytes_lands_as_the_chips_auto_increment_rule_says(name, reg, moves_on):
    p = plant(name)
    write(p, name, reg, 0x11, 0x22)
    got = read(p, name, reg)[0], p.bus_device("i2c0", CHIPS[name][1]).regs[reg + 1]
    assert got == ((0x11, 0x22) if moves_on else (0x22, 0x00)), name

"""Part ``bmp280``: a Bosch BMP280 (``chip = "bmp280"``, id 0x58) or BME280 (``"bme280"``,
id 0x60) barometer on I2C (address 0x76, 0x77 with SDO high) reading a set temperature and
pressure (``temperature_c``, ``pressure_pa``), and on a BME280 a set humidity
(``humidity_pct``).

The chip's calibration registers (0x88..0x9F, dig_T1..dig_P9, little-endian) hold the
BMP280 datasheet's example trimming values (3.12: 27504, 26435, -1000; 36477, -10685,
3024, 2855, 140, -7, 15500, -14600, 6000); its raw readings are the ones the datasheet's
compensation formulas (3.11.3, the 32-bit temperature and 64-bit pressure) turn into the
set temperature (to 0.01 °C) and pressure (to 1/256 Pa, nearest).

Modelled registers: the calibration, id 0xD0, reset 0xE0 (0xB6 puts every register back,
reads 0), status 0xF3 (measuring, bit 3: a conversion running; im_update not modelled:
the trimming is there at once), ctrl_meas 0xF4 (osrs_t, osrs_p: skipped (0) leaves that
output at 0x80000; mode: sleep, forced (one conversion, then sleep), normal), config 0xF5
(t_sb: normal mode's standby; filter kept, no effect on a set value), the outputs
0xF7..0xFC (press, temp: msb, lsb, xlsb, 20 bits; 0x80000 until a conversion writes them).
A conversion takes the BME280 datasheet's maximum (9.1): 1.25 ms + 2.3 ms per temperature
oversample + 2.3 ms per pressure oversample + 0.575 ms (+ 2.3 ms per humidity oversample
+ 0.575 ms on a BME280).

The BME280's humidity (its datasheet, 4.2.3 and 5.4): ctrl_hum 0xF2 (osrs_h, taken at the
next write of ctrl_meas, as the datasheet says), the output hum 0xFD..0xFE (msb, lsb, 16
bits; 0x8000 while skipped or before a conversion), its trimming dig_H1 0xA1, dig_H2
0xE1..0xE2, dig_H3 0xE3, dig_H4 0xE4..0xE5[3:0], dig_H5 0xE5[7:4]..0xE6, dig_H6 0xE7
(``TRIM_H``: values as a chip carries them; the datasheet gives no example), the raw
reading the one the 32-bit compensation (4.2.3) turns into the set humidity
(``humidity_pct``, the nearest a raw reading gives: 0.012 %RH steps). On a BMP280 those registers read 0 and hum
0x8000 (the chip has no humidity). A write to another register is named once in the
run's output."""

from sim_plant.buses import BusName, RegisterDevice, check_placement
from sim_plant.catalogue.base import Build, Opt, PartType
from sim_plant.option_table import Num, OneOf

CALIB, ID, RESET_REG, CTRL_HUM, STATUS, CTRL_MEAS, CONFIG = 0x88, 0xD0, 0xE0, 0xF2, 0xF3, 0xF4, 0xF5
PRESS, TEMP, HUM = 0xF7, 0xFA, 0xFD
TRIM_T = (27504, 26435, -1000)  # the BMP280 datasheet's example (3.12)
TRIM_P = (36477, -10685, 3024, 2855, 140, -7, 15500, -14600, 6000)
TRIM_H = (75, 362, 0, 313, 50, 30)  # dig_H1..dig_H6, of the order a BME280 carries (its datasheet has no example)
CALIB_H1, CALIB_H2 = 0xA1, 0xE1
IDS = {"bmp280": 0x58, "bme280": 0x60}
OVERSAMPLES = (0, 1, 2, 4, 8, 16, 16, 16)
STANDBY_US = (500, 62_500, 125_000, 250_000, 500_000, 1_000_000, 2_000_000, 4_000_000)  # BMP280 t_sb


def t_fine(adc_t: int) -> int:
    """The datasheet's (3.11.3) temperature compensation: t_fine of a raw temperature."""
    t1, t2, t3 = TRIM_T
    var1 = (((adc_t >> 3) - (t1 << 1)) * t2) >> 11
    var2 = (((((adc_t >> 4) - t1) * ((adc_t >> 4) - t1)) >> 12) * t3) >> 14
    return var1 + var2


def temperature_centi(adc_t: int) -> int:
    """The compensated temperature in 0.01 °C (3.11.3)."""
    return (t_fine(adc_t) * 5 + 128) >> 8


def pressure_q24_8(adc_p: int, fine: int) -> int:
    """The datasheet's 64-bit pressure compensation (3.11.3): Pa in Q24.8 (C's division
    truncates towards zero: so here)."""
    p1, p2, p3, p4, p5, p6, p7, p8, p9 = TRIM_P
    var1 = fine - 128000
    var2 = var1 * var1 * p6
    var2 = var2 + ((var1 * p5) << 17)
    var2 = var2 + (p4 << 35)
    var1 = ((var1 * var1 * p3) >> 8) + ((var1 * p2) << 12)
    var1 = (((1 << 47) + var1) * p1) >> 33
    if var1 == 0:
        return 0
    p = 1048576 - adc_p
    num = ((p << 31) - var2) * 3125
    p = abs(num) // var1 * (1 if num >= 0 else -1)
    var1 = (p9 * (p >> 13) * (p >> 13)) >> 25
    var2 = (p8 * p) >> 19
    return ((p + var1 + var2) >> 8) + (p7 << 4)


def humidity_q22_10(adc_h: int, fine: int) -> int:
    """The BME280 datasheet's 32-bit humidity compensation (4.2.3): %RH in Q22.10."""
    h1, h2, h3, h4, h5, h6 = TRIM_H
    v = fine - 76800
    v = ((((adc_h << 14) - (h4 << 20) - (h5 * v)) + 16384) >> 15) * (
        ((((((v * h6) >> 10) * (((v * h3) >> 11) + 32768)) >> 10) + 2097152) * h2 + 8192) >> 14
    )
    v = v - (((((v >> 15) * (v >> 15)) >> 7) * h1) >> 4)
    v = min(max(v, 0), 419430400)
    return v >> 12


def humidity_trimming() -> dict:
    """dig_H1..dig_H6 in the BME280's registers (its datasheet, table 16): register -> byte."""
    h1, h2, h3, h4, h5, h6 = TRIM_H
    h2_bytes = h2.to_bytes(2, "little", signed=True)
    return {
        CALIB_H1: h1,
        CALIB_H2: h2_bytes[0],
        CALIB_H2 + 1: h2_bytes[1],
        CALIB_H2 + 2: h3,
        CALIB_H2 + 3: (h4 >> 4) & 0xFF,
        CALIB_H2 + 4: (h4 & 0xF) | (h5 & 0xF) << 4,
        CALIB_H2 + 5: (h5 >> 4) & 0xFF,
        CALIB_H2 + 6: h6 & 0xFF,
    }


def _nearest(f, target: float, decreasing: bool = False, bits: int = 20) -> int:
    """The ``bits``-bit raw value whose compensated value ``f(raw)`` is nearest ``target``."""
    lo, hi = 0, (1 << bits) - 1
    while lo < hi:
        mid = (lo + hi) // 2
        below = f(mid) > target if decreasing else f(mid) < target
        lo, hi = (mid + 1, hi) if below else (lo, mid)
    return min((r for r in (lo - 1, lo) if 0 <= r < 1 << bits), key=lambda r: abs(f(r) - target))


def raw_readings(temperature_c: float, pressure_pa: float, humidity_pct: float = 0.0) -> tuple[int, int, int]:
    """(adc_T, adc_P, adc_H) that the compensation turns into the temperature, pressure
    and humidity."""
    adc_t = _nearest(temperature_centi, temperature_c * 100)
    fine = t_fine(adc_t)
    adc_p = _nearest(lambda raw: pressure_q24_8(raw, fine), pressure_pa * 256, decreasing=True)
    adc_h = _nearest(lambda raw: humidity_q22_10(raw, fine), humidity_pct * 1024, bits=16)
    return adc_t, adc_p, adc_h


class Bmp280Chip(RegisterDevice):
    MODELLED = {
        **{reg: "calibration dig_T1..dig_P9 (the datasheet's example)" for reg in range(CALIB, CALIB + 24)},
        ID: "id: 0x58 (BMP280) or 0x60 (BME280)",
        RESET_REG: "reset: 0xB6 resets every register",
        CTRL_HUM: "ctrl_hum: osrs_h (BME280; taken at the next ctrl_meas write)",
        STATUS: "status: measuring",
        CTRL_MEAS: "ctrl_meas: osrs_t, osrs_p, mode (sleep, forced, normal)",
        CONFIG: "config: t_sb (filter kept)",
        **{reg: "press, temp (msb, lsb, xlsb)" for reg in range(PRESS, HUM)},
        HUM: "hum msb (BME280: osrs_h skipped or no conversion yet: 0x8000; BMP280: 0x8000)",
        HUM + 1: "hum lsb",
        CALIB_H1: "calibration dig_H1 (BME280)",
        **{reg: "calibration dig_H2..dig_H6 (BME280)" for reg in range(CALIB_H2, CALIB_H2 + 7)},
    }
    FIXED_STATE = (*RegisterDevice.FIXED_STATE, "RESET", "raw", "humid")

    def __init__(
        self,
        name,
        bus,
        address,
        *,
        chip: str,
        temperature_c: float,
        pressure_pa: float,
        humidity_pct: float = 0.0,
    ):
        super().__init__(name, bus, address)
        calibration = b"".join(v.to_bytes(2, "little", signed=v < 0) for v in (*TRIM_T, *TRIM_P))
        self.humid = chip == "bme280"  # (a BMP280 has no humidity)
        self.RESET = {
            **{CALIB + i: b for i, b in enumerate(calibration)},
            **(humidity_trimming() if self.humid else {}),
            ID: IDS[chip],
            PRESS: 0x80,
            TEMP: 0x80,
            HUM: 0x80,
        }
        self.raw = raw_readings(temperature_c, pressure_pa, humidity_pct)
        self.power_on()
        self.osrs_h = 0  # ctrl_hum's osrs_h as the last ctrl_meas write took it (datasheet 5.4.3)
        self.started_us = 0  # when the current forced or normal-mode run began
        self.written = False  # a conversion wrote the outputs since the last power-on

    def power_on(self) -> None:
        super().power_on()
        self.osrs_h = 0

    def conversion_us(self) -> int:
        ctrl = self.regs[CTRL_MEAS]
        os_t, os_p, os_h = OVERSAMPLES[ctrl >> 5], OVERSAMPLES[ctrl >> 2 & 7], OVERSAMPLES[self.osrs_h]
        return 1250 + 2300 * os_t + (2300 * os_p + 575 if os_p else 0) + (2300 * os_h + 575 if os_h else 0)

    def _convert(self, t_us: int) -> bool:
        """Whether a conversion is running at ``t_us``; one that has ended wrote the outputs."""
        mode = self.regs[CTRL_MEAS] & 3
        if mode == 0:
            return False
        elapsed, busy = t_us - self.started_us, self.conversion_us()
        if mode == 3:
            cycle = busy + STANDBY_US[self.regs[CONFIG] >> 5]
            if elapsed >= busy:
                self._write_outputs()
            return elapsed % cycle < busy
        if elapsed < busy:
            return True
        self._write_outputs()
        self.regs[CTRL_MEAS] &= 0xFC  # forced: back to sleep
        return False

    def _write_outputs(self) -> None:
        ctrl = self.regs[CTRL_MEAS]
        adc_t, adc_p, _ = self.raw
        for reg, on, raw in ((TEMP, ctrl >> 5, adc_t), (PRESS, ctrl >> 2 & 7, adc_p)):
            value = raw if on else 0x80000
            self.regs[reg : reg + 3] = [value >> 12, value >> 4 & 0xFF, (value & 0xF) << 4]
        if self.humid:
            value = self.raw[2] if self.osrs_h else 0x8000
            self.regs[HUM : HUM + 2] = [value >> 8, value & 0xFF]

    def load(self, t_us, reg):
        measuring = self._convert(t_us)
        if reg == STATUS:
            return 0x08 if measuring else 0x00
        return self.regs[reg]

    def store(self, t_us, reg, value):
        self._convert(t_us)
        if reg == RESET_REG:
            if value == 0xB6:
                self.power_on()
            return
        if reg in self.RESET or reg in range(PRESS, HUM + 2) or reg == STATUS:
            return  # read-only
        self.regs[reg] = value & 0xFF
        if reg == CTRL_MEAS:  # (ctrl_hum takes effect at a write of ctrl_meas: datasheet 5.4.3)
            self.osrs_h = self.regs[CTRL_HUM] & 7 if self.humid else 0
            if value & 3:
                self.started_us = t_us


class Bmp280(PartType):
    CHIP = Bmp280Chip  # (its registers: docs/parts.md)
    kind = "bmp280"
    MODELLED_FEATURES = (
        "the datasheet's example trimming, raw readings that compensate to the set temperature and pressure",
        "the BME280's humidity: ctrl_hum taking effect at the next ctrl_meas write, its trimming (typical "
        "values: the datasheet gives none) and a raw reading that compensates to the set humidity",
        "sleep, forced and normal modes; a conversion's time from the oversampling; status' measuring bit; "
        "reset by 0xB6",
        "the chip id of the BMP280 (0x58) or BME280 (0x60)",
    )
    NOT_MODELLED = (
        "the IIR filter (kept: a set value does not move)",
        "status' im_update (the trimming is there at once)",
        "SPI",
        "noise and drift",
    )
    doc = (
        "A BMP280 (id 0x58) or BME280 (id 0x60) barometer on I2C: a set temperature and pressure"
        " (and humidity on a BME280), compensated."
    )
    OPTIONS = (
        Opt("bus", BusName(), "i2c0", "the bus it is on, as the firmware creates it"),
        Opt("address", Num("", 0, 127, whole=True), 0x76, "its 7-bit I2C address (0x76; 0x77 with SDO high)"),
        Opt("chip", OneOf(tuple(IDS)), "bmp280", "which chip: its id register; a BME280 measures humidity too"),
        Opt("temperature_c", Num("°C", -40, 85), 25.0, "the temperature it reads (the datasheet's range)"),
        Opt("pressure_pa", Num("pascals", 30_000, 110_000), 101_325.0, "the pressure it reads (the datasheet's range)"),
        Opt("humidity_pct", Num("percent RH", 0, 100), 40.0, "the humidity a BME280 reads (a BMP280 has none)"),
    )
    SIGNALS = ()
    on_bus = True

    def check(self) -> None:
        check_placement(self.options, "the bmp280 part")

    def add(self, build: Build) -> None:
        o = self.options
        build.parts.append(
            Bmp280Chip(
                self.name,
                o["bus"],
                o["address"],
                chip=o["chip"],
                temperature_c=float(o["temperature_c"]),
                pressure_pa=float(o["pressure_pa"]),
                humidity_pct=float(o["humidity_pct"]),
            )
        )

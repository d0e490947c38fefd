"""kitbot in the loop (hil_tests/firmware/kitbot): firmware written as a robot kit's
MicroPython library is (a package under lib/ with relative imports; motors on PWM slice 7
through its registers by mem32, encoders counted by PIO, an IMU reset that polls BOOT and
REBOOT, a bus clear with writeto(0, ""), array('h') reads, an SH1106 on SPI behind a
Pin.ALT re-mux of its clock, APA102 LEDs sharing SPI0's MOSI with it on a clock pin of
their own as on a Pololu 3pi+ 2040, rp2.bootsel_button, QTR line sensors), held to what the
plant says happened."""

import dataclasses
import subprocess
from pathlib import Path

import pytest

from host.core import interpreter
from host.rig.config.rigfile import load_rig
from host.tests.conftest import results
from host.tests.test_oled import vlsb_rows

pytestmark = pytest.mark.hil
RIG = Path(__file__).parent / "firmware" / "kitbot" / "rig.toml"
LINES = ("LINE0", "LINE1", "LINE2")
V_MAX_M_S = 0.4  # the differential body's default at full duty (deadband 0 in rig.toml)
HALF = 3000 / 6000  # main.py's drive: CC 3000 of TOP + 1 = 6000
LSB_MDPS_2000 = 70.0  # LSM6DSO gyro at +-2000 dps (datasheet table 2)
LSB_G_2 = 0.061e-3  # accelerometer at +-2 g, g per count
TAPE_X_M, TAPE_HALF_M, LINE_AHEAD_M, START_X_M = 0.62, 0.0095, 0.04, 0.5  # rig.toml
WHITE_US, BLACK_US = 120, 700  # rig.toml's qtr
LOOP_PASS_US = 4 * 10  # a pass of the driver's read loop: a clock read and three pin reads, 10 us each spinning


def run(make_rig, app, seconds=1.2):
    rig = make_rig(app, allow_exit=True)
    rig.run_for(seconds)
    parts = {getattr(p, "label", ""): p for p in getattr(rig.plant, "inner", rig.plant).parts}
    truth = rig.truth()
    leds = [rig.plant.output(f"leds.led{i}") for i in range(3)]
    rig.stop()
    return rig, results(rig.console), truth, parts, leds


def framebuf_picture(lines: list, rect: tuple) -> bytes:
    """What MicroPython's own framebuf draws for these text lines and rectangle (the
    interpreter the harness runs, without the harness): the reference picture."""
    draw = "".join(f"f.text({text!r}, 0, {y}, 1)\n" for text, y in lines)
    script = f"import framebuf\nb = bytearray(1024)\nf = framebuf.FrameBuffer(b, 128, 64, framebuf.MONO_VLSB)\n{draw}"
    script += f"f.rect(*{rect!r}, 1)\nprint(bytes(b).hex())\n"
    command = [str(interpreter.find()), "-c", script]
    out = subprocess.run(command, capture_output=True, text=True, timeout=30, check=True)
    return vlsb_rows(list(bytes.fromhex(out.stdout.strip())), 128, 64)


def without_line_sensors():
    """The rig with the line sensors' pins wired to nothing (their pads read their pull)."""
    app = load_rig(RIG)
    return dataclasses.replace(app, wiring={k: v for k, v in app.wiring.items() if k not in LINES})


# Both tests' figures are a free CPU's (MPYFIL_CPU=free, stated): on an RP2040
# (rp2040@125MHz) the set-up before BOOTSEL's wait computes 19 ms (t0 at 42 ms, not 23 ms),
# so the wait for the press at 50 ms is 11 ms, not 30; and the line driver's read loop
# (ticks_us and three Pin.value a pass, a C call 24.5 us each in that model) stamps the
# 120 us falls with its pass before, 65 us.


def test_kitbot_drives_counts_reads_its_imu_and_shows_what_the_plant_says_happened(make_rig, monkeypatch):
    monkeypatch.setenv("MPYFIL_CPU", "free")
    rig, r, truth, parts, leds = run(make_rig, without_line_sensors())
    where = f"console:\n{rig.console}\nartefacts: {rig.artefacts}"
    assert "totals" in r, f"the firmware did not finish; {where}"
    assert "[mpy-fil:" not in rig.console, f"a note on an unmodelled register, poll or address; {where}"
    # the IMU: both chips answered, each self-clearing bit was seen set then clear
    assert r["detect"] is True
    boot, sw_reset, reboot, soft_rst = r["reset_polls"]
    assert boot > 10 and reboot > 10, "BOOT (10 ms) and REBOOT (5 ms) were polled until they cleared"
    assert r["started_ms"] >= 30 and r["button_a"] is False, "waited for BOOTSEL (pressed at 50 ms)"
    assert r["acc"] == [0, 0, round(1 / LSB_G_2)], "flat and still: 1 g on z"
    assert r["gyro_still"] == [0, 0, 0]
    assert r["mag"] == [0, round(0.20 * 6842), round(-0.44 * 6842)], "20 uT north (+y), 44 uT down, at 6842/gauss"
    # the motors: CSR EN, DIV 1.0, TOP 5999, CC half on both channels
    assert r["regs"] == [1, 16, 5999, 3000 << 16 | 3000]
    drive_s, turn_s = r["drive_us"] / 1e6, r["turn_us"] / 1e6
    # the distance the duty implies: ahead at HALF of v_max for drive_s (the turn adds none)
    assert truth["distance_m"] == pytest.approx(V_MAX_M_S * HALF * drive_s, rel=1e-3), (truth, r)
    assert truth["x_m"] == pytest.approx(START_X_M + V_MAX_M_S * HALF * drive_s, abs=1e-3)
    wheel_w = V_MAX_M_S * (2000 / 6000) / 0.15 * 2  # rad/s of the body turning in place, track 0.15 m
    assert truth["theta_rad"] == pytest.approx(wheel_w * turn_s, rel=1e-3), "turned left as CC 2000 each way says"
    assert r["gyro_turn"][2] == pytest.approx(truth["imu_sample_dps"] * 1000 / LSB_MDPS_2000, abs=1)
    assert r["gyro_turn"][2] * LSB_MDPS_2000 / 1000 == pytest.approx(wheel_w * 57.29578, rel=0.01)
    # the encoders: the PIO decoders counted what the plant's wheels turned, edge for edge
    assert r["totals"] == [truth["enc_l_edges"], truth["enc_r_edges"]]
    left, right = r["drive_counts"]
    assert left == right > 200 and r["turn_counts"][0] == -r["turn_counts"][1] < -50
    assert sum(r["drive_counts"]) + sum(r["turn_counts"]) == sum(r["totals"])
    # the display: the glass shows what framebuf draws for the counts the plant made
    text = [("kitbot done", 0), ("L %d" % truth["enc_l_edges"], 16), ("R %d" % truth["enc_r_edges"], 28)]
    want = framebuf_picture(text, (0, 44, 128, 20))
    assert vlsb_rows(list(bytes.fromhex(r["picture"])), 128, 64) == want, "the firmware's own buffer"
    assert parts["oled"].picture() == want, "the glass"
    assert truth["oled_on"] == 1 and truth["oled_lit_px"] == sum(want)
    # the LEDs: red once done (green while driving, blue turning), full brightness, no framing
    # fault: on SPI0 with the display, they heard their own frames only (their clock pin, GP6,
    # the SPI's only while they are written; the display's on GP2), and the display only its own
    leds_seen = (leds, truth["leds_faults"], truth["leds_frames"])
    assert leds == [0xFF0000, 0, 0] and truth["leds_faults"] == 0, f"LEDs, faults, frames: {leds_seen}; {where}"
    assert truth["leds_frames"] == 3 * 3, f"three shows of three LED frames, none of the display's: {leds_seen}"
    # the line sensors' pins wired to nothing: each reads its pull (low) at once, and
    # time_pulse_us never sees the line rise (its timeout: the driver's 1000)
    assert all(row[1:] == [0, 0, 0] for row in r["line"]) and r["one"] == [1000] * 3


def test_kitbot_line_sensors_follow_the_floor_as_it_crosses_the_tape(make_rig, monkeypatch):
    monkeypatch.setenv("MPYFIL_CPU", "free")
    rig, r, truth, _parts, _leds = run(make_rig, load_rig(RIG))
    assert "line" in r, f"the firmware did not finish; console:\n{rig.console}"
    assert "[mpy-fil:" not in rig.console, rig.console
    v = V_MAX_M_S * HALF
    crossed = 0
    for t_ms, *times in r["line"]:
        x = START_X_M + LINE_AHEAD_M + v * t_ms / 1000  # the channels' row (y offsets: across the path)
        off = abs(x - TAPE_X_M)
        if abs(off - TAPE_HALF_M) < 0.003:
            continue  # (at the tape's edge within a read's travel)
        crossed += off < TAPE_HALF_M
        want = BLACK_US if off < TAPE_HALF_M else WHITE_US
        # the driver stamps each pass before its reads: channel 0, read first, gives the
        # discharge time to the us; a later channel that fell during the pass's first reads
        # gets the pass's stamp (less, by under one pass of the loop)
        where = f"at {t_ms} ms, the channels' row at x {x:.4f} m: {times}, {want} expected"
        assert times[0] == want, where
        assert all(want - LOOP_PASS_US < us <= want for us in times), where
    assert crossed >= 3, r["line"]
    assert r["one"] == [WHITE_US] * 3, f"time_pulse_us over the floor after the drive: {r['one']}"
    assert truth["line_on_tape"] == [False, False, False]

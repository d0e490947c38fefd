"""The parts the common Wokwi projects need beside the first ones, on their own: the
character LCD's HD44780 decoding behind its PCF8574, the buzzer's tones, the KY-040's
quadrature, the DHT's frames (their projects: host/tests/test_wokwi_more_parts.py)."""

import pytest

from sim_plant.catalogue.buzzer import _Buzzer
from sim_plant.catalogue.char_lcd import CUSTOM, CharLcdChip
from sim_plant.catalogue.dht import frame
from sim_plant.catalogue.rotary_knob import schedule

E, RS, LIGHT = 0x04, 0x01, 0x08


class Lcd:
    """A chip and the bytes a 4-bit driver sends it (each nibble: E high, then low)."""

    def __init__(self, cols=16, rows=2):
        self.chip = CharLcdChip("lcd", "i2c0", 0x27, cols, rows, 100)
        for nibble in (3, 3, 3, 2):  # 8-bit resets, then 4-bit
            self._nibble(nibble, 0)
        self.command(0x28 if rows > 1 else 0x20)
        self.command(0x0C)  # display on
        self.command(0x01)

    def _nibble(self, nibble, rs):
        byte = nibble << 4 | rs | LIGHT
        self.chip.write(0, byte | E)
        self.chip.write(0, byte)

    def command(self, op):
        self._nibble(op >> 4, 0)
        self._nibble(op & 0xF, 0)

    def text(self, s):
        for c in s.encode():
            self._nibble(c >> 4, RS)
            self._nibble(c & 0xF, RS)


def test_a_4_bit_driver_writes_rows_and_the_2004s_third_row_goes_on_from_the_first():
    lcd = Lcd(20, 4)
    lcd.text("abc")
    lcd.command(0x80 | 0x40)
    lcd.text("second")
    lcd.command(0x80 | 0x14)
    lcd.text("third")
    lines = lcd.chip.lines()
    assert [line.rstrip() for line in lines] == ["abc", "second", "third", ""] and len(lines[3]) == 20


def test_entry_mode_cursor_and_display_shift_clear_and_display_off():
    lcd = Lcd()
    lcd.command(0x80 | 5)
    lcd.command(0x04)  # decrement
    lcd.text("xy")
    assert lcd.chip.lines()[0] == "    yx          "
    lcd.command(0x06)
    lcd.command(0x14)  # the cursor right, from 3 (after y at 4) to 4
    lcd.text("z")
    assert lcd.chip.lines()[0] == "    zx          "
    lcd.command(0x18)  # the display one to the left
    assert lcd.chip.lines()[0] == "   zx           "
    lcd.command(0x1C)
    lcd.command(0x1C)  # and two to the right
    assert lcd.chip.lines()[0] == "     zx         "
    lcd.command(0x08)
    assert lcd.chip.lines() == [" " * 16] * 2
    lcd.command(0x0C)
    lcd.command(0x01)
    assert lcd.chip.lines() == [" " * 16] * 2 and lcd.chip.address_counter == 0


def test_a_line_wraps_into_the_other_and_a_custom_character_shows_as_a_block():
    lcd = Lcd()
    lcd.command(0x80 | 0x27)
    lcd.text("AB")  # 0x27 is the first line's last address: B goes to 0x40
    assert lcd.chip.lines()[1].startswith("B")
    lcd.command(0x40)  # CGRAM 0
    lcd.text("\x1f\x11\x1f")
    lcd.command(0x80)
    lcd.text("\x00!")
    assert lcd.chip.lines()[0].startswith(CUSTOM + "!") and lcd.chip.cgram[:3] == [0x1F, 0x11, 0x1F]
    assert lcd.chip.truth(0, None)["lcd_backlight"] == 1


def test_the_buzzer_sounds_only_for_a_pwm_between_0_and_full():
    bz = _Buzzer("bz", 3)
    bz.set_pwm("bz.in", 440, 32768, 100)
    bz.set_pwm("bz.in", 440, 1000, 200)  # the same tone
    bz.set_pwm("bz.in", 880, 1000, 300)
    bz.set_pwm("bz.in", 880, 65535, 400)  # full: a steady level
    bz.set_pwm("bz.in", 1000, 20000, 500)
    bz.set_input("bz.in", 1, 600, None)
    assert bz.tones == [[100, 300, 440], [300, 400, 880], [500, 600, 1000]]
    assert bz.truth(700, None) == {"bz_freq_hz": 0, "bz_tones": 3}
    bz.set_pwm("bz.in", 2000, 100, 800)
    assert len(bz.tones) == 3 and bz.tones[-1] == [800, None, 2000], "the oldest goes past max_tones"


def test_a_detent_is_a_full_quadrature_cycle_clk_leading_clockwise():
    events = schedule("k", [[0.001, 1], [0.01, -1]], [[0.02, 0.03]], 100)
    assert [(t, s, v) for t, s, v, _ in events] == [
        (1000, "k.clk", 0),
        (1100, "k.dt", 0),
        (1200, "k.clk", 1),
        (1300, "k.dt", 1),
        (10000, "k.dt", 0),
        (10100, "k.clk", 0),
        (10200, "k.dt", 1),
        (10300, "k.clk", 1),
        (20000, "k.sw", 0),
        (30000, "k.sw", 1),
    ]
    assert sum(d for *_, d in events) == 0
    with pytest.raises(ValueError, match="released"):
        schedule("k", [], [[0.5, 0.4]], 100)


@pytest.mark.parametrize(
    "model, t, h, sent",
    [
        ("dht22", 21.5, 55.0, (0x02, 0x26, 0x00, 0xD7)),
        ("dht22", -12.3, 80.5, (0x03, 0x25, 0x80, 0x7B)),
        ("dht11", 31.4, 62.0, (62, 0, 31, 0)),
        ("dht11", -5.0, 99.0, (90, 0, 0, 0)),  # clamped to the DHT11's range
    ],
)
def test_the_dht_frame_and_its_checksum(model, t, h, sent):
    data = frame(model, t, h)
    assert tuple(data[:4]) == sent and data[4] == sum(sent) & 0xFF

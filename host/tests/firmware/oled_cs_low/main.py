# An SSD1306 on SPI under the published micropython-ssd1306 driver, its chip select
# held low for good: the firmware drives CS_HOLD low once and hands the driver another pin
# (DRIVER_CS) to toggle. Which of the two the rig wires to the display's CS (or neither,
# with the display's CS tied low) is the rig's: the picture must be the same each way.
from machine import SPI, Pin

import framebuf
import ssd1306

hold = Pin(15, Pin.OUT, value=0)  # CS_HOLD
spi = SPI(1, baudrate=8_000_000, sck=Pin(14), mosi=Pin(13), miso=Pin(12))
oled = ssd1306.SSD1306_SPI(128, 32, spi, Pin(4), Pin(5), Pin(16))  # dc, res, DRIVER_CS
for text in ("first", "SPI 32"):  # (two pictures: each show() after the first goes on in one selection)
    oled.fill(0)
    oled.text(text, 0, 8, 1)
    oled.show()

ref = bytearray(128 * 32 // 8)
fb = framebuf.FrameBuffer(ref, 128, 32, framebuf.MONO_VLSB)
fb.text("SPI 32", 0, 8, 1)
print("R same", int(ref == oled.buffer))
print("R ref", list(ref))

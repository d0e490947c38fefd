# A colour display's way of writing its frame (the Pico-Go's ST7789 demos: one
# spi.write of the whole RGB565 buffer, 240 x 135 x 2 = 64,800 bytes), here into the
# published micropython-ssd1306 driver's SPI panel: its buffer replaced by a longer one,
# which show() sends in one spi.write. The panel's pointer wraps round its 512 bytes, so
# the glass keeps each address's last byte of the write.
import time
from machine import SPI, Pin

import ssd1306

N = 9000

spi = SPI(1, baudrate=8_000_000, sck=Pin(14), mosi=Pin(13), miso=Pin(12))
panel = ssd1306.SSD1306_SPI(128, 32, spi, Pin(4), Pin(5), Pin(15))
big = bytearray(N)
for i in range(N):
    big[i] = (i * 7 + i // 512) & 0xFF
panel.buffer = big
t0 = time.ticks_us()
panel.show()
print("R us", time.ticks_diff(time.ticks_us(), t0))
print("R n", N)

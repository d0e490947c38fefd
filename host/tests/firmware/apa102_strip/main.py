# A strip of 3 APA102 LEDs driven as the public DotStar drivers drive it (dotstar.py here):
# red, green, blue at full brightness; 100 ms later all dim white at brightness 4; then the
# start frame and the first LED sent in two writes, and a stray byte where a frame starts.
import time
from machine import SPI, Pin

import dotstar

spi = SPI(1, baudrate=4_000_000, sck=Pin(14), mosi=Pin(13), miso=Pin(12))
leds = dotstar.DotStar(spi, 3)
leds[0] = (255, 0, 0)
leds[1] = (0, 255, 0)
leds[2] = (0, 0, 255)
leds.show()
time.sleep_ms(100)
leds.brightness = 4
leds.fill((16, 16, 16))
leds.show()
time.sleep_ms(100)
spi.write(b"\x00\x00")
spi.write(b"\x00\x00\xff\x01\x02")
spi.write(b"\x03\x42")
time.sleep_ms(100)
print("R done", 1)

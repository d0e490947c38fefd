# The 3pi+ 2040's display and RGB LEDs, in the style of Pololu's rgb_demo.py and its menu's
# screens (written here, not copied): three screens in turn, 300 ms each, the six LEDs one
# colour a screen; after each show the frame buffer goes to the console in hex (the test
# holds the report's pictures to it). The board support is the kitbot package (lib/kitbot:
# the SH1106 on SPI0 with its clock on GP2, the APA102 LEDs on SPI0 with theirs on GP6).
import time
from binascii import hexlify

from kitbot.display import Display
from kitbot.rgb_leds import RGBLEDs

display = Display()
leds = RGBLEDs(count=6)
leds.show()  # (all off; as the library's RGBLEDs() does, its show() takes GP6 back from the SPI)
COLOURS = ((255, 0, 0), (0, 255, 0), (0, 0, 255))
for screen, rgb in enumerate(COLOURS):
    display.fill(0)
    display.text("3pi+ 2040", 0, 0)
    display.text("screen %d" % screen, 0, 16)
    display.fill_rect(8 + 40 * screen, 40, 24, 16, 1)
    display.show()
    for led in range(6):
        leds.set(led, rgb)
    leds.show()
    print("shown", screen, time.ticks_ms(), hexlify(display.buffer).decode())
    time.sleep_ms(300)
print("done")

# Modules the loop provides, and files of the same names the firmware brings: which one
# an import gives is the board's choice (an ESP32: '', '.frozen', '/lib', built-ins).
import rp2
import select

import dht
import esp
import neopixel

found = {m.__name__: getattr(m, "ORIGIN", "board") for m in (neopixel, dht, esp, rp2, select)}
print("R origins", repr(found))
print("R dht", repr(hasattr(dht, "DHT22")))

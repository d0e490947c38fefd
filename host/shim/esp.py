# esp: the ESP ports' module, as far as a firmware in the loop uses it: dht_readinto (the
# dht module's read, host/shim/_hildht.py) and osdebug (a boot.py's esp.osdebug(None):
# nothing to silence here). Other names raise AttributeError, as on a port without them.
# Only an ESP32 board has it: elsewhere `import esp` fails, as on an RP2040.
import sys

if not sys.platform.startswith("esp"):
    raise ImportError(
        "no module named 'esp': the loop has it for an ESP32 board only (its dht_readinto and osdebug; docs/shim.md)"
    )

from _hildht import dht_readinto  # noqa: E402, F401  (the port's name)


def osdebug(level, *args):
    pass

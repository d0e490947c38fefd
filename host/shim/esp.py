# esp: the ESP ports' module, as far as a firmware in the loop uses it: dht_readinto (the
# dht module's read, host/shim/_hildht.py) and osdebug (a boot.py's esp.osdebug(None):
# nothing to silence here). Other names raise AttributeError, as on a port without them.
from _hildht import dht_readinto  # noqa: F401  (the port's name)


def osdebug(level, *args):
    pass

# The names each version's ESP32 port has in network and socket (host/tests/test_network.py):
# ESP-IDF's constants follow the IDF each MicroPython version is built with.
import network
import socket
import sys

print("R version", tuple(sys.implementation.version[:2]))
print("R auth_max", network.AUTH_MAX)
NAMES = ("SEC_DPP", "SEC_WPA3_ENT", "SEC_WPA_ENT", "PROTOCOL_DEFAULT")
print("R sec", sorted(n for n in NAMES if hasattr(network.WLAN, n)))
print("R msg", [getattr(socket, n, None) for n in ("MSG_PEEK", "MSG_DONTWAIT")])
sys.exit()

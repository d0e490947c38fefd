# dht: DHT11 / DHT22 sensors (micropython-lib's drivers/sensor/dht, which the ESP32, ESP8266
# and RP2 ports freeze), as that module is: measure() reads 5 bytes with the port's
# dht_readinto and checks their checksum; DHT11 reads whole degrees and percent, DHT22
# tenths, its temperature negative with the top bit set.
import sys

if sys.platform.startswith("esp"):
    from esp import dht_readinto
elif sys.platform == "rp2":
    from rp2 import dht_readinto
else:
    from machine import dht_readinto


class DHTBase:
    def __init__(self, pin):
        self.pin = pin
        self.buf = bytearray(5)

    def measure(self):
        buf = self.buf
        dht_readinto(self.pin, buf)
        if (buf[0] + buf[1] + buf[2] + buf[3]) & 0xFF != buf[4]:
            raise Exception("checksum error")


class DHT11(DHTBase):
    def humidity(self):
        return self.buf[0]

    def temperature(self):
        return self.buf[2]


class DHT22(DHTBase):
    def humidity(self):
        return (self.buf[0] << 8 | self.buf[1]) * 0.1

    def temperature(self):
        t = ((self.buf[2] & 0x7F) << 8 | self.buf[3]) * 0.1
        if self.buf[2] & 0x80:
            t = -t
        return t

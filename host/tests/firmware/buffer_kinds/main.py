# Every bus method that takes or fills a buffer, given each kind of object a board's C meets:
# each call's outcome printed as `R method:kind (outcome, detail)`, the detail what the
# buffer holds after a fill (its raw bytes, and an array's items) or what the chip holds
# after a write (test_buffer_kinds.py holds the expected table).
import struct
import time
from array import array
from machine import I2C, SPI, UART, Pin, SoftI2C, SoftSPI, bitstream

PAYLOAD = b"\x12\x21"  # a register's address is sent first, then these


def write_kinds(reg=None):
    """Two bytes in each kind: the register's address then its value (0x12), or with no
    register the value and the next register's."""
    data = PAYLOAD if reg is None else bytes((reg,)) + PAYLOAD[:1]
    (h,) = struct.unpack("<h", data)
    return (
        ("bytes", data),
        ("bytearray", bytearray(data)),
        ("str", data.decode()),
        ("memoryview", memoryview(bytearray(data))),
        ("memoryview_slice", memoryview(bytearray(b"\xee" + data + b"\xee"))[1:3]),
        ("memoryview_bytes", memoryview(data)),
        ("array_B", array("B", data)),
        ("array_h", array("h", [h])),
        ("memoryview_array_h", memoryview(array("h", [0, h]))[1:]),
        ("list", list(data)),
        ("int", 2),
        ("none", None),
    )


def fill_kinds():
    return (
        ("bytes", bytes(4)),
        ("bytearray", bytearray(4)),
        ("str", "abcd"),
        ("memoryview", memoryview(bytearray(4))),
        ("memoryview_slice", memoryview(bytearray(6))[1:5]),
        ("memoryview_bytes", memoryview(bytes(4))),
        ("array_B", array("B", [0] * 4)),
        ("array_h", array("h", [0, 0])),
        ("array_i", array("i", [0])),
        ("array_f", array("f", [0])),
        ("memoryview_array_h", memoryview(array("h", [0, 0, 0]))[1:]),
        ("list", [0] * 4),
        ("int", 4),
    )


def show(name, call, buf, after):
    """call(buf), then the outcome: the exception raised, or after(call's result, buf)."""
    try:
        got = call(buf)
    except Exception as e:
        print("R %s %r" % (name, (type(e).__name__, str(e))))
        return
    print("R %s %r" % (name, ("ok", after(got, buf))))


def raw(_result, buf):
    kind = type(buf).__name__
    try:
        items = list(buf)
    except TypeError:
        items = None
    return (bytes(buf), items if kind == "array" else None)


def check_i2c(name, bus, addr, reg):
    bus.writeto_mem(addr, reg, b"\x00\x00\x00\x00")
    bus.writeto_mem(addr, reg, PAYLOAD)
    print("R %s.ref %r" % (name, bus.readfrom_mem(addr, reg, 4)))

    def read_back(_result, _buf):
        got = bus.readfrom_mem(addr, reg, 1)
        bus.writeto_mem(addr, reg, b"\x00")
        return got

    for kind, buf in write_kinds(reg):
        bus.writeto_mem(addr, reg, b"\x00")
        show("%s.writeto:%s" % (name, kind), lambda b: bus.writeto(addr, b), buf, read_back)
    for kind, buf in write_kinds(reg):
        bus.writeto_mem(addr, reg, b"\x00")
        show("%s.writevto:%s" % (name, kind), lambda b: bus.writevto(addr, (b,)), buf, read_back)
    for kind, buf in write_kinds():
        bus.writeto_mem(addr, reg, b"\x00")
        show("%s.writeto_mem:%s" % (name, kind), lambda b: bus.writeto_mem(addr, reg, b), buf, read_back)
    bus.writeto_mem(addr, reg, PAYLOAD)
    for kind, buf in fill_kinds():
        show("%s.readfrom_mem_into:%s" % (name, kind), lambda b: bus.readfrom_mem_into(addr, reg, b), buf, raw)

    def into(buf):
        bus.writeto(addr, bytes((reg,)), False)
        return bus.readfrom_into(addr, buf)

    for kind, buf in fill_kinds():
        show("%s.readfrom_into:%s" % (name, kind), into, buf, raw)


i2c = I2C(0, scl=Pin(18), sda=Pin(19), freq=400_000)
check_i2c("i2c", i2c, 0x6A, 0x10)  # LSM6DSOX: CTRL1_XL, CTRL2_G
soft = SoftI2C(scl=Pin(5), sda=Pin(4))
check_i2c("softi2c", soft, 0x68, 0x19)  # MPU-6050: SMPLRT_DIV, CONFIG
print("R i2c.writeto:empty_str %r" % (i2c.writeto(0x6A, ""),))
try:
    i2c.writevto(0x6A, iter((b"\x10",)))
except Exception as e:
    print("R i2c.writevto:iterator %r" % ((type(e).__name__, str(e)),))
for kind, buf in write_kinds(0x10):
    show("softi2c.write:%s" % kind, lambda b: soft.write(b), buf, lambda n, _b: n)
for kind, buf in fill_kinds():
    show("softi2c.readinto:%s" % kind, lambda b: soft.readinto(b), buf, lambda _n, b: len(bytes(b)))

cs = Pin(15, Pin.OUT, value=1)
spi = SPI(1, baudrate=1_000_000, sck=Pin(14), mosi=Pin(13), miso=Pin(12))


def spi_write(buf):
    cs(0)
    spi.write(b"\x10\x00\x00\x00\x00")
    cs(1)
    cs(0)
    try:
        spi.write(buf)
    finally:
        cs(1)


def spi_read_back(_result, _buf):
    cs(0)
    got = spi.read(2, 0x90)[1:]
    cs(1)
    return got


for kind, buf in write_kinds(0x10):
    show("spi.write:%s" % kind, lambda b: spi_write(b), buf, spi_read_back)
cs(0)
spi.write(b"\x10" + PAYLOAD)
cs(1)


def spi_into(buf):
    cs(0)
    try:
        spi.write(b"\x90")
        return spi.readinto(buf)
    finally:
        cs(1)


def spi_write_into(buf):
    cs(0)
    try:
        spi.write(b"\x90")
        return spi.write_readinto(b"\x00\x00\x00\x00", buf)
    finally:
        cs(1)


for kind, buf in fill_kinds():
    show("spi.readinto:%s" % kind, lambda b: spi_into(b), buf, raw)
for kind, buf in fill_kinds():
    show("spi.write_readinto:%s" % kind, lambda b: spi_write_into(b), buf, raw)
for kind, buf in write_kinds(0x10):  # (the lengths compared in bytes)
    show("spi.write_readinto_src:%s" % kind, lambda b: spi.write_readinto(b, bytearray(2)), buf, lambda _n, _b: None)
softspi = SoftSPI(baudrate=100_000, sck=Pin(5), mosi=Pin(4), miso=Pin(2))
for kind, buf in write_kinds(0x10):
    show("softspi.write:%s" % kind, lambda b: softspi.write(b), buf, lambda _n, _b: None)
for kind, buf in fill_kinds():
    show("softspi.readinto:%s" % kind, lambda b: softspi.readinto(b, 0x1FF), buf, raw)

uart = UART(1, baudrate=115200, tx=Pin(26), rx=Pin(27), timeout=0)
for kind, buf in write_kinds(0x10):
    show("uart.write:%s" % kind, lambda b: uart.write(b), buf, lambda n, _b: n)
for kind, buf in fill_kinds():
    show("uart.readinto:%s" % kind, lambda b: uart.readinto(b), buf, lambda n, _b: n)

led = Pin(25, Pin.OUT)
for kind, buf in write_kinds(0x10):
    show("bitstream:%s" % kind, lambda b: bitstream(led, 0, (400, 850, 800, 450), b), buf, lambda n, _b: n)
time.sleep_ms(1)
print("R done", True)

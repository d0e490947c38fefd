"""Buffers as the ports take them (docs/shim.md, "Buffers"): every bus method that takes or
fills a buffer, given each kind of object, against the outcome the port's C gives. A C
method takes its buffer with mp_get_buffer_raise (py/obj.c): MP_BUFFER_READ takes anything
with the buffer protocol, str included (py/objstr.c, mp_obj_str_get_buffer), as its bytes;
MP_BUFFER_WRITE refuses bytes, str and a memoryview of either (py/objarray.c,
array_get_buffer); both refuse a list, an int or None with
TypeError("object with buffer protocol required"). An array is read and filled byte by byte
in the machine's order (little-endian)."""

import ast
import shutil
import struct
from pathlib import Path

import pytest

from host.tests.conftest import FIRMWARE, bench_app
from host.tests.test_buses import bench, run

pytestmark = pytest.mark.hil

NO_BUFFER = ("TypeError", "object with buffer protocol required")  # py/obj.c, mp_get_buffer_raise

WRITE_KINDS = (  # MP_BUFFER_READ: what a write takes
    "bytes", "bytearray", "str", "memoryview", "memoryview_slice", "memoryview_bytes",
    "array_B", "array_h", "memoryview_array_h",
)  # fmt: skip
WRITE_REFUSED = ("list", "int", "none")
FILL_KINDS = (  # MP_BUFFER_WRITE: what a fill takes
    "bytearray",
    "memoryview",
    "memoryview_slice",
    "array_B",
    "array_h",
    "array_i",
    "array_f",
    "memoryview_array_h",
)
FILL_REFUSED = ("bytes", "str", "memoryview_bytes", "list", "int")

# method -> the C function that takes its buffer
WRITES = {
    "i2c.writeto": "extmod/machine_i2c.c machine_i2c_writeto",
    "i2c.writevto": "extmod/machine_i2c.c machine_i2c_writevto",
    "i2c.writeto_mem": "extmod/machine_i2c.c machine_i2c_writeto_mem",
    "softi2c.writeto": "extmod/machine_i2c.c machine_i2c_writeto",
    "softi2c.writevto": "extmod/machine_i2c.c machine_i2c_writevto",
    "softi2c.writeto_mem": "extmod/machine_i2c.c machine_i2c_writeto_mem",
    "softi2c.write": "extmod/machine_i2c.c machine_i2c_write",
    "spi.write": "extmod/machine_spi.c mp_machine_spi_write",
    "spi.write_readinto_src": "extmod/machine_spi.c mp_machine_spi_write_readinto",
    "softspi.write": "extmod/machine_spi.c mp_machine_spi_write",
    "uart.write": "py/stream.c stream_write_method",
    "bitstream": "extmod/machine_bitstream.c machine_bitstream_",
}
FILLS = {
    "i2c.readfrom_into": "extmod/machine_i2c.c machine_i2c_readfrom_into",
    "i2c.readfrom_mem_into": "extmod/machine_i2c.c machine_i2c_readfrom_mem_into",
    "softi2c.readfrom_into": "extmod/machine_i2c.c machine_i2c_readfrom_into",
    "softi2c.readfrom_mem_into": "extmod/machine_i2c.c machine_i2c_readfrom_mem_into",
    "softi2c.readinto": "extmod/machine_i2c.c machine_i2c_readinto",
    "spi.readinto": "extmod/machine_spi.c mp_machine_spi_readinto",
    "spi.write_readinto": "extmod/machine_spi.c mp_machine_spi_write_readinto",
    "softspi.readinto": "extmod/machine_spi.c mp_machine_spi_readinto",
    "uart.readinto": "py/stream.c stream_readinto",
}
# the chip's register after a write (the value written in every kind): reads back 0x12
READ_BACK = {"i2c.writeto", "i2c.writevto", "i2c.writeto_mem", "softi2c.writeto", "softi2c.writevto",
             "softi2c.writeto_mem", "spi.write"}  # fmt: skip
# the bytes filled, the same in every kind as in a bytearray
COMPARED = {"i2c.readfrom_into", "i2c.readfrom_mem_into", "softi2c.readfrom_into", "softi2c.readfrom_mem_into",
            "spi.readinto", "spi.write_readinto", "softspi.readinto"}  # fmt: skip

TABLE = [(m, k, "ok") for m in WRITES for k in WRITE_KINDS]
TABLE += [(m, k, NO_BUFFER) for m in WRITES for k in WRITE_REFUSED]
TABLE += [(m, k, "ok") for m in FILLS for k in FILL_KINDS]
TABLE += [(m, k, NO_BUFFER) for m in FILLS for k in FILL_REFUSED]

# ports/rp2/rp2_pio.c: put reads items of 'B' (bytes, str, bytearray), 'H', 'I' and refuses
# other typecodes at the first item; a non-buffer must convert to an int
# (mp_obj_get_int_truncated). get fills items of 'b', 'h', 'i' whatever their sign, refuses
# other typecodes once the first word is taken, and returns the buffer. (shift 1; the
# program gives back each word: put 0x12348081, 0xFFFFFFFE before each get)
PIO_TABLE = {
    "put:bytes": ("ok", [2, 260]),
    "put:bytearray": ("ok", [2, 260]),
    "put:str": ("ok", [0x61 << 1, 0x62 << 1]),
    "put:memoryview_slice": ("ok", [2, 260]),
    "put:array_B": ("ok", [2, 260]),
    "put:array_H": ("ok", [0x2468, 0x10002]),
    "put:array_I": ("ok", [0x2468ACF0]),
    "put:memoryview_array_H": ("ok", [0x2468, 0x10002]),
    "put:array_b": ("ValueError", "unsupported buffer type"),
    "put:array_h": ("ValueError", "unsupported buffer type"),
    "put:array_i": ("ValueError", "unsupported buffer type"),
    "put:array_h_empty": ("ok", []),
    "put:list": ("TypeError", "can't convert list to int"),
    "put:float": ("TypeError", "can't convert float to int"),
    "put:int": ("ok", [0x3FE]),
    "get:bytearray": ("ok", (True, b"\x40\xff", None, [])),
    "get:memoryview_slice": ("ok", (True, b"\x40\xff", None, [])),
    "get:array_b": ("ok", (True, b"\x40\xff", [0x40, -1], [])),
    "get:array_B": ("ok", (True, b"\x40\xff", [0x40, 0xFF], [])),
    "get:array_h": ("ok", (True, b"\x40\x40\xff\xff", [0x4040, -1], [])),
    "get:array_H": ("ok", (True, b"\x40\x40\xff\xff", [0x4040, 0xFFFF], [])),
    "get:array_i": ("ok", (True, struct.pack("<2I", 0x091A4040, 0x7FFFFFFF), [0x091A4040, 0x7FFFFFFF], [])),
    "get:array_I": ("ok", (True, struct.pack("<2I", 0x091A4040, 0x7FFFFFFF), [0x091A4040, 0x7FFFFFFF], [])),
    "get:memoryview_array_h": ("ok", (True, b"\x40\x40\xff\xff", None, [])),
    "get:array_f": ("ValueError", "unsupported buffer type"),
    "get:array_q": ("ValueError", "unsupported buffer type"),
    "get:array_h_empty": ("ok", (True, b"", [], [0x12348081, 0xFFFFFFFE])),  # (returns at once)
    "get:bytes": NO_BUFFER,
    "get:str": NO_BUFFER,
    "get:list": NO_BUFFER,
}


def outcomes(console: str) -> dict:
    out = {}
    for line in console.splitlines():
        if line.startswith("R "):
            _, name, value = line.split(" ", 2)
            out[name] = ast.literal_eval(value.replace("nan", "None"))
    return out


@pytest.fixture(scope="module")
def table_run():
    from host.pytest_plugin import rig_from_keywords

    rig = rig_from_keywords(bench(), main_dir=FIRMWARE / "buffer_kinds", allow_exit=True)
    rig.start()
    try:
        rig.run_for(2.0)
    finally:
        rig.stop()
    return rig.console, outcomes(rig.console)


@pytest.mark.parametrize("method, kind, expected", TABLE, ids=[f"{m}:{k}" for m, k, _ in TABLE])
def test_each_bus_method_takes_each_kind_of_buffer_as_the_ports_c_does(table_run, method, kind, expected):
    console, r = table_run
    assert r.get("done"), console[-2000:]
    got = r["%s:%s" % (method, kind)]
    where = WRITES.get(method) or FILLS[method]
    if expected != "ok":
        assert got == expected, f"{method}({kind}): expected {expected} as {where} raises, got {got}"
        return
    assert got[0] == "ok", f"{method}({kind}): expected it taken as {where} takes it, got {got}"
    if method in READ_BACK:  # (writeto_mem: the value then the next register's, as the chip takes them)
        same = r["%s:bytes" % method][1]
        assert got[1] == same, f"{method}({kind}): the chip's register holds {got[1]!r}, {same!r} after bytes"
        if not method.endswith("writeto_mem"):
            assert got[1] == b"\x12", f"{method}({kind}): the chip's register holds {got[1]!r}, not 0x12"
    if method in COMPARED:
        raw, items = got[1]
        assert raw == r["%s:bytearray" % method][1][0], f"{method}({kind}): filled otherwise than a bytearray"
        assert len(raw) == 4
        if items is not None and kind != "array_f":
            code = kind[-1]
            assert items == list(struct.unpack("<%d%s" % (4 // struct.calcsize(code), code), raw)), (
                f"{method}({kind}): items {items} are not the bytes {raw!r} little-endian"
            )


def test_writes_count_bytes_and_a_str_clears_the_bus_as_on_a_board(table_run):
    """A str is a buffer (py/objstr.c): writeto(0, "") is a bus clear; an array's length is its bytes."""
    _console, r = table_run
    assert r["i2c.writeto:empty_str"] == 0
    assert r["uart.write:array_h"] == ("ok", 2) and r["uart.write:str"] == ("ok", 2)
    assert r["softi2c.readinto:array_i"] == ("ok", 4)
    assert r["i2c.writevto:iterator"] == ("TypeError", "object 'iterator' isn't a tuple or list")  # mp_obj_get_array


def test_an_array_h_is_filled_byte_by_byte_little_endian(table_run):
    _console, r = table_run
    assert r["softi2c.readfrom_mem_into:array_h"] == ("ok", (b"\x12\x21\x00\x00", [0x2112, 0]))


def test_pio_put_and_get_take_buffers_by_their_typecode_as_rp2_pio_c(make_rig):
    app = bench_app("buffers", {"body": "bench", "parts": []}, board="rpi_pico_bench")
    rig = make_rig(app, main_dir=FIRMWARE / "buffer_kinds_pio", allow_exit=True)
    rig.run_for(1.0)
    rig.stop()
    r = outcomes(rig.console)
    assert r.get("done"), rig.console[-2000:]
    for name, expected in PIO_TABLE.items():
        assert r[name] == expected, f"StateMachine.{name}: expected {expected} (ports/rp2/rp2_pio.c), got {r[name]}"


def test_an_imu_read_into_an_array_h_as_micropython_libs_lsm6dsox_driver_reads_it(make_rig):
    """micropython-lib's lsm6dsox driver reads each vector into a memoryview of one
    array('h', 3) (readfrom_mem_into); a board fills its 6 bytes, little-endian: +1 g on z
    flat, as the same registers read as bytes say."""
    rig, r = run(make_rig, "imu_array_reads", duration_s=0.5)
    assert r["accel"] == tuple(r["accel_bytes"]), rig.console
    ax, ay, az = r["accel"]
    assert abs(ax) < 0.01 and abs(ay) < 0.01 and abs(az - 1.0) < 0.01, r["accel"]
    assert r["accel_array"] == r["accel_readfrom_into"] == [round(v * 8192) for v in r["accel"]]
    assert all(abs(a - b) < 0.01 for a, b in zip(r["spi_accel"], r["accel"])), r["spi_accel"]


DHT_READS = """\
import time
from array import array
from machine import Pin
from rp2 import dht_readinto

for kind, buf in (("bytearray", bytearray(5)), ("array_B", array("B", [0] * 5)),
                  ("memoryview_array_h", memoryview(array("h", [0, 0, 0]))), ("array_h2", array("h", [0, 0])),
                  ("bytes", bytes(5)), ("list", [0] * 5)):
    try:
        dht_readinto(Pin(28), buf)
        print("R", kind, repr(("ok", bytes(buf)[:5])))
    except Exception as e:
        print("R", kind, repr((type(e).__name__, str(e))))
    time.sleep_ms(1000)
print("R done", True)
while True:
    time.sleep_ms(100)
"""


def test_dht_readinto_fills_any_writable_buffer_of_5_bytes_as_dht_c(make_rig, tmp_path):
    """drivers/dht/dht.c, dht_readinto: MP_BUFFER_WRITE, at least 5 bytes ("buffer too small")."""
    folder = tmp_path / "dht_kinds"
    shutil.copytree(Path(__file__).parent / "wokwi_projects" / "pico_dht11", folder)
    (folder / "main.py").write_text(DHT_READS)
    rig = make_rig(str(folder))
    rig.run_for(9.0)
    r = outcomes(rig.console)
    assert r.get("done"), rig.console[-2000:]
    reading = bytes((62, 0, 31, 0, 93))
    assert r["bytearray"] == r["array_B"] == r["memoryview_array_h"] == ("ok", reading)
    assert r["array_h2"] == ("ValueError", "buffer too small")  # (4 bytes)
    assert r["bytes"] == r["list"] == NO_BUFFER

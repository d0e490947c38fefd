# ruff: noqa: F821  (a PIO body's names exist only while rp2.asm_pio assembles it)
# StateMachine.put and get given each kind of buffer: a program that gives back each word
# it is given; each outcome printed as `R method:kind (outcome, detail)`.
import rp2
import time
from array import array


@rp2.asm_pio()
def echo():
    pull()
    mov(isr, osr)
    push()


sm = rp2.StateMachine(0, echo, freq=1_000_000)
sm.active(1)


def show(name, call, buf, after):
    """call(buf), then the outcome: the exception raised, or after(call's result, buf)."""
    try:
        got = call(buf)
    except Exception as e:
        print("R %s %r" % (name, (type(e).__name__, str(e))))
        return
    print("R %s %r" % (name, ("ok", after(got, buf))))


def drain():
    words = []
    time.sleep_ms(1)
    while sm.rx_fifo():
        words.append(sm.get())
    return words


PUT = (
    ("bytes", b"\x01\x82"),
    ("bytearray", bytearray(b"\x01\x82")),
    ("str", "ab"),
    ("memoryview_slice", memoryview(bytearray(b"\x00\x01\x82\x00"))[1:3]),
    ("array_B", array("B", [1, 0x82])),
    ("array_H", array("H", [0x1234, 0x8001])),
    ("array_I", array("I", [0x12345678])),
    ("memoryview_array_H", memoryview(array("H", [9, 0x1234, 0x8001]))[1:]),
    ("array_b", array("b", [1, 2])),
    ("array_h", array("h", [1, 2])),
    ("array_i", array("i", [1])),
    ("array_h_empty", array("h")),
    ("list", [1, 2]),
    ("float", 1.5),
    ("int", 0x1FF),
)
for kind, value in PUT:
    show("put:%s" % kind, lambda v: sm.put(v, 1), value, lambda _r, _v: drain())

GET = (
    ("bytearray", bytearray(2)),
    ("memoryview_slice", memoryview(bytearray(4))[1:3]),
    ("array_b", array("b", [0, 0])),
    ("array_B", array("B", [0, 0])),
    ("array_h", array("h", [0, 0])),
    ("array_H", array("H", [0, 0])),
    ("array_i", array("i", [0, 0])),
    ("array_I", array("I", [0, 0])),
    ("memoryview_array_h", memoryview(array("h", [7, 0, 0]))[1:]),
    ("array_f", array("f", [0, 0])),
    ("array_q", array("q", [0, 0])),
    ("array_h_empty", array("h")),
    ("bytes", bytes(2)),
    ("str", "ab"),
    ("list", [0, 0]),
)


def got(result, buf):
    left = drain()
    return (result is buf, bytes(buf), list(buf) if type(buf).__name__ == "array" else None, left)


for kind, buf in GET:
    drain()
    sm.put(array("I", [0x1234_8081, 0xFFFF_FFFE]))

    show("get:%s" % kind, lambda b: sm.get(b, 1), buf, got)
print("R done", True)

# The Pin constants, names and machine.freq() as the board's port has them, printed for the
# test to compare with the port's C (host/tests/test_pin_family.py).
import machine
from machine import Pin

NAMES = ("IN", "OUT", "OPEN_DRAIN", "ALT", "ALT_OPEN_DRAIN", "PULL_UP", "PULL_DOWN", "IRQ_RISING", "IRQ_FALLING")
NAMES += ("ALT_SPI", "ALT_UART", "ALT_I2C", "ALT_PWM", "ALT_SIO", "ALT_PIO0", "ALT_PIO1", "ALT_GPCK", "ALT_USB")
print("R consts", {n: getattr(Pin, n) for n in NAMES if hasattr(Pin, n)})
print("R has_cpu", hasattr(Pin, "cpu"))


def outcome(fn):
    try:
        return repr(fn())
    except Exception as e:  # noqa: BLE001  (the port's exception, by type and text)
        return "%s: %s" % (type(e).__name__, e)


print("R led", repr(outcome(lambda: Pin("LED") is Pin(25))))
print("R gp14", repr(outcome(lambda: Pin("GP14") is Pin(14) and Pin.board.GP14 is Pin(14))))
print("R gpio29", repr(outcome(lambda: Pin.cpu.GPIO29 is Pin("GPIO29"))))
print("R unknown", repr(outcome(lambda: Pin("NOPE"))))
print("R board_gp23", repr(outcome(lambda: Pin.board.GP23)))
print("R alt_kw", repr(outcome(lambda: Pin(6, Pin.OUT, alt=1))))
print("R bad_af", repr(outcome(lambda: Pin(6).init(mode=Pin.ALT, alt=8))))
print("R irq_hard", repr(outcome(lambda: Pin(5, Pin.IN).irq(lambda p: None, Pin.IRQ_RISING, hard=True) and "ok")))
print("R irq_hard_pos", repr(outcome(lambda: Pin(5, Pin.IN).irq(lambda p: None, Pin.IRQ_RISING, None) and "ok")))
print("R irq_wake", repr(outcome(lambda: Pin(5, Pin.IN).irq(lambda p: None, Pin.IRQ_RISING, wake=None) and "ok")))
Pin(5).irq(None)
print("R freq", machine.freq())
for hz in (133_000_000, 200_000_000, 240_000_000, 80_000_000, 123_456_789):
    print("R set_%d" % hz, (outcome(lambda hz=hz: machine.freq(hz)), machine.freq()))
print("R peri", repr(outcome(lambda: machine.freq(125_000_000, 12_000_000))))

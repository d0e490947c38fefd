# The board's identity and the entry file's place, as firmware and unittest look at them.
import machine
import sys

print("R platform", repr(sys.platform))
print("R machine", repr(sys.implementation._machine))
print("R argv", repr(sys.argv[0].split("/")[-1]))
try:
    import rp2

    blink = rp2.asm_pio(set_init=rp2.PIO.OUT_LOW)(lambda: set(pins, 1))  # noqa: F821
    print("R rp2", [rp2.PIO.OUT_LOW, list(blink[0])])
except ImportError:
    print("R rp2", None)
import __main__  # noqa: E402

MARKER = 42
print("R main_module", getattr(__main__, "MARKER", None))
machine.mem32[0x3FF44004] = 0x12345678
print("R mem", [hex(machine.mem32[0x3FF44004]), machine.mem8[0x3FF44005], repr(machine.mem16)])
try:
    machine.mem16[1]
except ValueError:
    print("R mem_align", repr("ValueError"))
rtc = machine.RTC()
rtc.datetime((2024, 2, 29, 3, 23, 59, 58, 0))
import time  # noqa: E402

time.sleep(3)
print("R rtc", [list(rtc.datetime()[:7]), time.localtime()[:6]])

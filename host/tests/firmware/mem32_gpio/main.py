# GPIOs through their registers (RP2040 datasheet 2.3.1.7 SIO, 2.19.6.1 IO_BANK0): GP16
# driven through SIO's GPIO_OUT and GPIO_OE, GP17 a button on the pin of an LED, read
# with the LED's driver let go through the pin's output-enable override.
import time
from machine import Pin, mem32

IO_BANK0 = 0x40014000
SIO = 0xD0000000
GPIO_IN, OUT, OUT_SET, OUT_CLR, OUT_XOR = SIO + 0x04, SIO + 0x10, SIO + 0x14, SIO + 0x18, SIO + 0x1C
OE, OE_SET = SIO + 0x20, SIO + 0x24
FUNC_SIO = 5
OEOVER_DISABLE = 2 << 12
INOVER_INVERT = 1 << 16


def ctrl(n):
    return IO_BANK0 + 8 * n + 4


mem32[ctrl(16)] = FUNC_SIO
mem32[OE_SET] = 1 << 16
mem32[OUT_SET] = 1 << 16
print("R set", [mem32[OUT] >> 16 & 1, mem32[OE] >> 16 & 1, Pin(16).value()])
time.sleep_ms(10)
mem32[OUT_XOR] = 1 << 16
time.sleep_ms(10)
mem32[OUT] = 1 << 16
time.sleep_ms(10)
mem32[OUT_CLR] = 1 << 16
Pin(16).value(1)  # (the other way: Pin.value shows in GPIO_OUT)
print("R pin_value", mem32[OUT] >> 16 & 1)

reads = []
for _ in range(4):
    time.sleep_ms(25)
    was = mem32[ctrl(17)]  # the LED's driver let go, the pad read, the LED's control back
    mem32[ctrl(17)] = was & ~(1 << 12) | OEOVER_DISABLE
    reads.append(mem32[ctrl(17) - 4] >> 17 & 1)  # GPIO17_STATUS's INFROMPAD
    mem32[ctrl(17)] = was
print("R button", reads)
print("R gpio_in", mem32[GPIO_IN] >> 17 & 1)
mem32[ctrl(17)] = FUNC_SIO | OEOVER_DISABLE
mem32[ctrl(17)] = FUNC_SIO | OEOVER_DISABLE | INOVER_INVERT
print("R inverted", [mem32[GPIO_IN] >> 17 & 1, hex(mem32[ctrl(17)])])
mem32[ctrl(3)] = FUNC_SIO  # (GP3 is wired to nothing: driven all the same)
mem32[OE_SET] = 1 << 3
mem32[OUT_SET] = 1 << 3
print("R unwired", [mem32[GPIO_IN] >> 3 & 1, mem32[ctrl(3) - 4] >> 17 & 1])
print("R funcsel", [mem32[ctrl(16)] & 0x1F, mem32[ctrl(2)] & 0x1F])
print("R unknown", [mem32[SIO + 0x100], mem32[SIO + 0x100], mem32[0x40054000]])

# The 3pi+ 2040's yellow LED and button A share GP25: the LED (from 3V3) is lit while the
# pin drives low, and button A is read with the pin's output disabled for a moment through
# GPIO25_CTRL's OEOVER (IO_BANK0), its pad level from GPIO25_STATUS's INFROMPAD, as the
# kit's library reads it. Written in that library's style: a YellowLED class on Pin(25,
# Pin.OUT), a ButtonA class on the registers.
import machine
import time
from machine import Pin

GPIO25_STATUS = 0x400140C8
GPIO25_CTRL = 0x400140CC


class YellowLED:
    def __init__(self):
        self.pin = Pin(25, Pin.OUT)
        self.off()

    def on(self):
        self.pin.low()

    def off(self):
        self.pin.high()


class ButtonA:
    def is_pressed(self):
        ctrl = machine.mem32[GPIO25_CTRL]
        machine.mem32[GPIO25_CTRL] = ctrl & ~(0x1 << 12) | 0x1 << 13  # OEOVER: disable the output
        time.sleep_us(1)
        level = 0x1 & machine.mem32[GPIO25_STATUS] >> 17
        machine.mem32[GPIO25_CTRL] = ctrl
        return not level


T0 = time.ticks_ms()
led = YellowLED()
button = ButtonA()
seen = []
for step in range(8):  # every 50 ms: the LED on for the even steps, the button read each time
    if step % 2 == 0:
        led.on()
    else:
        led.off()
    time.sleep_ms(10)
    print("R step", step, time.ticks_diff(time.ticks_ms(), T0), int(button.is_pressed()), led.pin.value())
    time.sleep_ms(40)
print("done")

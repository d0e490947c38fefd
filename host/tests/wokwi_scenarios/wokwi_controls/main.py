# A Wokwi project's knobs read back: the knob and the light sensor on ADCs, the light
# sensor's dark output and the slide switch on pins, an HC-SR04 on request; the LED
# follows the switch. Each change is printed once, as "name value".
import time

from machine import ADC, Pin, time_pulse_us

pot = ADC(Pin(34))
ldr = ADC(Pin(35))
dark = Pin(25, Pin.IN)
switch = Pin(26, Pin.IN)
led = Pin(13, Pin.OUT, value=0)
trig = Pin(5, Pin.OUT, value=0)
echo = Pin(19, Pin.IN)


def distance_cm():
    trig.value(1)
    time.sleep_us(10)
    trig.value(0)
    return round(time_pulse_us(echo, 1, 30_000) / 58.31)


last = {}
print("ready")
while True:
    now = {"pot": pot.read_u16(), "ldr": ldr.read_u16(), "dark": dark.value(), "switch": switch.value()}
    now["cm"] = distance_cm()
    for name, value in now.items():
        if last.get(name) != value:
            print(name, value)
    last = now
    led.value(now["switch"])
    time.sleep_ms(50)

# Drivers that make their Pin and ADC objects anew on every read (common in sonar and
# button code), and an IRQ set on a Pin object the program then drops.
import time
from machine import ADC, Pin

last = [0, 0]


def first(pin):
    last[0] += 1


def second(pin):
    last[1] += 1


Pin(35, Pin.IN).irq(first)
Pin(35, Pin.IN).irq(second)  # the pin's IRQ is replaced, as on a board
time.sleep_ms(100)
edges = [0]


def count(pin):
    edges[0] += 1


Pin(34, Pin.IN).irq(count, Pin.IRQ_RISING | Pin.IRQ_FALLING)
highs = 0
reads = 0
for _ in range(3000):  # 3 s: pin 34 toggles 300 times meanwhile
    highs += Pin(34, Pin.IN).value()  # a new object every time
    reads += 1
    time.sleep_ms(1)
adc = [ADC(Pin(32)).read_u16() for _ in range(3)]
print("R edges", edges[0])
print("R highs_between", 1000 < highs < 2000)
print("R reads", reads)
print("R adc", adc)
print("R last_irq_wins", last)

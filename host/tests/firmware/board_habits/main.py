# Habits of public driver code that a board forgives: objects made again (one peripheral
# per pin or id), a PWM made per call, irq() asked for its flags, UART settings changed
# with init(), a read that waits its timeout, a poll that is ready at once in a loop.
import select
import time
from machine import PWM, UART, Counter, Pin, Timer

led = Pin(4, Pin.OUT, value=0)
Pin(4, Pin.OUT).on()
led.off()  # the same pin: off
print("R same_pin", [Pin(4) is led, Pin(5, Pin.IN).value()])

for _ in range(300):  # a servo driver that makes its PWM on every call
    pwm = PWM(Pin(12), freq=50)
    pwm.duty_ns(1_500_000)
print("R pwm_same", PWM(Pin(12)) is pwm)
pwm.deinit()

edges = []
Pin(5, Pin.IN).irq(lambda p: edges.append(p.irq().flags()), Pin.IRQ_RISING | Pin.IRQ_FALLING)
for _ in range(2):
    led.on()
    time.sleep_ms(1)
    led.off()
    time.sleep_ms(1)
print("R flags", edges)

u = UART(1)
u.init(115200, timeout=50)
t0 = time.ticks_us()
u.write(b"0123456789\n")
line = u.readline()  # waits for the line (its own, looped back)
print("R uart", [UART(1) is u, line, time.ticks_diff(time.ticks_us(), t0)])

c = Counter(0, Pin(13, Pin.IN))
Pin(12, Pin.OUT).on()
Pin(12).off()
Pin(12).on()
print("R counter_again", [Counter(0) is c, Counter(0).value()])
tm = Timer(0)
print("R timer_same", Timer(0) is tm)

p = select.poll()
p.register(u, select.POLLIN)
u.write(b"xy")  # two bytes: the second comes 87 us after the first
t0 = time.ticks_us()
n = 0
while not (p.poll(1000) and u.any() >= 2):  # half a packet in: the poll returns at once
    n += 1
print("R poll_spin", [n > 0, time.ticks_diff(time.ticks_us(), t0) > 0])

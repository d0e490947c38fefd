# A small robot's firmware on the smallest heap a rig file takes: machine, time and
# asyncio imported, pins, an ADC, a PWM and a Timer made, two tasks that sample, steer
# and print for a while, as a control loop does.
import asyncio
import gc
import time
from machine import ADC, PWM, Pin, Timer

button = Pin(23, Pin.IN, Pin.PULL_UP)
sonar = ADC(Pin(32))
motor = PWM(Pin(25), freq=20_000, duty_u16=0)
direction = Pin(26, Pin.OUT)
edges = [0]
ticks = [0]


def pressed(_pin):
    edges[0] += 1


def tick(_timer):
    ticks[0] += 1


button.irq(pressed, Pin.IRQ_FALLING)
Timer(0, mode=Timer.PERIODIC, period=10, callback=tick)
readings = []


async def sample():
    for _ in range(20):
        readings.append(sonar.read_u16())
        await asyncio.sleep_ms(10)


async def steer():
    for k in range(20):
        motor.duty_u16(1000 * k)
        direction.value(k % 2)
        print("step", k, time.ticks_ms() % 1000)
        await asyncio.sleep_ms(10)


async def main():
    await asyncio.gather(sample(), steer())


asyncio.run(main())
gc.collect()
print("R readings", len(readings))
print("R ticks", ticks[0])
print("R edges", edges[0])
print("R free", gc.mem_free())

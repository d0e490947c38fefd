# An NEC remote's keys decoded two ways, in the styles of the Pico-Go's published demos
# and of the IRQ-driven NEC decoders (written here, not copied): first by polling the
# receiver's pin, counting 100 us sleeps through each burst and space (a space of more
# than 7 counts is a 1); then from the instants of its falling edges, taken with
# ticks_us() in a pin IRQ (13.5 ms from the start burst to the first bit, then 1.125 ms
# for a 0 and 2.25 ms for a 1).
import time
from machine import Pin

ir = Pin(5, Pin.IN)


def poll_key():
    if ir.value() == 1:
        return None
    count = 0
    while ir.value() == 0 and count < 100:  # the 9 ms burst
        count += 1
        time.sleep_us(100)
    if count < 10:
        return None
    count = 0
    while ir.value() == 1 and count < 50:  # the 4.5 ms space
        count += 1
        time.sleep_us(100)
    data = [0, 0, 0, 0]
    longest = 0
    for i in range(32):
        count = 0
        while ir.value() == 0 and count < 10:
            count += 1
            time.sleep_us(100)
        count = 0
        while ir.value() == 1 and count < 20:
            count += 1
            time.sleep_us(100)
        if count > 7:
            data[i // 8] |= 1 << (i % 8)
        longest = max(longest, count)
    if data[0] + data[1] == 0xFF and data[2] + data[3] == 0xFF:
        return data[2]
    return "repeat"


got = 0
t_end = time.ticks_add(time.ticks_ms(), 1200)
while got < 3 and time.ticks_diff(t_end, time.ticks_ms()) > 0:
    key = poll_key()
    if key is not None and key != "repeat":
        print("poll", hex(key), time.ticks_us())
        got += 1

falls = []


def on_fall(pin):
    falls.append(time.ticks_us())


ir.irq(on_fall, Pin.IRQ_FALLING)


def decode(ts):
    gaps = [time.ticks_diff(b, a) for a, b in zip(ts, ts[1:])]
    if len(gaps) != 33 or not 12_000 < gaps[0] < 15_000:
        return None
    word = 0
    for i, gap in enumerate(gaps[1:]):
        if gap > 1_700:
            word |= 1 << i
    addr, inv_addr, cmd, inv_cmd = word & 0xFF, word >> 8 & 0xFF, word >> 16 & 0xFF, word >> 24
    if addr ^ inv_addr == 0xFF and cmd ^ inv_cmd == 0xFF:
        return cmd
    return None


got = 0
while got < 2:
    time.sleep_ms(10)
    if falls and time.ticks_diff(time.ticks_us(), falls[-1]) > 20_000:
        ts, falls = falls, []
        key = decode(ts)
        print("irq", hex(key) if key is not None else key, len(ts), time.ticks_us())
        got += 1
print("done")

# Timer(hard=): a one-shot Timer due 10 ms into a 30 ms time_pulse_us (a busy loop in C on a
# board), made with hard=True, then with hard=False. Where the port takes hard=True
# (ports/rp2/machine_timer.c from 1.26) the callback runs at its due time inside the call;
# a soft one runs once the call has returned. Where the port has no hard= (rp2 1.25, esp32
# up to 1.26) either is a TypeError; the ESP32's from 1.27 takes hard= and refuses True.
import sys
import time
from machine import Pin, Timer, time_pulse_us

echo = Pin(5, Pin.IN)  # (its wire is held low: no pulse comes)
timer_id = 0 if sys.platform == "esp32" else -1  # (an ESP32's timers are hardware ones, an rp2's virtual)
inside = False
ran = [None, None]  # (a hard callback runs with the heap locked on a board: it stores, never allocates)
t0 = time.ticks_us()


def on_timer(_t):
    ran[0] = time.ticks_diff(time.ticks_us(), t0)
    ran[1] = inside


print("R version", sys.implementation.version[:2])
for hard in (True, False):
    name = "hard" if hard else "soft"
    try:
        Timer(timer_id, mode=Timer.ONE_SHOT, period=10, callback=on_timer, hard=hard)
    except Exception as e:  # noqa: BLE001  (the port's refusal is the result)
        print("R %s_made" % name, [type(e).__name__, str(e)])
        continue
    print('R %s_made "ok"' % name)
    t0 = time.ticks_us()
    inside = True
    time_pulse_us(echo, 1, 30_000)
    inside = False
    time.sleep_ms(1)
    print("R %s_ran" % name, tuple(ran))
    ran[0] = ran[1] = None

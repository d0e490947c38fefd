from machine import Timer
from time import sleep_ms, ticks_diff, ticks_ms

t0 = ticks_ms()
periodic, oneshot, fast = [], [], []
Timer(0, mode=Timer.PERIODIC, period=50, callback=lambda t: periodic.append(ticks_diff(ticks_ms(), t0)))
Timer(1, mode=Timer.ONE_SHOT, period=120, callback=lambda t: oneshot.append(ticks_diff(ticks_ms(), t0)))
tf = Timer(2, freq=100, callback=lambda t: fast.append(ticks_diff(ticks_ms(), t0)))
sleep_ms(205)
tf.deinit()
sleep_ms(100)
print("R periodic", periodic)
print("R oneshot", oneshot)
print("R fast", fast)

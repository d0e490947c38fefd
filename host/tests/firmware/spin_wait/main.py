# Waits that call nothing of the board's, as vendors' libraries write them: a buzzer's note
# held by a one-shot Timer (`while self.is_playing: pass`, as Pololu's 3pi+ Buzzer.play), a
# bumper's IRQ flag, and the same under micropython.heap_lock(). Each loop reads no clock
# and no pin: only the Timer or the IRQ can end it.
import micropython
import time
from machine import Pin, Timer


class Buzzer:
    def __init__(self):
        self.is_playing = False
        self.timer = Timer(-1)

    def _done(self, _timer):
        self.is_playing = False

    def play(self, ms):
        self.is_playing = True
        self.timer.init(mode=Timer.ONE_SHOT, period=ms, callback=self._done)
        while self.is_playing:
            pass


buzzer = Buzzer()
t0 = time.ticks_us()
buzzer.play(100)
print("R played_us", time.ticks_diff(time.ticks_us(), t0))

pressed = []
bumper = Pin(23, Pin.IN)
bumper.irq(lambda pin: pressed.append(time.ticks_us()), Pin.IRQ_RISING)
while not pressed:
    pass
print("R pressed_at_us", [time.ticks_diff(pressed[0], t0), time.ticks_diff(time.ticks_us(), t0)])

buzzer.is_playing = True  # (Timer.init allocates: before the lock, as a board needs too)
t0 = time.ticks_us()
buzzer.timer.init(mode=Timer.ONE_SHOT, period=30, callback=buzzer._done)
micropython.heap_lock()
while buzzer.is_playing:
    pass
t1 = time.ticks_us()
micropython.heap_unlock()
print("R locked_us", time.ticks_diff(t1, t0))
